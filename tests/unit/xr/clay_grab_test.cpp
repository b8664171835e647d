// SPDX-License-Identifier: Apache-2.0
#include "xr/clay_grab.h"

#include <gtest/gtest.h>

namespace kizamu::xr {
namespace {

Pose at(glm::dvec3 p, glm::dquat q = glm::dquat(1, 0, 0, 0)) { return {p, q}; }

void expectNear(const glm::dvec3& a, const glm::dvec3& b, double tol = 1e-9) {
    EXPECT_LT(glm::length(a - b), tol) << "(" << a.x << ", " << a.y << ", " << a.z << ") vs (" << b.x << ", " << b.y << ", " << b.z << ")";
}

TEST(ClayGrab, OneHandCarriesTheClayRigidly) {
    ClayGrab grab;
    Similarity placement;
    placement.translation = {0.0, 0.0, -0.4};
    const glm::dvec3 clayPoint(0.02, 0.01, 0.0);
    const glm::dvec3 seenBefore = placement.apply(clayPoint);
    placement = grab.update({at({0.1, 0.0, -0.3}), std::nullopt}, placement);  // takes hold: nothing moves
    expectNear(placement.apply(clayPoint), seenBefore);
    // The hand moves 5 cm up and turns a quarter about Y: the clay follows it exactly.
    const glm::dquat turn = glm::angleAxis(0.5 * M_PI, glm::dvec3(0, 1, 0));
    placement = grab.update({at({0.1, 0.05, -0.3}, turn), std::nullopt}, placement);
    const glm::dvec3 handToPoint = seenBefore - glm::dvec3(0.1, 0.0, -0.3);
    expectNear(placement.apply(clayPoint), glm::dvec3(0.1, 0.05, -0.3) + turn * handToPoint);
    EXPECT_NEAR(placement.scale, 1.0, 1e-12);
    // Letting go leaves it where it is.
    const Similarity held = placement;
    placement = grab.update({std::nullopt, std::nullopt}, placement);
    expectNear(placement.apply(clayPoint), held.apply(clayPoint));
    EXPECT_FALSE(grab.holding());
}

TEST(ClayGrab, TwoHandsScaleWithTheirDistanceAboutTheirMidpoint) {
    ClayGrab grab;
    Similarity placement;
    placement.translation = {0.0, 0.0, -0.4};
    placement = grab.update({at({-0.1, 0.0, -0.4}), at({0.1, 0.0, -0.4})}, placement);
    // Hands twice as far apart, same midpoint: twice the size, the midpoint fixed.
    placement = grab.update({at({-0.2, 0.0, -0.4}), at({0.2, 0.0, -0.4})}, placement);
    EXPECT_NEAR(placement.scale, 2.0, 1e-12);
    expectNear(placement.apply(glm::dvec3(0.0)), glm::dvec3(0.0, 0.0, -0.4));
    expectNear(placement.apply(glm::dvec3(0.05, 0.0, 0.0)), glm::dvec3(0.1, 0.0, -0.4));
    // Both hands move 10 cm to the right: the clay goes with them.
    placement = grab.update({at({-0.1, 0.0, -0.4}), at({0.3, 0.0, -0.4})}, placement);
    expectNear(placement.apply(glm::dvec3(0.0)), glm::dvec3(0.1, 0.0, -0.4));
}

TEST(ClayGrab, ChangingHandsNeverJumps) {
    ClayGrab grab;
    Similarity placement;
    placement = grab.update({at({-0.1, 0, 0}), at({0.1, 0, 0})}, placement);
    placement = grab.update({at({-0.15, 0, 0}), at({0.15, 0, 0})}, placement);
    const Similarity twoHanded = placement;
    // One hand lets go while the other stays still: the clay stays.
    placement = grab.update({at({-0.15, 0, 0}), std::nullopt}, placement);
    expectNear(placement.apply(glm::dvec3(0.01, 0.02, 0.03)), twoHanded.apply(glm::dvec3(0.01, 0.02, 0.03)));
    EXPECT_NEAR(placement.scale, twoHanded.scale, 1e-12);
}

TEST(ClayGrab, ScaleStaysWithinItsLimits) {
    ClayGrab grab(0.5, 2.0);
    Similarity placement;
    placement = grab.update({at({-0.1, 0, 0}), at({0.1, 0, 0})}, placement);
    placement = grab.update({at({-1.0, 0, 0}), at({1.0, 0, 0})}, placement);
    EXPECT_NEAR(placement.scale, 2.0, 1e-12);
    placement = grab.update({at({-0.001, 0, 0}), at({0.001, 0, 0})}, placement);
    EXPECT_NEAR(placement.scale, 0.5, 1e-12);
}

}  // namespace
}  // namespace kizamu::xr
