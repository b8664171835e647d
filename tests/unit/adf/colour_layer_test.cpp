// SPDX-License-Identifier: Apache-2.0
// The colour layer: lookups, the trilinear blend, copy-on-write replacement, and that snapshots
// built from a base carry its paint.
#include "adf/colour_layer.h"

#include "adf/generate.h"

#include <gtest/gtest.h>

using namespace kizamu;
using namespace kizamu::adf;

namespace {

Domain smallDomain() {
    Domain d;
    d.maxLevel = 6;
    d.tileSpanLevels = 3;  // 8 slots per axis, 8 points per slot axis
    return d;
}

/// A tile painting the given local points of one slot.
ColourTilePtr tileOf(std::vector<uint32_t> points, Rgb8 c) {
    std::vector<Rgb8> colours(points.size(), c);
    return std::make_shared<const ColourTile>(std::move(points), std::move(colours));
}

uint32_t local(glm::uvec3 p) { return (p.z << 6) | (p.y << 3) | p.x; }

TEST(ColourLayer, LooksUpPaintedPointsAndBlendsBetweenThem) {
    const Domain d = smallDomain();
    const Rgb8 red(255, 0, 0);
    const ColourLayer empty(d);
    EXPECT_EQ(empty.baseColour(), kClayColour);
    EXPECT_EQ(empty.colourAt({0.5f, 0.5f, 0.5f}), kClayColour);
    // Slot (1, 2, 3): points (9..10, 17, 25) in lattice units.
    const uint32_t key = empty.slotKey({1, 2, 3});
    const ColourLayerPtr layer = empty.withTiles({{key, tileOf({local({1, 1, 1}), local({2, 1, 1})}, red)}});
    EXPECT_EQ(layer->colourAtLattice({9, 17, 25}), red);
    EXPECT_EQ(layer->colourAtLattice({10, 17, 25}), red);
    EXPECT_EQ(layer->colourAtLattice({11, 17, 25}), kClayColour);
    EXPECT_EQ(layer->colourAtLattice({9, 18, 25}), kClayColour);
    EXPECT_EQ(layer->pointCount(), 2u);
    // World positions: the finest cell is 1/64 m.
    const float h = 1.0f / 64.0f;
    EXPECT_EQ(layer->colourAt(glm::vec3(9, 17, 25) * h), red) << "exactly on a painted point";
    // Half-way between (10,17,25) (red) and (11,17,25) (clay) along x, on the lattice in y, z.
    const Rgb8 half = layer->colourAt(glm::vec3(10.5f, 17.0f, 25.0f) * h);
    EXPECT_NEAR(half.r, (255 + 200) / 2.0, 0.51);
    EXPECT_NEAR(half.g, 192 / 2.0, 0.51);
    EXPECT_NEAR(half.b, 180 / 2.0, 0.51);
    // The accessor agrees everywhere, also across slot borders and outside the domain.
    ColourAccessor acc(*layer);
    for (float x = -0.1f; x < 1.1f; x += 0.013f)
        for (float y : {17.0f * h, 17.3f * h, 16.9f * h})
            EXPECT_EQ(acc.colourAt({x, y, 25.2f * h}), layer->colourAt({x, y, 25.2f * h})) << x << " " << y;
}

TEST(ColourLayer, ReplacingTilesSharesTheOthersAndNullUnpaints) {
    const Domain d = smallDomain();
    const ColourLayer empty(d);
    const uint32_t a = empty.slotKey({0, 0, 0}), b = empty.slotKey({7, 7, 7}), c = empty.slotKey({3, 0, 0});
    const ColourLayerPtr one = empty.withTiles({{b, tileOf({5}, {1, 2, 3})}, {a, tileOf({0, 7}, {4, 5, 6})}});
    ASSERT_EQ(one->slotCount(), 2u);
    EXPECT_EQ(one->slotKeys()[0], a) << "slots are kept sorted";
    const ColourLayerPtr two = one->withTiles({{c, tileOf({1}, {7, 8, 9})}, {a, nullptr}});
    ASSERT_EQ(two->slotCount(), 2u);
    EXPECT_EQ(two->tileAt(a), nullptr);
    EXPECT_EQ(two->tileAt(b), one->tileAt(b)) << "untouched tiles are shared, not copied";
    EXPECT_EQ(one->tileAt(a)->size(), 2u) << "the old layer is unchanged";
    EXPECT_THROW(ColourLayer::create(d, kClayColour, {b, a}, {tileOf({1}, {1, 1, 1}), tileOf({1}, {1, 1, 1})}),
                 std::invalid_argument);
    EXPECT_THROW(ColourLayer::create(d, kClayColour, {512}, {tileOf({1}, {1, 1, 1})}), std::invalid_argument);
}

TEST(ColourLayer, SnapshotsBuiltFromABaseCarryItsPaintAndRegenerationKeepsIt) {
    const Domain d = smallDomain();
    const AdfPtr plain = generate(*makeTranslated(makeSphere(0.3), glm::dvec3(0.5)), d, GenerationSettings{});
    EXPECT_EQ(plain->colours(), nullptr);
    const ColourLayer empty(d);
    const ColourLayerPtr layer = empty.withTiles({{empty.slotKey({4, 4, 7}), tileOf({1, 2, 3}, {9, 9, 9})}});
    AdfBuilder b(*plain);
    b.setColours(layer);
    const AdfPtr painted = b.build(plain->version() + 1);
    EXPECT_EQ(painted->colours(), layer);
    EXPECT_EQ(painted->tileAtSlot({4, 4, 4}), plain->tileAtSlot({4, 4, 4}));
    const BoxWorld region{glm::dvec3(0.1), glm::dvec3(0.3)};
    const AdfPtr carved = regenerate(*painted, *makeTranslated(makeSphere(0.25), glm::dvec3(0.5)), region);
    EXPECT_EQ(carved->colours(), layer) << "an edit keeps the paint";
    Domain other = d;
    other.maxLevel = 7;
    AdfBuilder wrong(*plain);
    EXPECT_THROW(wrong.setColours(std::make_shared<const ColourLayer>(other)), std::invalid_argument);
}

}  // namespace
