// SPDX-License-Identifier: Apache-2.0
/// @file paint.h
/// @brief The paint tool: colours the clay near its surface inside a swept tool, leaving the
/// distance field untouched.
///
/// Every finest lattice point in the box around the swept tool whose field value lies within
/// kPaintBandCells of the surface, and inside the tool, takes
/// lerp(old colour, paint colour, weight × strength): the weight is the gradual tools' smooth
/// weight (toolWeight: 0 at the tool's boundary, 1 at half the tool's radius inside it, so a
/// brush has a solid centre and a soft rim), and the strength is the opacity (for paint it does
/// not shrink the tool). The band covers every lattice point a mesh vertex blends (a vertex sits
/// on the surface, its cell's corners within √3 cells of it). Mirrored strokes paint each copy
/// in turn. Only the colour layer changes: the result shares every distance tile, and every
/// colour tile it does not touch, with the snapshot it was painted on (adf/colour_layer.h).
///
/// Live strokes (Sculptor::extendStroke) paint segment by segment: a point's colour after the
/// whole stroke is its start colour blended in turn by each mirrored copy's weight, and the
/// weight of a path is the maximum of its pieces' weights (toolWeight falls with the distance,
/// and the swept distance is the minimum over the pieces). So a segment rewrites only the points
/// where some copy's running maximum weight grows, and writes there that blend from the start
/// colour with the weights so far: nothing is blended twice, and every point ends as the whole
/// stroke paints it.
///
/// Deterministic: each point's new colour depends only on its old colour, the field and the
/// tool, so the result is the same for any thread count. Complexity: O(leaves in the swept
/// box), trilinear evaluations only at lattice points of leaves that reach the band, swept-tool
/// queries only for points in the band (most of the time: a turned cube's golden-section search).
/// Threading: tile slots in parallel on `pool`. Memory: the new colour tiles and slot list.
#pragma once

#include "adf/adf.h"
#include "adf/colour_layer.h"
#include "sculpt/stroke.h"

#include <cstddef>
#include <span>

namespace kizamu::util {
class ThreadPool;
}

namespace kizamu::sculpt {

/// Half-width of the shell around the surface that paint colours, finest cells.
inline constexpr double kPaintBandCells = 3.0;

/// Counters of one paint stroke.
struct PaintStats {
    std::size_t slotsPainted = 0;   ///< colour tiles written (one per slot whose colours changed)
    std::size_t pointsChanged = 0;  ///< lattice points whose colour changed
    std::size_t replacedBytes = 0;  ///< bytes of the colour tiles and slot list it replaced
};

/// The colour layer of `adf` after `stroke` (its tool's op must be Paint). Returns adf's own
/// layer (possibly null) when nothing changed.
/// @throw std::invalid_argument for an invalid stroke (validateStroke) or another op.
adf::ColourLayerPtr paintStroke(const adf::Adf& adf, const Stroke& stroke, util::ThreadPool* pool = nullptr,
                                PaintStats* stats = nullptr);

/// The colour layer of `adf` (the snapshot the previous segment left) after one segment of a
/// live paint stroke: the points where some mirrored copy's running maximum weight grows take
/// the start colour blended, copy by copy as paintStroke does, by the weights of the path so far.
/// @param header   the stroke's tool (op Paint), constraints (masks) and mirror; its poses are ignored
/// @param start    the colour layer at the stroke's start (null: unpainted)
/// @param before   the resolved poses already applied (empty for the first segment)
/// @param segment  the resolved poses from the joint (before's last pose) to the newest
/// Returns adf's own layer (possibly null) when nothing changed; `stats` counts this segment.
/// @throw std::invalid_argument for another op or an invalid tool or segment.
/// Complexity: paintStroke's over the segment's box, plus a query of the path so far at each
/// point the segment reaches. Threading: tile slots in parallel on `pool`. Memory: the new
/// colour tiles and slot list, and the swept tool of `before` (O(poses)).
adf::ColourLayerPtr paintLiveSegment(const adf::Adf& adf, const Stroke& header, const adf::ColourLayer* start,
                                     std::span<const ToolSample> before, std::span<const ToolSample> segment,
                                     util::ThreadPool* pool = nullptr, PaintStats* stats = nullptr);

/// What replacing the colour layer `before` by `after` (either may be null) costs, counted as
/// paintStroke counts a stroke: slotsPainted = the slots whose tile `after` does not share,
/// replacedBytes = those tiles of `before` plus its slot list once (0 when none); pointsChanged
/// is not counted (0). A live paint stroke's undo record. Complexity: O(slots of both).
PaintStats paintedBetween(const adf::ColourLayer* before, const adf::ColourLayer* after);

}  // namespace kizamu::sculpt
