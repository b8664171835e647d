// SPDX-License-Identifier: Apache-2.0
/// @file cell_view.h
/// @brief The cells debug view's boxes: the ADF's leaf cells whose corners change sign (the
/// cells the surface passes through), read from a snapshot for the renderer, which never reads
/// the octree (render/cell_box_lines.h).
///
/// Threading: reads an immutable snapshot; any thread (the window's, where it draws).
#pragma once

#include "adf/adf.h"
#include "render/cell_box_lines.h"

#include <cstddef>
#include <vector>

namespace kizamu::app {

/// Replaces `out` with the boundary leaf cells of `adf` as boxes (m, world), tile by tile, at
/// most `cap` of them: beyond that, every k-th (k = ceil(count / cap)), so they still spread
/// over the whole surface. Returns the count in all (Adf::Stats::boundaryCells).
/// Complexity: O(nodes + leaf cells). Memory: 20 bytes per boundary cell in `out` until the cap
/// thins it (its capacity is kept).
std::size_t collectBoundaryCellBoxes(const adf::Adf& adf, std::size_t cap,
                                     std::vector<render::CellBox>& out);

}  // namespace kizamu::app
