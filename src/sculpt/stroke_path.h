// SPDX-License-Identifier: Apache-2.0
/// @file stroke_path.h
/// @brief Where the tool actually goes: a stroke's poses after its curve and constraints.
///
/// In order: a Bezier stroke is flattened into poses within `tolerance` of its curve (Kizamu
/// 4.2); if it follows the surface or keeps out of regions, the path is resampled so no two
/// poses are further apart than a quarter of the tool's radius (a straight chord between
/// constrained poses must stay close to the constrained path); each pose is moved along the
/// clay's gradient onto the offset surface it follows (Kizamu 4.1 and 4.4, Newton steps on the
/// ADF); then pushed out of the keep-out regions (force_field.h); and finally thinned again to
/// the poses the shape needs (Douglas-Peucker within `tolerance`), since a sweep costs per segment.
/// Deterministic for a given snapshot. Complexity: O(poses) queries. Edit thread.
#pragma once

#include "adf/adf.h"
#include "sculpt/stroke.h"

#include <vector>

namespace kizamu::sculpt {

/// @param clay       the snapshot before the stroke (what `follow` follows)
/// @param tolerance  m, how far a flattened curve may stray from the Bezier curve
std::vector<ToolSample> resolvePath(const Stroke& stroke, const adf::Adf& clay, double tolerance);

/// `samples` with poses added (position linear, orientation slerped) so that consecutive
/// positions are at most `spacing` (m) apart.
std::vector<ToolSample> densify(const std::vector<ToolSample>& samples, double spacing);

/// Douglas-Peucker: the poses of `path` needed for every dropped position to lie within
/// `tolerance` (m) of a chord. Paths whose orientation turns are returned unchanged.
std::vector<ToolSample> simplify(const std::vector<ToolSample>& path, double tolerance);

/// Moves `p` along the gradient of `clay` until it lies on the offset surface d = `offset` (m)
/// within a thousandth of a finest cell, or 16 Newton steps pass.
glm::dvec3 projectOntoOffsetSurface(const adf::Adf& clay, glm::dvec3 p, double offset);

}  // namespace kizamu::sculpt
