// SPDX-License-Identifier: Apache-2.0
/// AdfBuilder: every slot must be assigned before a snapshot is published, and an edit shares
/// the chunks it does not write.
#include "adf/adf.h"
#include "adf/tile.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <stdexcept>
#include <tuple>
#include <utility>
#include <vector>

using namespace kizamu::adf;

namespace {

/// 16^3 tile slots in 2^3 chunks of 8^3.
Domain smallDomain() {
    Domain d;
    d.originWorld = glm::dvec3(0.0);
    d.sizeWorld = 1.0;
    d.maxLevel = 6;
    d.tileSpanLevels = 2;
    return d;
}

/// A tile at `slot` that is one leaf outside the material, its corners at `value` (m).
TilePtr outsideTile(const Domain& d, glm::uvec3 slot, float value = 0.5f) {
    const std::vector<float> corners(8, value);
    return Tile::create(d.tileLevel(), slot * d.cellLattice(d.tileLevel()),
                        std::vector<uint32_t>{node::makeLeaf(0, CellType::Exterior)}, corners, {}, 1, d.finestCellSize());
}

/// Assigns every slot but `skip` (none when it lies outside the domain).
void fillExcept(AdfBuilder& b, const Domain& d, glm::uvec3 skip) {
    const uint32_t n = d.slotsPerAxis();
    for (uint32_t z = 0; z < n; ++z)
        for (uint32_t y = 0; y < n; ++y)
            for (uint32_t x = 0; x < n; ++x)
                if (glm::uvec3(x, y, z) != skip) b.setTile(outsideTile(d, {x, y, z}));
}

/// A complete snapshot (version 1) and an edit of it (version 2) that replaces the tiles at
/// `changed`.
std::pair<AdfPtr, AdfPtr> snapshotAndEdit(const Domain& d, const std::vector<glm::uvec3>& changed) {
    AdfBuilder first(d, GenerationSettings{});
    fillExcept(first, d, glm::uvec3(99));
    AdfPtr base = first.build(1);
    AdfBuilder edit(*base);
    for (const glm::uvec3& s : changed) edit.setTile(outsideTile(d, s, 0.25f));
    return {std::move(base), edit.build(2)};
}

}  // namespace

TEST(AdfBuilder, AnUnassignedSlotOfAWrittenChunkIsAnError) {
    const Domain d = smallDomain();
    ASSERT_EQ(d.slotsPerAxis(), 16u);
    for (const glm::uvec3 skip : {glm::uvec3(0), glm::uvec3(5, 11, 2), glm::uvec3(15)}) {
        AdfBuilder b(d, GenerationSettings{});
        fillExcept(b, d, skip);
        EXPECT_THROW(b.build(1), std::logic_error) << skip.x << " " << skip.y << " " << skip.z;
    }
    AdfBuilder whole(d, GenerationSettings{});
    fillExcept(whole, d, glm::uvec3(99));
    EXPECT_NO_THROW(whole.build(1));
}

TEST(AdfBuilder, AChunkNeverAssignedIsAnError) {
    const Domain d = smallDomain();
    AdfBuilder b(d, GenerationSettings{});
    const uint32_t n = d.slotsPerAxis();
    for (uint32_t z = 0; z < n; ++z)
        for (uint32_t y = 0; y < n; ++y)
            for (uint32_t x = 0; x < n; ++x)
                if (x < 8 || y < 8 || z < 8) b.setTile(outsideTile(d, {x, y, z}));  // chunk (1, 1, 1) left out
    EXPECT_THROW(b.build(1), std::logic_error);
}

TEST(AdfBuilder, AnEditSharesTheChunksItDoesNotWrite) {
    const Domain d = smallDomain();
    const glm::uvec3 changed(3, 4, 5);  // in chunk (0, 0, 0)
    const auto [base, next] = snapshotAndEdit(d, {changed});
    EXPECT_EQ(next->version(), 2u);
    const uint32_t n = d.slotsPerAxis();
    for (uint32_t z = 0; z < n; ++z)
        for (uint32_t y = 0; y < n; ++y)
            for (uint32_t x = 0; x < n; ++x) {
                const glm::uvec3 s(x, y, z);
                if (s == changed) {
                    EXPECT_NE(next->tileAtSlot(s), base->tileAtSlot(s));
                    EXPECT_EQ(next->tileAtSlot(s)->latticeOrigin(), s * d.cellLattice(d.tileLevel()));
                } else {
                    EXPECT_EQ(next->tileAtSlot(s), base->tileAtSlot(s));
                }
            }
}

TEST(AdfBuilder, SlotsDifferingBetweenSnapshotsAreExactlyTheReplacedOnes) {
    const Domain d = smallDomain();
    const std::vector<glm::uvec3> changed{{3, 4, 5}, {3, 4, 6}, {12, 1, 9}};  // two chunks of eight
    const auto [base, next] = snapshotAndEdit(d, changed);

    std::vector<glm::uvec3> found;
    next->forEachSlotDiffering(*base, [&](glm::uvec3 s) { found.push_back(s); });
    auto sorted = [](std::vector<glm::uvec3> v) {
        std::sort(v.begin(), v.end(), [](glm::uvec3 l, glm::uvec3 r) {
            return std::tie(l.z, l.y, l.x) < std::tie(r.z, r.y, r.x);
        });
        return v;
    };
    EXPECT_EQ(sorted(found), sorted(changed));
    found.clear();
    base->forEachSlotDiffering(*next, [&](glm::uvec3 s) { found.push_back(s); });
    EXPECT_EQ(sorted(found), sorted(changed));
    std::size_t none = 0;
    next->forEachSlotDiffering(*next, [&](glm::uvec3) { ++none; });
    EXPECT_EQ(none, 0u);
    // Snapshots built apart share no chunk and no tile: every slot differs.
    AdfBuilder apart(d, GenerationSettings{});
    fillExcept(apart, d, glm::uvec3(99));
    std::size_t all = 0;
    apart.build(3)->forEachSlotDiffering(*base, [&](glm::uvec3) { ++all; });
    EXPECT_EQ(all, std::size_t(d.slotsPerAxis()) * d.slotsPerAxis() * d.slotsPerAxis());
}
