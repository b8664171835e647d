// SPDX-License-Identifier: Apache-2.0
/// AdfBuilder: every slot must be assigned before a snapshot is published, and an edit shares
/// the chunks it does not write.
#include "adf/adf.h"
#include "adf/tile.h"

#include <gtest/gtest.h>

#include <stdexcept>
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

TEST(AdfBuilder, AnEditSharesTheChunksItDoesNotWrite) {
    const Domain d = smallDomain();
    AdfBuilder first(d, GenerationSettings{});
    fillExcept(first, d, glm::uvec3(99));
    const AdfPtr base = first.build(1);

    AdfBuilder edit(*base);
    const glm::uvec3 changed(3, 4, 5);  // in chunk (0, 0, 0)
    edit.setTile(outsideTile(d, changed, 0.25f));
    const AdfPtr next = edit.build(2);
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
