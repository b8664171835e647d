// SPDX-License-Identifier: Apache-2.0
#include "xr/stylus_registration.h"

#include <gtest/gtest.h>

#include <random>
#include <stdexcept>
#include <vector>

namespace kizamu::xr {
namespace {

Similarity knownRegistration() {
    Similarity s;
    s.rotation = glm::normalize(glm::angleAxis(0.7, glm::normalize(glm::dvec3(0.3, 1.0, -0.2))));
    s.scale = 1.8;
    s.translation = glm::dvec3(0.1, -0.4, 0.25);
    return s;
}

TEST(StylusRegistration, ThreeExactPointsGiveTheTransformBack) {
    const Similarity truth = knownRegistration();
    const std::vector<glm::dvec3> device{{0.0, 0.0, 0.0}, {0.05, 0.0, 0.0}, {0.0, 0.04, 0.01}};
    std::vector<glm::dvec3> space;
    for (const auto& p : device) space.push_back(truth.apply(p));
    const StylusRegistration r = registerStylus(device, space);
    EXPECT_LT(r.rmsM, 1e-9);
    EXPECT_NEAR(r.deviceToSpace.scale, truth.scale, 1e-9);
    for (const glm::dvec3 probe : {glm::dvec3(0.02, -0.03, 0.05), glm::dvec3(-0.1, 0.2, 0.0)})
        EXPECT_LT(glm::length(r.deviceToSpace.apply(probe) - truth.apply(probe)), 1e-9);
}

TEST(StylusRegistration, NoisyTouchesFitWithinTheNoise) {
    const Similarity truth = knownRegistration();
    std::mt19937 rng(7);
    std::normal_distribution<double> noise(0.0, 0.001);  // 1 mm: a hand holding two tips together
    std::uniform_real_distribution<double> spot(-0.06, 0.06);
    std::vector<glm::dvec3> device, space;
    for (int i = 0; i < 8; ++i) {
        device.emplace_back(spot(rng), spot(rng), spot(rng));
        space.push_back(truth.apply(device.back()) + glm::dvec3(noise(rng), noise(rng), noise(rng)));
    }
    const StylusRegistration r = registerStylus(device, space);
    EXPECT_LT(r.rmsM, 0.003);
    EXPECT_LT(glm::length(r.deviceToSpace.apply(glm::dvec3(0.0)) - truth.apply(glm::dvec3(0.0))), 0.003);
}

TEST(StylusRegistration, RefusesTooFewMismatchedOrCollinearPoints) {
    const std::vector<glm::dvec3> two{{0, 0, 0}, {1, 0, 0}};
    EXPECT_THROW(registerStylus(two, two), std::invalid_argument);
    const std::vector<glm::dvec3> three{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    EXPECT_THROW(registerStylus(three, two), std::invalid_argument);
    const std::vector<glm::dvec3> line{{0, 0, 0}, {0.1, 0, 0}, {0.2, 0, 0}, {0.3, 0, 0}};
    try {
        registerStylus(line, line);
        FAIL() << "collinear points were accepted";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("one line"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace kizamu::xr
