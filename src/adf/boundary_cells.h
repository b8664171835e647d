// SPDX-License-Identifier: Apache-2.0
/// @file boundary_cells.h
/// @brief The leaf cells of a tile whose corners change sign: where the surface is.
///
/// Both the mesher and the point sampler start here. A lone leaf without a sign change is
/// skipped on the type in its node word (no corner decoded), a brick on its 27 raw 16-bit
/// values (quantisation keeps signs), decoded once for its 8 children, which are then told
/// apart by masks of those values' signs; so the cost follows the cells near the surface.
/// Complexity: O(nodes of the tile). Threading: any thread. Memory: the output only.
#pragma once

#include "adf/adf.h"

#include <cstdint>
#include <vector>

namespace kizamu::adf {

struct BoundaryCell {
    glm::uvec3 origin{0};  ///< lattice
    uint32_t size = 0;     ///< lattice units
    float corners[8] = {};  ///< m, corner order of tile.h
    bool brickChild = false;  ///< its 7 siblings are leaves of the same size (no lookup needed)
};

struct LatticeBox;

/// A test of a sign-changing leaf's box (lattice origin and size), made before a lone leaf's
/// corners are decoded (a brick child's after its brick's 27 values, which tell its sign
/// change): a leaf it refuses costs no decoding of its own and no record.
struct LeafFilter {
    bool (*keep)(const void* context, glm::uvec3 origin, uint32_t size) = nullptr;
    const void* context = nullptr;
};

/// Appends the sign-changing leaves of `tile` (depth-first order) to `out`.
void appendBoundaryCells(const adf::Tile& tile, int maxLevel, std::vector<BoundaryCell>& out);

/// The same, restricted to leaves whose closed box shares a point with one of `boxes` (closed)
/// and, with a filter, that it keeps: subtrees clear of every box are not visited.
/// Complexity: O(nodes near the boxes × boxes).
void appendBoundaryCellsTouching(const adf::Tile& tile, int maxLevel, const std::vector<LatticeBox>& boxes,
                                 std::vector<BoundaryCell>& out, LeafFilter filter = {});

}  // namespace kizamu::adf
