// SPDX-License-Identifier: Apache-2.0
// Exact values of every primitive, transforms, CSG, and the 1-Lipschitz property.
#include "adf/distance_source.h"
#include "adf/domain.h"

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace kizamu::adf;

namespace {

constexpr double kTol = 1e-12;

TEST(DistanceSource, SphereIsExact) {
    const auto s = makeSphere(0.5);
    EXPECT_NEAR(s->distance({0, 0, 0}), -0.5, kTol);
    EXPECT_NEAR(s->distance({1, 0, 0}), 0.5, kTol);
    EXPECT_NEAR(s->distance({0, 0.3, 0.4}), 0.0, kTol);
}

TEST(DistanceSource, BoxIsExactInsideOutsideAndAtCorners) {
    const auto b = makeBox({1, 2, 3});
    EXPECT_NEAR(b->distance({0, 0, 0}), -1.0, kTol);          // nearest face x
    EXPECT_NEAR(b->distance({0, 0, 2.5}), -0.5, kTol);        // nearest face z
    EXPECT_NEAR(b->distance({2, 0, 0}), 1.0, kTol);           // face
    EXPECT_NEAR(b->distance({2, 3, 0}), std::sqrt(2.0), kTol);  // edge
    EXPECT_NEAR(b->distance({2, 3, 4}), std::sqrt(3.0), kTol);  // corner
}

TEST(DistanceSource, RoundedBoxRoundsEdges) {
    const auto b = makeRoundedBox({1, 1, 1}, 0.25);
    EXPECT_NEAR(b->distance({2, 0, 0}), 1.0, kTol);
    // Along the edge diagonal the surface sits at the rounded edge: 0.75*sqrt2 + 0.25 from the axis.
    const double r = 0.75 * std::sqrt(2.0) + 0.25;
    EXPECT_NEAR(b->distance({r / std::sqrt(2.0), r / std::sqrt(2.0), 0}), 0.0, kTol);
    EXPECT_NEAR(b->distance({0, 0, 0}), -1.0, kTol);
}

TEST(DistanceSource, CapsuleCylinderTorusHalfSpace) {
    const auto c = makeCapsule({0, 0, -1}, {0, 0, 1}, 0.5);
    EXPECT_NEAR(c->distance({1, 0, 0.3}), 0.5, kTol);
    EXPECT_NEAR(c->distance({0, 0, 2}), 0.5, kTol);
    EXPECT_NEAR(c->distance({0, 0, 0}), -0.5, kTol);

    const auto y = makeCylinder(0.5, 1.0);
    EXPECT_NEAR(y->distance({1, 0, 0}), 0.5, kTol);
    EXPECT_NEAR(y->distance({0, 0, 1.5}), 0.5, kTol);
    EXPECT_NEAR(y->distance({0.8, 0, 1.4}), 0.5, kTol);  // rim: (0.3, 0.4) away
    EXPECT_NEAR(y->distance({0, 0, 0}), -0.5, kTol);
    EXPECT_NEAR(y->distance({0, 0, 0.9}), -0.1, kTol);

    const auto t = makeTorus(1.0, 0.25);
    EXPECT_NEAR(t->distance({1, 0, 0}), -0.25, kTol);
    EXPECT_NEAR(t->distance({0, 0, 0}), 0.75, kTol);
    EXPECT_NEAR(t->distance({0, 1, 0.5}), 0.25, kTol);

    const auto h = makeHalfSpace({0, 0, 2}, 0.5);
    EXPECT_NEAR(h->distance({3, 4, 0.5}), 0.0, kTol);
    EXPECT_NEAR(h->distance({0, 0, -1}), -1.5, kTol);
}

TEST(DistanceSource, TransformsMoveRotateAndScale) {
    const auto moved = makeTranslated(makeSphere(1.0), {2, 0, 0});
    EXPECT_NEAR(moved->distance({2, 0, 0}), -1.0, kTol);
    // A box 1 x 0.1 x 0.1 rotated 90 degrees about z lies along y.
    const auto rotated = makeTransformed(makeBox({1, 0.1, 0.1}), {0, 0, 0},
                                         glm::angleAxis(M_PI / 2, glm::dvec3(0, 0, 1)));
    EXPECT_NEAR(rotated->distance({0, 2, 0}), 1.0, 1e-9);
    EXPECT_NEAR(rotated->distance({2, 0, 0}), 1.9, 1e-9);
    const auto scaled = makeTransformed(makeSphere(1.0), {0, 0, 0}, glm::dquat(1, 0, 0, 0), 3.0);
    EXPECT_NEAR(scaled->distance({5, 0, 0}), 2.0, kTol);
}

TEST(DistanceSource, CsgOperators) {
    const auto a = makeSphere(1.0);
    const auto b = makeTranslated(makeSphere(1.0), {1.5, 0, 0});
    const glm::dvec3 p(-2, 0, 0), q(0.75, 0, 0);
    EXPECT_NEAR(makeCsg(CsgOp::Union, a, b)->distance(p), 1.0, kTol);
    EXPECT_NEAR(makeCsg(CsgOp::Intersection, a, b)->distance(q), -0.25, kTol);
    EXPECT_NEAR(makeCsg(CsgOp::Difference, a, b)->distance(q), 0.25, kTol);
    // Smooth union lies below the sharp one in the blend zone and equals it away from it.
    const auto smooth = makeCsg(CsgOp::Union, a, b, 0.5);
    EXPECT_LT(smooth->distance({0.75, 1.0, 0}), makeCsg(CsgOp::Union, a, b)->distance({0.75, 1.0, 0}));
    EXPECT_NEAR(smooth->distance(p), 1.0, kTol);
    EXPECT_THROW(makeCsg(CsgOp::Union, std::vector<SourcePtr>{}), std::invalid_argument);
    EXPECT_THROW(makeSphere(-1.0), std::invalid_argument);
}

TEST(DistanceSource, BatchMatchesScalarAndIsLipschitz) {
    const auto part = makeCsg(
        CsgOp::Difference,
        {makeRoundedBox({0.3, 0.3, 0.3}, 0.05), makeCylinder(0.1, 0.5),
         makeTransformed(makeTorus(0.2, 0.05), {0, 0, 0.3}, glm::angleAxis(0.3, glm::dvec3(1, 0, 0)))},
        0.02);
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(-0.6, 0.6);
    std::vector<glm::dvec3> pts(300);
    for (auto& p : pts) p = {u(rng), u(rng), u(rng)};
    std::vector<double> out(pts.size());
    part->distances(pts, out);
    for (std::size_t i = 0; i < pts.size(); ++i) {
        EXPECT_EQ(out[i], part->distance(pts[i]));
        if (i > 0) {
            EXPECT_LE(std::abs(out[i] - out[i - 1]), glm::distance(pts[i], pts[i - 1]) * (1 + 1e-9));
        }
    }
}

TEST(DistanceSource, LatticeBatchIsTheFieldAtTheLatticePointsWorldPositions) {
    // What generation asks: 150 points (past two batches of kSourceBatch) of a level-7 lattice
    // whose origin and size are not powers of two, so world points computed with less precision
    // (in float, say) give other values.
    const auto box = makeTranslated(makeBox({0.1, 0.2, 0.1}), {0.25, 0, 0});
    const auto part = makeCsg(CsgOp::Union, makeSphere(0.3), box);
    Domain d;
    d.originWorld = glm::dvec3(-0.2466, -0.2, 0.1234 - 0.37);
    d.sizeWorld = 0.37 * 1.7;
    d.maxLevel = 7;
    std::mt19937_64 rng(11);
    std::uniform_int_distribution<uint32_t> u(0, d.latticeSize());
    std::vector<glm::uvec3> lattice(150);
    for (auto& p : lattice) p = {u(rng), u(rng), u(rng)};
    std::vector<double> out(lattice.size());
    part->latticeDistances(d, lattice, out);
    for (std::size_t i = 0; i < lattice.size(); ++i)
        EXPECT_EQ(out[i], part->distance(d.latticeToWorld(lattice[i].x, lattice[i].y, lattice[i].z))) << i;
}

}  // namespace
