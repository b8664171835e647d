// SPDX-License-Identifier: Apache-2.0
// The simulated stylus (sim/simulated_stylus.h): its spec, following the hand in free space,
// determinism (bit for bit), its energy bookkeeping balancing the kinetic energy, and what
// read() reports.
#include "sim/simulated_stylus.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace kizamu {
namespace {

sim::Hand moveHand() {
    sim::Hand h;
    h.add(0.0, {0.0, 0.0, 0.0});
    h.add(0.1, {0.0, 0.0, 0.0}, 1u);
    h.add(0.6, {0.02, -0.01, 0.005}, 1u);
    h.add(0.7, {0.02, -0.01, 0.005}, 0u);
    return h;
}

TEST(SimulatedStylus, SpecIsAFalconClassDeviceWithItsPassivityBound) {
    const sim::SimulatedStylus s{sim::Hand{}};
    EXPECT_EQ(s.spec().name, "sim");
    EXPECT_DOUBLE_EQ(s.spec().maxForce, 9.0);
    EXPECT_DOUBLE_EQ(s.spec().damping, 2.0);
    EXPECT_DOUBLE_EQ(s.spec().maxStiffness, 4000.0);  // 2 b / T at 1 kHz
    EXPECT_DOUBLE_EQ(s.spec().workspaceMax.x - s.spec().workspaceMin.x, 0.1);
    EXPECT_FALSE(s.spec().orientation);
}

TEST(SimulatedStylus, FollowsTheHandInFreeSpaceAndReportsItsButtons) {
    sim::SimulatedStylus s(moveHand());
    haptics::DeviceState st;
    double worstMoving = 0.0;
    for (int i = 0; i < 1200; ++i) {
        ASSERT_TRUE(s.read(st));
        EXPECT_EQ(st.timeNs, int64_t(i) * 1'000'000);
        EXPECT_EQ(st.buttons, (i >= 100 && i < 700) ? 1u : 0u) << i;
        if (i > 150 && i < 600) worstMoving = std::max(worstMoving, glm::length(st.position - s.hand().at(s.time()).position));
        s.write(glm::dvec3(0.0));
        s.step(1e-3);
    }
    // A 500 N/m hand moving 4.6 cm/s drags the 0.1 kg mass (b + B_h = 7 N·s/m) behind by about
    // v (b + B_h) / K_h = 0.6 mm; at rest it catches up.
    EXPECT_LT(worstMoving, 0.001);
    EXPECT_LT(glm::length(s.position() - glm::dvec3(0.02, -0.01, 0.005)), 1e-5);
    EXPECT_LT(glm::length(s.velocity()), 1e-4);
}

TEST(SimulatedStylus, IsDeterministicAndItsEnergyBalances) {
    auto run = [](std::vector<glm::dvec3>& positions) {
        sim::SimulatedStylus s(moveHand());
        for (int i = 0; i < 800; ++i) {
            s.write(glm::dvec3(std::sin(0.05 * i), 0.5, -0.25 * std::cos(0.02 * i)));  // some rendered force
            s.step(1e-3);
            positions.push_back(s.position());
        }
        // Kinetic energy = work of the hand + work of the rendered force - damping loss.
        const sim::StylusEnergy& e = s.energy();
        const double kinetic = 0.5 * s.settings().mass * glm::dot(s.velocity(), s.velocity());
        EXPECT_NEAR(kinetic, e.hand + e.rendered - e.damped, 1e-12 + 1e-9 * (std::abs(e.hand) + std::abs(e.rendered)));
        EXPECT_GT(e.damped, 0.0);
        EXPECT_DOUBLE_EQ(e.dampedUnderForce, e.damped) << "a force acted in every step";
    };
    std::vector<glm::dvec3> a, b;
    run(a);
    run(b);
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i) ASSERT_EQ(a[i], b[i]) << "step " << i;
    // A non-finite force is held as zero.
    sim::SimulatedStylus s(moveHand());
    s.write(glm::dvec3(std::nan(""), 0.0, 0.0));
    EXPECT_EQ(s.force(), glm::dvec3(0.0));
}

}  // namespace
}  // namespace kizamu
