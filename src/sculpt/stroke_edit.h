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

/// One segment of a live stroke of a gradual tool (build, heat gun, smooth, flatten; Sculptor's
/// live strokes). The whole stroke moves the start field by a weight W(p) (the swept tool's
/// toolWeight), and W of a path is the maximum of W of its pieces, so the stroke so far is the
/// start field moved by its running maximum weight. A segment changes only the points where
/// that maximum grows (W_now > W_before) and writes there the start field moved by W_now: the
/// previous result plus the growth, with everything (smooth's mean, flatten's distance to the
/// plane) read from the start snapshot and nothing re-read from the regenerated field, so no
/// interpolation error accumulates over segments. The heat gun melts rate x dwell x W: when the
/// dwell grew, the whole path so far melts further (start + rate x dwellNow x W_now).
struct LiveSegment {
    adf::SourcePtr start;                       ///< the field at the stroke's start (what it measures against)
    std::shared_ptr<const SweptTool> segment;   ///< swept from the last applied pose (the joint) to the newest
    std::shared_ptr<const SweptTool> before;    ///< swept along the path already applied; null for the first segment
    double offsetBefore = 0.0;                  ///< m: build's amount; the heat gun's rate x dwell applied so far
    double offsetNow = 0.0;                     ///< m: the same after this segment
    ToolSample first;                           ///< the stroke's first pose (flatten's plane)
};

/// The field `old` (the snapshot the previous segment left) plus what `segment` adds to a live
/// gradual stroke (LiveSegment), mirrored like makeStrokeEdit. @throw std::invalid_argument for
/// carve, add and paint (carve and add segment as plain makeStrokeEdit: min/max is associative).
adf::SourcePtr makeLiveSegmentEdit(adf::SourcePtr old, LiveSegment segment, uint8_t reflect, glm::dvec3 centre,
                                   ToolLimits limits, double finestCell);

}  // namespace kizamu::sculpt
