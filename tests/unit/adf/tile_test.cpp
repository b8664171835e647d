// SPDX-License-Identifier: Apache-2.0
/// @file tile_test.cpp
/// @brief Tile encoding: narrow bricks (8-bit steps from the centre) and the wide fallback.
#include "adf/tile.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

using namespace kizamu::adf;

namespace {

constexpr double kCell = 1.0 / 4096.0;  // finest cell, m (level 12 of a 1 m domain)

/// The 27 half-grid values of a brick of finest cells at `origin` (lattice) for the signed
/// distance to a sphere of radius r around c (lattice units): a 1-Lipschitz field.
std::vector<float> sphereBrick(glm::dvec3 origin, glm::dvec3 c, double r) {
    std::vector<float> v(27);
    for (int g = 0; g < 27; ++g) {
        const glm::dvec3 p = origin + glm::dvec3(g % 3, (g / 3) % 3, g / 9);
        v[std::size_t(g)] = float((std::sqrt((p.x - c.x) * (p.x - c.x) + (p.y - c.y) * (p.y - c.y) + (p.z - c.z) * (p.z - c.z)) - r) * kCell);
    }
    return v;
}

/// A tile whose root is internal with 8 brick children, each from `values` (27 per brick).
TilePtr tileOfBricks(const std::vector<float>& values, const std::vector<float>& leafCorners = {}) {
    std::vector<uint32_t> nodes{1};
    for (uint32_t b = 0; b < 8; ++b) nodes.push_back(node::makeBrick(b));
    return Tile::create(9, glm::uvec3(0), nodes, leafCorners, values, 1, kCell);
}

}  // namespace

TEST(Tile, BricksOfFinestCellsAreNarrowAndWithinAStep) {
    std::vector<float> values;
    for (int b = 0; b < 8; ++b) {
        const auto v = sphereBrick(glm::dvec3(b & 1, (b >> 1) & 1, b >> 2) * 2.0, {1.3, 2.1, 40.0}, 37.7 + 0.3 * b);
        values.insert(values.end(), v.begin(), v.end());
    }
    const TilePtr t = tileOfBricks(values);
    EXPECT_EQ(t->narrowBrickCount(), 8u);
    // The figure memory work is judged by: 29 bytes per narrow brick (54 wide).
    const TilePtr wide = Tile::create(9, glm::uvec3(0), std::vector<uint32_t>{node::makeBrick(0)}, {},
                                      std::vector<float>(values.begin(), values.begin() + 27), 1, 1e-9);
    EXPECT_EQ(wide->narrowBrickCount(), 0u);
    const double step = double(t->brickStep()) * double(t->scale());
    EXPECT_LT(step, 0.02 * kCell) << "a step must stay far under epsilon (0.25 cells)";
    for (uint32_t b = 0; b < 8; ++b)
        for (int g = 0; g < 27; ++g) {
            const float exact = values[27 * b + uint32_t(g)];
            const float decoded = float(t->brickValue(t->nodes()[1 + b] & node::kBrickMask, g)) * t->scale();
            EXPECT_LE(std::abs(double(decoded - exact)), step + double(t->scale())) << "brick " << b << " point " << g;
            EXPECT_EQ(decoded < 0.0f, exact < 0.0f) << "inside must stay inside";
        }
}

TEST(Tile, NarrowEncodingIsIdempotent) {
    // Decode and re-encode (what file loading and sub-tile copying do): the same bits.
    std::vector<float> values;
    for (int b = 0; b < 8; ++b) {
        const auto v = sphereBrick(glm::dvec3(b & 1, (b >> 1) & 1, b >> 2) * 2.0, {0.4, 0.9, 1.1}, 0.7 + 0.05 * b);
        values.insert(values.end(), v.begin(), v.end());
    }
    const TilePtr t = tileOfBricks(values);
    std::vector<int16_t> decoded;
    for (uint32_t b = 0; b < t->brickCount(); ++b)
        for (int g = 0; g < 27; ++g) decoded.push_back(t->brickValue(b, g));
    const TilePtr again = Tile::createQuantised(t->level(), t->latticeOrigin(), {t->nodes(), t->nodeCount()}, {},
                                                decoded, t->scale(), 1, kCell);
    EXPECT_EQ(again->checksum(), t->checksum());
    EXPECT_EQ(again->bytes(), t->bytes());
}

TEST(Tile, BricksOutOfRangeStayWideAndExactAndAreRenumberedAfterNarrowOnes) {
    std::vector<float> values;
    for (int b = 0; b < 8; ++b) {
        auto v = sphereBrick(glm::dvec3(b & 1, (b >> 1) & 1, b >> 2) * 2.0, {0.5, 0.5, 9.0}, 6.0);
        if (b % 3 == 0) v[0] += float(20.0 * kCell);  // not 1-Lipschitz: no 8-bit step reaches it
        values.insert(values.end(), v.begin(), v.end());
    }
    const TilePtr t = tileOfBricks(values);
    EXPECT_EQ(t->narrowBrickCount(), 5u);
    for (uint32_t b = 0; b < 8; ++b) {
        const uint32_t stored = t->nodes()[1 + b] & node::kBrickMask;
        EXPECT_EQ(stored >= t->narrowBrickCount(), b % 3 == 0) << "wide bricks come after the narrow ones";
        const float exact = values[27 * b];
        const float decoded = float(t->brickValue(stored, 0)) * t->scale();
        // Wide: only the 16-bit rounding; narrow: within a step. Either way the same brick.
        EXPECT_NEAR(decoded, exact, b % 3 == 0 ? t->scale() : (t->brickStep() + 1) * t->scale());
    }
    // Memory by counter: 29 bytes a narrow brick (2 for its centre, 27 steps), 54 a wide one.
    const std::size_t header = Tile::create(9, glm::uvec3(0), std::vector<uint32_t>{node::makeLeaf(0, CellType::Exterior)},
                                            std::vector<float>(8, 1.0f), {}, 1, kCell)->bytes() - 8 - 16;
    EXPECT_EQ(t->bytes(), header + 40 /* 9 node words, 8-aligned */ + 5 * 29 + 1 /* 2-alignment */ + 3 * 54);
}
