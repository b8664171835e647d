// SPDX-License-Identifier: Apache-2.0
/// @file boundary_cells_test.cpp
/// @brief appendBoundaryCells against a plain walk that decodes every leaf's corners (the scan
/// decides lone leaves on their node word's type and brick children on sign masks).
#include "adf/generate.h"
#include "adf/test_part.h"
#include "adf/boundary_cells.h"
#include "adf/tile_diff.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <tuple>
#include <vector>

namespace kizamu::adf {
namespace {

/// Every leaf of `t` whose decoded corners change sign, depth first.
void referenceCells(const Tile& t, int maxLevel, uint32_t nodeIndex, glm::uvec3 origin, uint32_t size,
                    std::vector<BoundaryCell>& out) {
    auto add = [&](glm::uvec3 o, uint32_t s, const float* c, bool brickChild) {
        const bool anyIn = std::any_of(c, c + 8, [](float v) { return v < 0.0f; });
        const bool allIn = std::all_of(c, c + 8, [](float v) { return v < 0.0f; });
        if (!anyIn || allIn) return;
        BoundaryCell b{o, s, {}, brickChild};
        std::copy(c, c + 8, b.corners);
        out.push_back(b);
    };
    const uint32_t w = t.node(nodeIndex);
    const uint32_t half = size / 2;
    if (node::isInternal(w)) {
        for (int c = 0; c < 8; ++c)
            referenceCells(t, maxLevel, w + uint32_t(c), origin + glm::uvec3(c & 1, (c >> 1) & 1, c >> 2) * half, half, out);
    } else if (node::isLeaf(w)) {
        float c[8];
        t.leafCorners(node::leafIndex(w), c);
        add(origin, size, c, false);
    } else {
        for (int child = 0; child < 8; ++child) {
            float c[8];
            t.brickCorners(node::brickIndex(w), child, c);
            add(origin + glm::uvec3(child & 1, (child >> 1) & 1, child >> 2) * half, half, c, true);
        }
    }
}

void expectSameCells(std::vector<BoundaryCell> got, std::vector<BoundaryCell> want) {
    auto key = [](const BoundaryCell& b) { return std::make_tuple(b.origin.z, b.origin.y, b.origin.x, b.size); };
    auto byKey = [&](const BoundaryCell& l, const BoundaryCell& r) { return key(l) < key(r); };
    std::sort(got.begin(), got.end(), byKey);
    std::sort(want.begin(), want.end(), byKey);
    ASSERT_EQ(got.size(), want.size());
    for (std::size_t i = 0; i < got.size(); ++i) {
        ASSERT_EQ(key(got[i]), key(want[i])) << "cell " << i;
        EXPECT_EQ(got[i].brickChild, want[i].brickChild) << "cell " << i;
        for (int c = 0; c < 8; ++c) EXPECT_EQ(got[i].corners[c], want[i].corners[c]) << "cell " << i << " corner " << c;
    }
}

TEST(BoundaryCells, AreTheLeavesWhoseDecodedCornersChangeSign) {
    const Domain d = testPartDomain(8);
    const AdfPtr a = generate(*makeTestPart(d), d, testPartSettings());
    std::size_t cells = 0, brickChildren = 0, lone = 0;
    a->forEachTile([&](const Tile& t) {
        std::vector<BoundaryCell> got, want;
        appendBoundaryCells(t, d.maxLevel, got);
        referenceCells(t, d.maxLevel, 0, t.latticeOrigin(), 1u << uint32_t(d.maxLevel - t.level()), want);
        expectSameCells(got, want);
        cells += want.size();
        for (const BoundaryCell& b : want) (b.brickChild ? brickChildren : lone) += 1;
    });
    // The part exercises both kinds of cell.
    EXPECT_GT(brickChildren, 1000u);
    EXPECT_GT(lone, 100u);
    EXPECT_EQ(cells, brickChildren + lone);
}

TEST(BoundaryCells, TouchingABoxAreThoseOfTheWholeTileThatTouchIt) {
    const Domain d = testPartDomain(8);
    const AdfPtr a = generate(*makeTestPart(d), d, testPartSettings());
    const std::vector<LatticeBox> boxes{{glm::uvec3(100, 90, 120), 37}, {glm::uvec3(20, 140, 60), 5}};
    std::size_t cells = 0;
    a->forEachTile([&](const Tile& t) {
        std::vector<BoundaryCell> got, all;
        appendBoundaryCellsTouching(t, d.maxLevel, boxes, got);
        appendBoundaryCells(t, d.maxLevel, all);
        std::erase_if(all, [&](const BoundaryCell& b) {
            return std::none_of(boxes.begin(), boxes.end(), [&](const LatticeBox& x) { return touches(x, b.origin, b.size); });
        });
        expectSameCells(got, all);
        cells += all.size();
    });
    EXPECT_GT(cells, 0u);
}

TEST(BoundaryCells, TouchingABoxWithAFilterAreThoseTheFilterKeeps) {
    const Domain d = testPartDomain(8);
    const AdfPtr a = generate(*makeTestPart(d), d, testPartSettings());
    const std::vector<LatticeBox> boxes{{glm::uvec3(100, 90, 120), 37}, {glm::uvec3(20, 140, 60), 5}};
    // Keeps a leaf by its box alone (its position in units of its size), so lone leaves and
    // brick children are both kept and refused.
    auto keep = [](glm::uvec3 o, uint32_t size) { return (o.x / size + o.y / size + o.z / size) % 3 != 0; };
    const LeafFilter filter{[](const void* k, glm::uvec3 o, uint32_t size) { return (*static_cast<const decltype(keep)*>(k))(o, size); },
                            &keep};
    std::size_t kept[2] = {}, refused[2] = {};  // [brick child]
    a->forEachTile([&](const Tile& t) {
        std::vector<BoundaryCell> got, all;
        appendBoundaryCellsTouching(t, d.maxLevel, boxes, got, filter);
        appendBoundaryCellsTouching(t, d.maxLevel, boxes, all);
        for (const BoundaryCell& b : all) ++(keep(b.origin, b.size) ? kept : refused)[b.brickChild];
        std::erase_if(all, [&](const BoundaryCell& b) { return !keep(b.origin, b.size); });
        expectSameCells(got, all);
    });
    for (int brickChild = 0; brickChild < 2; ++brickChild) {
        EXPECT_GT(kept[brickChild], 0u);
        EXPECT_GT(refused[brickChild], 0u);
    }
}

}  // namespace
}  // namespace kizamu::adf
