// SPDX-License-Identifier: Apache-2.0
/// @file adf_breakdown.cpp
/// @brief computeBreakdown: one walk over every distinct tile.
#include "adf/adf_breakdown.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace kizamu::adf {

namespace {

int distanceBin(double cells) {
    if (cells < 1.0) return 0;
    if (cells < 2.0) return 1;
    if (cells < 4.0) return 2;
    if (cells < 8.0) return 3;
    if (cells < 16.0) return 4;
    return 5;
}

/// Largest |second difference| of the half grid along the three axes, in units of its spacing.
/// A smooth distance field curving with radius R gives about spacing / R; a kink of angle θ
/// gives up to about 2 sin(θ/2).
double secondDifference(const float* v, float spacing) {
    double m = 0.0;
    for (int a = 0; a < 3; ++a) {
        const int step = a == 0 ? 1 : (a == 1 ? 3 : 9);
        for (int g = 0; g < 27; ++g) {
            const int i = a == 0 ? g % 3 : (a == 1 ? (g / 3) % 3 : g / 9);
            if (i != 0) continue;
            m = std::max(m, std::abs(double(v[g]) - 2.0 * double(v[g + step]) + double(v[g + 2 * step])));
        }
    }
    return m / double(spacing);
}

}  // namespace

AdfBreakdown computeBreakdown(const Adf& adf) {
    AdfBreakdown b;
    const Domain& d = adf.domain();
    const double h = d.finestCellSize();
    const Adf::Stats st = adf.computeStats();
    b.tableBytes = st.tableBytes;
    adf.forEachTile([&](const Tile& t) {
        ++b.tiles;
        if (t.level() < d.tileLevel()) ++b.coarseTiles;
        const std::size_t total = t.bytes();
        const std::size_t nodeBytes = (t.nodeBytes() + 7) / 8 * 8;  // 8-aligned, as tile.cpp lays them out
        b.nodeBytes += nodeBytes;
        const Tile::Counts n = t.counts();
        const std::size_t ownNarrowBytes = std::size_t(n.narrowLeaves) * Tile::kNarrowLeafBytes;
        const std::size_t packedGroups = std::size_t(n.narrowGroups) + n.coarseGroups + n.farGroups;
        const std::size_t groupBytes = Tile::gridBytes(n.narrowGroups, packedGroups, packedGroups + n.wideGroups);
        const std::size_t leafBytes = ownNarrowBytes + std::size_t(n.wideLeaves) * Tile::kWideLeafBytes + groupBytes;
        b.cornerBytes += leafBytes;
        b.narrowLeafBytes += ownNarrowBytes;
        b.groupBytes += groupBytes;
        b.narrowLeaves += n.narrowLeaves;
        b.wideLeaves += n.wideLeaves;
        b.groups += packedGroups + n.wideGroups;
        b.packedGroups += packedGroups;
        b.farGroups += n.farGroups;
        b.narrowGroups += n.narrowGroups;
        b.groupedLeaves += n.groupedLeaves;
        const std::size_t brickBytes = Tile::gridBytes(n.narrowBricks, t.packedBrickCount(), t.brickCount());
        b.brickBytes += brickBytes;
        b.narrowBricks += n.narrowBricks;
        b.coarseBricks += n.coarseBricks;
        b.farBricks += n.farBricks;
        b.wideBricks += n.wideBricks;
        b.headerBytes += total - nodeBytes - leafBytes - brickBytes;
        struct Item {
            uint32_t node;
            int level;
        };
        Item stack[8 * (kMaxSupportedLevel + 1)];
        int top = 0;
        stack[top++] = {0, t.level()};
        while (top > 0) {
            const Item it = stack[--top];
            const uint32_t w = t.node(it.node);
            AdfBreakdown::Level& L = b.levels[std::size_t(it.level)];
            if (node::isInternal(w)) {
                ++L.internalNodes;
                for (int c = 0; c < 8; ++c) stack[top++] = {w + uint32_t(c), it.level + 1};
                continue;
            }
            if (node::isLeaf(w)) {
                ++L.loneLeaves;
                if (t.packedLeaf(node::leafIndex(w))) ++L.narrowLoneLeaves;
                if (node::leafIndex(w) < 8 * t.groupCount()) ++L.groupedLeaves;
                float m = INFINITY;
                for (int c = 0; c < 8; ++c) m = std::min(m, std::abs(t.corner(node::leafIndex(w), c)));
                ++L.cellsByType[int(node::leafType(w))];
                ++L.cellsByDistance[std::size_t(distanceBin(double(m) / h))];
                continue;
            }
            AdfBreakdown::Level& C = b.levels[std::size_t(it.level + 1)];
            const uint32_t brick = node::brickIndex(w);
            if (brick < t.narrowBrickCount()) ++C.narrowBricks;
            else if (brick < t.narrowBrickCount() + t.coarseBrickCount()) ++C.coarseBricks;
            else if (brick < t.packedBrickCount()) ++C.farBricks;
            float v[27];
            for (int g = 0; g < 27; ++g) v[g] = float(t.brickValue(node::brickIndex(w), g)) * t.scale();
            const float spacing = float(double(d.cellLattice(it.level + 1)) * h);
            const bool creased = secondDifference(v, spacing) > 0.25;
            for (int child = 0; child < 8; ++child) {
                float corners[8];
                float m = INFINITY;
                for (int c = 0; c < 8; ++c) m = std::min(m, std::abs(corners[c] = v[brickPoint(child, c)]));
                ++C.brickCells;
                ++C.cellsByType[int(cellTypeOf(std::span<const float, 8>(corners, 8)))];
                const auto bin = std::size_t(distanceBin(double(m) / h));
                ++C.cellsByDistance[bin];
                if (creased) ++C.creasedBrickCells[bin];
            }
        }
    });
    return b;
}

