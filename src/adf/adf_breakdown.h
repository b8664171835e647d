// SPDX-License-Identifier: Apache-2.0
/// @file adf_breakdown.h
/// @brief Where an ADF's cells and bytes are: per level, per storage kind, per distance band.
///
/// A cold-path analysis for memory work (`kizamu info --breakdown`): it walks every distinct tile
/// once and classifies leaf cells by level, by how they are stored (lone leaf or brick child), by
/// cell type and by their distance to the surface in finest cells; it also counts *creased*
/// finest bricks, whose half grid has a second difference along an axis too large for a smooth
/// field at that distance (a kink of the field: groove rims, medial sheets). Any thread.
#pragma once

#include "adf/adf.h"

#include <array>
#include <cstddef>
#include <string>

namespace kizamu::adf {

struct AdfBreakdown {
    /// Distance classes of a leaf (min |corner| in finest cells): [0,1) [1,2) [2,4) [4,8) [8,16) >= 16.
    static constexpr int kDistanceBins = 6;
    static constexpr std::array<const char*, kDistanceBins> kBinNames{"<1", "1-2", "2-4", "4-8", "8-16", ">=16"};
    struct Level {
        std::size_t loneLeaves = 0;     ///< leaves with their own 8 corners
        std::size_t narrowLoneLeaves = 0;  ///< of them stored packed: narrow or in a packed group (tile.h)
        std::size_t groupedLeaves = 0;     ///< of them stored in leaf groups
        std::size_t brickCells = 0;     ///< leaves stored as brick children (8 per brick)
        std::size_t narrowBricks = 0;   ///< bricks whose children are at this level, stored narrow
        std::size_t coarseBricks = 0;   ///< of them, coarse-narrow
        std::size_t farBricks = 0;      ///< of them, far (the rest, brickCells / 8 less the three, wide)
        std::size_t internalNodes = 0;  ///< node words that point at children
        std::array<std::size_t, 3> cellsByType{};           ///< Exterior, Interior, Boundary
        std::array<std::size_t, kDistanceBins> cellsByDistance{};
        std::array<std::size_t, kDistanceBins> creasedBrickCells{};  ///< cells of creased bricks
    };
    std::array<Level, kMaxSupportedLevel + 1> levels{};
    std::size_t tiles = 0, coarseTiles = 0;
    std::size_t headerBytes = 0;      ///< Tile headers
    std::size_t nodeBytes = 0;        ///< node words (with alignment)
    std::size_t cornerBytes = 0;      ///< lone leaves' corner values (narrow and wide)
    std::size_t narrowLeafBytes = 0;  ///< of them, narrow own leaves' (9 each: corner 0, 7 steps)
    std::size_t groupBytes = 0;       ///< of them, leaf groups' (25 narrow, 28 coarse-narrow or far, 54 wide)
    std::size_t narrowLeaves = 0, wideLeaves = 0;  ///< own lone leaves (not in groups)
    std::size_t groups = 0, packedGroups = 0, narrowGroups = 0, farGroups = 0;  ///< leaf groups, packed ones, of them narrow, far
    std::size_t groupedLeaves = 0;    ///< the leaves in groups
    std::size_t brickBytes = 0;       ///< brick values (and packed bricks' centres, header padding aside)
    std::size_t narrowBricks = 0, coarseBricks = 0, farBricks = 0, wideBricks = 0;  ///< 25, 28, 28 and 54 bytes each
    std::size_t tableBytes = 0;       ///< root array and chunks
    std::size_t totalBytes() const { return headerBytes + nodeBytes + cornerBytes + brickBytes + tableBytes; }
};

/// Complexity: O(nodes + cells). Threading: any thread. Memory: none beyond the result.
AdfBreakdown computeBreakdown(const Adf& adf);

/// Multi-line table of `b` for a terminal.
std::string formatBreakdown(const AdfBreakdown& b, int maxLevel);

}  // namespace kizamu::adf
