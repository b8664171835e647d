// SPDX-License-Identifier: Apache-2.0
/// @file cell_view_test.cpp
/// @brief The cells view's boxes: one per boundary leaf cell of a small part, each the cell's
/// world box and level; thinned evenly past the cap.
#include "app/cell_view.h"

#include "adf/generate.h"
#include "adf/test_part.h"

#include <gtest/gtest.h>

#include <cmath>

namespace kizamu::app {
namespace {

TEST(CellView, OneBoxPerBoundaryCellOfASmallPart) {
    const adf::Domain d = adf::testPartDomain(6);
    const adf::AdfPtr a = adf::generate(*adf::makeTestPart(d), d, adf::testPartSettings());
    std::vector<render::CellBox> boxes;
    const std::size_t count = collectBoundaryCellBoxes(*a, 1000000, boxes);
    EXPECT_EQ(count, a->computeStats().boundaryCells);
    EXPECT_EQ(boxes.size(), count);
    ASSERT_GT(count, 100u);
    const double h = d.finestCellSize();
    for (const render::CellBox& b : boxes) {
        ASSERT_GE(b.level, 0);
        ASSERT_LE(b.level, d.maxLevel);
        EXPECT_NEAR(b.sizeWorld, h * double(1u << (d.maxLevel - b.level)), 1e-6);
        // On the lattice of its level, inside the domain.
        const glm::dvec3 cells = (glm::dvec3(b.minWorld) - d.originWorld) / double(b.sizeWorld);
        EXPECT_NEAR(cells.x, std::round(cells.x), 1e-3);
        EXPECT_NEAR(cells.z, std::round(cells.z), 1e-3);
        EXPECT_GE(double(b.minWorld.y), d.originWorld.y - 1e-6);
    }
    // Past the cap: every k-th, so about `cap` boxes spread over the same surface.
    std::vector<render::CellBox> thinned;
    EXPECT_EQ(collectBoundaryCellBoxes(*a, count / 10, thinned), count);
    EXPECT_LE(thinned.size(), count / 10);
    EXPECT_GE(thinned.size(), count / 11);
    EXPECT_EQ(thinned.front().minWorld, boxes.front().minWorld);
}

}  // namespace
}  // namespace kizamu::app
