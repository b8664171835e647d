// SPDX-License-Identifier: Apache-2.0
/// @file tile_diff_test.cpp
/// @brief appendChangedCells: its boxes against a plain comparison of every leaf of both tiles,
/// and the old tile's node words it reports at them against a search from the root.
#include "adf/tile_diff.h"

#include "adf/generate.h"
#include "adf/test_part.h"
#include "tests/util/dabbed.h"

#include <gtest/gtest.h>

#include <map>
#include <tuple>
#include <utility>
#include <vector>

namespace kizamu::adf {
namespace {

using CellKey = std::tuple<uint32_t, uint32_t, uint32_t, uint32_t>;  // origin, size

/// Every leaf of `t` (lone leaves and brick children) with its decoded corners.
void leavesOf(const Tile& t, uint32_t word, glm::uvec3 origin, uint32_t size,
              std::map<CellKey, std::vector<float>>& out) {
    const uint32_t half = size / 2;
    auto at = [&](int c) { return origin + glm::uvec3(c & 1, (c >> 1) & 1, c >> 2) * half; };
    if (node::isInternal(word)) {
        for (int c = 0; c < 8; ++c) leavesOf(t, t.node(word + uint32_t(c)), at(c), half, out);
    } else if (node::isLeaf(word)) {
        std::vector<float> v(8);
        t.leafCorners(node::leafIndex(word), v.data());
        out[{origin.x, origin.y, origin.z, size}] = v;
    } else {
        for (int c = 0; c < 8; ++c) {
            std::vector<float> v(8);
            t.brickCorners(node::brickIndex(word), c, v.data());
            out[{at(c).x, at(c).y, at(c).z, half}] = v;
        }
    }
}

/// The node word `t` holds at the cell (origin, size), searched from the root, and whether the
/// cell is a brick's child (then the word is the brick's).
std::pair<uint32_t, bool> wordAt(const Tile& t, int maxLevel, glm::uvec3 origin, uint32_t size) {
    uint32_t w = t.node(0), s = 1u << uint32_t(maxLevel - t.level());
    glm::uvec3 o = t.latticeOrigin();
    while (s > size) {
        EXPECT_FALSE(node::isLeaf(w)) << "a box inside a leaf";
        if (node::isBrick(w)) {
            EXPECT_EQ(s, 2 * size) << "a box inside a brick's child";
            return {w, true};
        }
        s /= 2;
        const glm::uvec3 c = (origin - o) / s;
        o += c * s;
        w = t.node(w + (c.x | (c.y << 1) | (c.z << 2)));
    }
    return {w, false};
}

TEST(TileDiff, BoxesCoverEveryChangedLeafAndNameTheOldTilesNodes) {
    const Domain d = testPartDomain(8);
    AdfPtr a = generate(*makeTestPart(d), d, testPartSettings());
    const double r = 3.5 * d.finestCellSize();
    std::size_t tiles = 0, boxes = 0, oldLeaves = 0, oldBrickChildren = 0,
                oldNodes = 0;  // by what `before` holds there
    for (int edit = 0; edit < 6; ++edit) {
        const glm::dvec3 c = d.originWorld + glm::dvec3(0.5, 0.45 + 0.02 * edit, 0.5) * d.sizeWorld;
        const AdfPtr b =
            dabbed(a, edit % 2 ? CsgOp::Union : CsgOp::Difference, c, r * (1 + edit % 3));
        b->forEachTile([&](const Tile& after) {
            const Tile* before =
                a->tileAtSlot(after.latticeOrigin() >> uint32_t(d.maxLevel - d.tileLevel()));
            if (before == &after || before->level() != after.level()) return;
            ++tiles;
            std::vector<LatticeBox> plain, got;
            std::vector<uint32_t> words;
            appendChangedCells(*before, after, d.maxLevel, plain);
            appendChangedCells(*before, after, d.maxLevel, got, &words);
            ASSERT_EQ(got.size(), plain.size());
            ASSERT_EQ(words.size(), got.size());
            // Every leaf of either tile that the other lacks or decodes differently lies in a box;
            // every box holds one.
            std::map<CellKey, std::vector<float>> la, lb;
            const uint32_t size = 1u << uint32_t(d.maxLevel - after.level());
            leavesOf(*before, before->node(0), before->latticeOrigin(), size, la);
            leavesOf(after, after.node(0), after.latticeOrigin(), size, lb);
            auto inBoxes = [&](const CellKey& k) {
                for (const LatticeBox& x : got)
                    if (std::get<0>(k) >= x.lo.x &&
                        std::get<0>(k) + std::get<3>(k) <= x.lo.x + x.size &&
                        std::get<1>(k) >= x.lo.y &&
                        std::get<1>(k) + std::get<3>(k) <= x.lo.y + x.size &&
                        std::get<2>(k) >= x.lo.z &&
                        std::get<2>(k) + std::get<3>(k) <= x.lo.z + x.size)
                        return true;
                return false;
            };
            for (const auto& [k, v] : la) {
                auto it = lb.find(k);
                EXPECT_EQ(it == lb.end() || it->second != v, inBoxes(k));
            }
            for (const auto& [k, v] : lb) {
                if (!la.count(k)) {
                    EXPECT_TRUE(inBoxes(k));
                }
            }
            for (std::size_t i = 0; i < got.size(); ++i) {
                EXPECT_EQ(got[i].lo, plain[i].lo);
                EXPECT_EQ(got[i].size, plain[i].size);
                const auto [want, brickChild] = wordAt(*before, d.maxLevel, got[i].lo, got[i].size);
                if (brickChild) {
                    EXPECT_EQ(words[i], node::kLeafBit)
                        << "box " << i;  // a leaf's word: its brick holds it
                    ++oldBrickChildren;
                } else {
                    EXPECT_EQ(words[i], want) << "box " << i;
                    ++(node::isLeaf(want) ? oldLeaves : oldNodes);
                }
            }
            boxes += got.size();
        });
        a = b;
    }
    // Carving refines leaves, adding coarsens some: every kind of old cell occurs.
    EXPECT_GT(tiles, 0u);
    EXPECT_GT(boxes, 50u);
    EXPECT_GT(oldLeaves, 0u);
    EXPECT_GT(oldBrickChildren, 0u);
    EXPECT_GT(oldNodes, 0u);
}

}  // namespace
}  // namespace kizamu::adf
