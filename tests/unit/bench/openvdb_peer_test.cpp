// SPDX-License-Identifier: Apache-2.0
// The OpenVDB peer against an exact sphere: trilinear distance and gradient, memory, band size.
#include "bench/openvdb_peer.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

using namespace kizamu;

namespace {

constexpr double kRadius = 0.3;

adf::Domain sphereDomain() {
    adf::Domain domain;
    domain.originWorld = glm::dvec3(-0.5);
    domain.sizeWorld = 1.0;
    domain.maxLevel = 7;
    return domain;
}

/// Random point within `band` (m) of the sphere surface.
glm::dvec3 pointNearSurface(std::mt19937& rng, double band) {
    std::normal_distribution<double> normal(0.0, 1.0);
    std::uniform_real_distribution<double> offset(-band, band);
    glm::dvec3 dir;
    do dir = {normal(rng), normal(rng), normal(rng)};
    while (glm::length(dir) < 1e-6);
    return glm::normalize(dir) * (kRadius + offset(rng));
}

/// Checks 200 points within `bandCells` finest cells of the surface.
void expectAccurate(float halfWidthVoxels, double bandCells) {
    const adf::Domain domain = sphereDomain();
    const double h = domain.finestCellSize();
    bench::OpenVdbPeer peer(*adf::makeSphere(kRadius), domain, halfWidthVoxels);

    std::mt19937 rng(1234);
    double worstDistance = 0.0, worstGradient = 0.0;
    for (int i = 0; i < 200; ++i) {
        const glm::dvec3 p = pointNearSurface(rng, bandCells * h);
        const adf::Sample s = peer.sample(glm::vec3(p));
        const double exact = glm::length(p) - kRadius;
        const glm::dvec3 normal = glm::normalize(p);
        worstDistance = std::max(worstDistance, std::abs(double(s.distance) - exact));
        worstGradient = std::max(worstGradient, glm::length(glm::dvec3(s.gradient) - normal));
    }
    // Trilinear interpolation of the exact SDF errs by O(h^2 / r), its gradient by O(h / r).
    // Measured worst over 2e5 such points: 0.0069 h and 0.019; the bounds leave ~1.5x margin.
    EXPECT_LT(worstDistance, 0.01 * h);
    EXPECT_LT(worstGradient, 0.03);
}

// The 8-voxel stencil reaches sqrt(3) cells beyond the query point, so points 2 cells out need
// a band wider than 2 + sqrt(3) cells to see only true distances, not clamped background.
TEST(OpenVdbPeer, SphereWithinTwoCellsWithWideBand) { expectAccurate(4.0f, 2.0); }

// With the default band (3 cells) the same accuracy holds within 3 - sqrt(3) cells.
TEST(OpenVdbPeer, SphereWithinOneCellWithDefaultBand) { expectAccurate(3.0f, 1.0); }

TEST(OpenVdbPeer, MemoryAndBandSize) {
    const adf::Domain domain = sphereDomain();
    const double h = domain.finestCellSize();
    const float halfWidth = 3.0f;
    bench::OpenVdbPeer peer(*adf::makeSphere(kRadius), domain, halfWidth);

    EXPECT_GT(peer.memoryBytes(), 0u);
    EXPECT_GE(peer.buildSeconds(), 0.0);
    const double bandVoxels =
        4.0 * std::numbers::pi * kRadius * kRadius * 2.0 * double(halfWidth) * h / (h * h * h);
    EXPECT_GT(double(peer.activeVoxels()), 0.5 * bandVoxels);
    EXPECT_LT(double(peer.activeVoxels()), 2.0 * bandVoxels);
}

TEST(OpenVdbPeer, FarPointsReadBackgroundWithTheRightSign) {
    const adf::Domain domain = sphereDomain();
    const float halfWidth = 3.0f;
    const float background = float(halfWidth * domain.finestCellSize());
    bench::OpenVdbPeer peer(*adf::makeSphere(kRadius), domain, halfWidth);

    // Centre: flood-filled interior; corner region: exterior background.
    EXPECT_FLOAT_EQ(peer.sample(glm::vec3(0.0f)).distance, -background);
    EXPECT_FLOAT_EQ(peer.sample(glm::vec3(0.45f, 0.45f, 0.45f)).distance, background);
}

}  // namespace
