// SPDX-License-Identifier: Apache-2.0
/// @file bezier_path.h
/// @brief Cubic Bezier tool paths (Kizamu 4.2), flattened into a polyline of tool poses.
///
/// The swept tool (swept_tool.h) sweeps continuously between poses, so a curve only has to be
/// turned into a polyline that stays within a tolerance of it: de Casteljau subdivision at the
/// midpoint until both inner control points lie within the tolerance of the chord (the curve
/// lies in its control points' hull, so the chord is then within the tolerance of the curve).
/// Straight parts cost two poses; tight bends get as many as they need.
/// Complexity: O(output) for a fixed tolerance. Pure functions; any thread.
#pragma once

#include "sculpt/tool.h"

#include <array>
#include <vector>

namespace kizamu::sculpt {

using BezierControls = std::array<glm::dvec3, 4>;

/// Distance from `p` to the segment a-b (m); what flattening and path thinning measure.
double distanceToSegment(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b);

/// The curve's point at parameter t in [0, 1].
glm::dvec3 bezierPoint(const BezierControls& c, double t);

/// Parameters t (0 first, 1 last, increasing) whose polyline is within `tolerance` (m, > 0) of
/// the curve. At most 2^16 + 1 of them.
std::vector<double> flattenBezier(const BezierControls& c, double tolerance);

/// Tool poses along the curve whose control points are the positions of `controls` (four
/// samples). The orientation at t is slerped between the controls' orientations at t = 0, 1/3,
/// 2/3 and 1, which are then poses of their own (all equal: a fixed tool, exactly).
std::vector<ToolSample> bezierSamples(const std::vector<ToolSample>& controls, double tolerance);

}  // namespace kizamu::sculpt