std::string formatBreakdown(const AdfBreakdown& b, int maxLevel) {
    std::string out;
    char line[512];
    auto mb = [](std::size_t n) { return double(n) / 1e6; };
    std::snprintf(line, sizeof line,
                  "  bytes       %.2f MB: headers %.2f (%zu tiles, %zu coarse), node words %.2f, lone-leaf corners %.2f "
                  "(%zu narrow %.2f, %zu wide %.2f, %zu groups of %zu leaves %.2f, %zu of them packed, %zu narrow, %zu far), brick values %.2f (%zu narrow %.2f, %zu coarse-narrow %.2f, "
                  "%zu far %.2f, %zu wide %.2f), table %.2f\n",
                  mb(b.totalBytes()), mb(b.headerBytes), b.tiles, b.coarseTiles, mb(b.nodeBytes), mb(b.cornerBytes),
                  b.narrowLeaves, mb(b.narrowLeafBytes), b.wideLeaves, mb(b.cornerBytes - b.narrowLeafBytes - b.groupBytes),
                  b.groups, b.groupedLeaves, mb(b.groupBytes), b.packedGroups, b.narrowGroups, b.farGroups,
                  mb(b.brickBytes), b.narrowBricks, mb(Tile::kNarrowGridBytes * b.narrowBricks), b.coarseBricks,
                  mb(Tile::kCoarseGridBytes * b.coarseBricks), b.farBricks, mb(Tile::kCoarseGridBytes * b.farBricks), b.wideBricks, mb(Tile::kWideGridBytes * b.wideBricks),
                  mb(b.tableBytes));
    out += line;
    out += "  level  lone-leaves (packed) [grouped]  brick-cells  bricks narrow/coarse/far/wide  internal   ext/int/boundary cells          "
           "cells by min|corner| (finest cells) <1 1-2 2-4 4-8 8-16 >=16   [of them in creased bricks]\n";
    for (int l = 0; l <= maxLevel; ++l) {
        const AdfBreakdown::Level& L = b.levels[std::size_t(l)];
        if (L.loneLeaves + L.brickCells + L.internalNodes == 0) continue;
        std::snprintf(line, sizeof line, "  %5d %12zu %9zu [%7zu] %12zu %9zu %7zu %7zu %7zu %9zu   %9zu %9zu %9zu  ", l, L.loneLeaves,
                      L.narrowLoneLeaves, L.groupedLeaves, L.brickCells, L.narrowBricks, L.coarseBricks,
                      L.farBricks, L.brickCells / 8 - L.narrowBricks - L.coarseBricks - L.farBricks, L.internalNodes, L.cellsByType[0],
                      L.cellsByType[1], L.cellsByType[2]);
        out += line;
        for (int i = 0; i < AdfBreakdown::kDistanceBins; ++i) {
            std::snprintf(line, sizeof line, " %zu[%zu]", L.cellsByDistance[std::size_t(i)], L.creasedBrickCells[std::size_t(i)]);
            out += line;
        }
        out += "\n";
    }
    return out;
}

}  // namespace kizamu::adf
