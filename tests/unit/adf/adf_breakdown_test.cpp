// SPDX-License-Identifier: Apache-2.0
// The memory breakdown (`kizamu info --breakdown`) accounts for every cell and byte the
// snapshot's own statistics count, brick forms included.
#include "adf/adf_breakdown.h"

#include "adf/generate.h"
#include "adf/test_part.h"

#include <gtest/gtest.h>

#include <numeric>

using namespace kizamu::adf;

TEST(AdfBreakdown, AccountsForEveryCellAndByte) {
    const Domain d = testPartDomain(8);
    const AdfPtr a = generate(*makeTestPart(d), d, testPartSettings());
    const Adf::Stats stats = a->computeStats();
    const AdfBreakdown b = computeBreakdown(*a);
    std::size_t grouped = 0, cells = 0, byType = 0, byDistance = 0, bricks = 0, leaves = 0, narrowLeaves = 0, narrowBricks = 0,
                coarseBricks = 0, farBricks = 0;
    for (const AdfBreakdown::Level& l : b.levels) {
        cells += l.loneLeaves + l.brickCells;
        byType += std::accumulate(l.cellsByType.begin(), l.cellsByType.end(), std::size_t(0));
        byDistance += std::accumulate(l.cellsByDistance.begin(), l.cellsByDistance.end(), std::size_t(0));
        bricks += l.brickCells / 8;
        leaves += l.loneLeaves;
        narrowLeaves += l.narrowLoneLeaves;
        grouped += l.groupedLeaves;
        narrowBricks += l.narrowBricks;
        coarseBricks += l.coarseBricks;
        farBricks += l.farBricks;
        EXPECT_LE(l.narrowBricks + l.coarseBricks + l.farBricks, l.brickCells / 8);
    }
    EXPECT_EQ(cells, stats.cells);
    EXPECT_EQ(byType, stats.cells);
    EXPECT_EQ(byDistance, stats.cells);
    EXPECT_EQ(bricks, stats.bricks);
    EXPECT_EQ(b.narrowBricks + b.coarseBricks + b.farBricks + b.wideBricks, stats.bricks);
    EXPECT_EQ(b.narrowBricks, stats.narrowBricks);
    EXPECT_EQ(b.coarseBricks, stats.coarseBricks);
    EXPECT_EQ(b.farBricks, stats.farBricks);
    EXPECT_EQ(narrowBricks, b.narrowBricks);
    EXPECT_EQ(coarseBricks, b.coarseBricks);
    EXPECT_EQ(farBricks, b.farBricks);
    EXPECT_GT(b.narrowBricks, 0u) << "a typical field has bricks of finest cells";
    EXPECT_GT(b.coarseBricks, 0u) << "and of 2-cell children";
    EXPECT_GT(b.farBricks, 0u) << "and of larger ones away from the surface";
    EXPECT_EQ(b.brickBytes, 25 * b.narrowBricks + 28 * (b.coarseBricks + b.farBricks) + 54 * b.wideBricks);
    EXPECT_EQ(b.narrowLeaves + b.wideLeaves + b.groupedLeaves, leaves);
    EXPECT_EQ(grouped, b.groupedLeaves) << "leaves the walk finds in groups, against the tiles' counts";
    EXPECT_EQ(b.narrowLeaves, stats.narrowLeaves);
    EXPECT_EQ(narrowLeaves, stats.narrowLeaves + stats.packedGroupedLeaves) << "packed: narrow own leaves and packed groups";
    EXPECT_GT(b.narrowLeaves, 0u) << "a typical field has narrow lone leaves";
    EXPECT_GT(b.groups, 0u) << "and cells with several lone-leaf children";
    EXPECT_EQ(b.cornerBytes, 9 * b.narrowLeaves + 16 * b.wideLeaves + b.groupBytes);
    EXPECT_EQ(b.groupBytes, 25 * b.narrowGroups + 28 * (b.packedGroups - b.narrowGroups) + 54 * (b.groups - b.packedGroups));
    EXPECT_EQ(b.narrowLeafBytes, 9 * b.narrowLeaves);
    EXPECT_EQ(b.tiles, stats.tiles);
    EXPECT_EQ(b.tableBytes, stats.tableBytes);
    EXPECT_EQ(b.totalBytes(), stats.tileBytes + stats.tableBytes);
    const std::string text = formatBreakdown(b, d.maxLevel);
    EXPECT_NE(text.find("narrow"), std::string::npos) << text;
    EXPECT_NE(text.find("coarse-narrow"), std::string::npos) << text;
}
