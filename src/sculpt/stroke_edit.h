// SPDX-License-Identifier: Apache-2.0
/// @file stroke_edit.h
/// @brief The field after one stroke: the old field combined with the swept tool (Kizamu 4.1,
/// 4.4; Galyean & Hughes 3.1), as a distance source for local regeneration.
///
/// Carve and add are min/max CSG with the swept tool; build, heat gun, smooth and flatten move
/// the old field by a weight that falls smoothly to 0 at the tool's boundary, so the surface
/// moves continuously as the tool arrives. Masks, and depth or height limits from a reference
/// surface, take away from what the tool does. Symmetry mirrors the query point, not the tool.
/// The source also says where it leaves the old field alone (unchangedRange), which lets
/// regeneration keep the old cells there.
/// Threading: immutable; any thread. Memory: allocates nothing per query.
#pragma once

#include "adf/distance_source.h"
#include "sculpt/swept_tool.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <memory>
#include <vector>

namespace kizamu::sculpt {

/// Where a stroke may act (Kizamu 4.4), in world coordinates (not mirrored): outside every mask,
/// and no deeper (carve) or higher (add, build) than a limit from the reference surface.
struct ToolLimits {
    std::vector<adf::SourcePtr> masks;
    adf::SourcePtr reference;  ///< set when a depth or height limit is
    double depth = -1.0;       ///< m, < 0: none
    double height = -1.0;      ///< m, < 0: none
    bool empty() const { return masks.empty() && !reference; }
};

/// The old field `old` edited by `tool` (mirrored across the planes through `centre` of the
/// axes set in `reflect`). `offset` (m): how far build and the heat gun move the surface at
/// the tool's core. `finestCell` (m) sets the slack of unchangedRange.
adf::SourcePtr makeStrokeEdit(adf::SourcePtr old, std::shared_ptr<const SweptTool> tool, uint8_t reflect,
                              glm::dvec3 centre, double offset, ToolLimits limits, double finestCell);

}  // namespace kizamu::sculpt
