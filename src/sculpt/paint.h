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

}  // namespace kizamu::sculpt
