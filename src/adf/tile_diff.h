// SPDX-License-Identifier: Apache-2.0
/// @file tile_diff.h
/// @brief The cells where two versions of a stored tile differ, for sub-tile re-meshing.
///
/// An edit rebuilds whole tiles but copies most cells from the old tile (adf/generate.h), so a
/// rebuilt tile is usually identical outside the edit's region. The mesher reads a tile only
/// through its leaf structure and the decoded (float) corner values, so that is what is
/// compared: two leaves are equal when they are the same cell and their 8 decoded corners are
/// bit-identical. Nothing about how the tile was made is assumed (a new quantisation scale
/// simply shows up as changed cells). Bricks compare as their 8 leaf children. When both tiles
/// have the same quantisation scale (regeneration keeps it whenever the values fit) the raw
/// 16-bit values are compared, a brick's 27 at once: the same answer, since decoding with one
/// positive scale is injective.
/// Complexity: O(nodes of the two tiles). Threading: any thread. Memory: the output only.
#pragma once

#include "adf/tile.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <vector>

namespace kizamu::adf {

/// An axis-aligned cube of lattice points: [lo, lo + size] per axis (closed).
struct LatticeBox {
    glm::uvec3 lo{0};
    uint32_t size = 0;
};

/// Appends to `out` the boxes of the largest cells of `before`/`after` (same level and origin,
/// asserted) below which the two tiles differ: a leaf whose decoded corners changed, or a cell
/// that is a leaf in one and subdivided in the other. No box where the tiles read the same.
/// With `beforeWords`, also appends for each box the node word `before` holds at that cell (a
/// leaf's word for a brick's child), so that its cells there can be listed without a search.
void appendChangedCells(const adf::Tile& before, const adf::Tile& after, int maxLevel, std::vector<LatticeBox>& out,
                        std::vector<uint32_t>* beforeWords = nullptr);

/// Whether lattice point `p` lies in the closed box.
inline bool contains(const LatticeBox& b, glm::uvec3 p) {
    return p.x - b.lo.x <= b.size && p.y - b.lo.y <= b.size && p.z - b.lo.z <= b.size;  // wraps below lo
}
/// Whether two closed boxes share at least a point.
inline bool touches(const LatticeBox& a, glm::uvec3 lo, uint32_t size) {
    return a.lo.x <= lo.x + size && lo.x <= a.lo.x + a.size && a.lo.y <= lo.y + size && lo.y <= a.lo.y + a.size &&
           a.lo.z <= lo.z + size && lo.z <= a.lo.z + a.size;
}

}  // namespace kizamu::adf
