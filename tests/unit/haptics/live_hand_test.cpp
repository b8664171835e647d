// SPDX-License-Identifier: Apache-2.0
// The live hand (the mouse driving the simulated stylus) and the stylus on the wall clock: targets
// become straight one-frame moves, buttons arrive with their target, a pause does not stretch a
// move, and a RealtimeStylus on a test clock follows the live targets.
#include "sim/live_hand.h"
#include "sim/realtime_stylus.h"
#include "sim/simulated_stylus.h"
#include "util/triple_buffer.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <algorithm>

namespace kizamu {
namespace {

constexpr int64_t kMs = 1'000'000;

TEST(TripleBuffer, TheReaderTakesTheNewestWholeValueOnce) {
    util::TripleBuffer<int> b(7);
    EXPECT_FALSE(b.take());
    EXPECT_EQ(b.read(), 7);
    b.write(1);
    b.write(2);
    EXPECT_TRUE(b.take());
    EXPECT_EQ(b.read(), 2) << "the newest, not the first";
    EXPECT_FALSE(b.take());
    EXPECT_EQ(b.read(), 2);
    for (int i = 10; i < 20; ++i) b.write(i);
    EXPECT_TRUE(b.take());
    EXPECT_EQ(b.read(), 19);
}

TEST(LiveHand, TargetsBecomeOneFrameMovesWithTheirButtons) {
    sim::LiveHand hand(glm::dvec3(0.0));
    EXPECT_EQ(hand.at(0).position, glm::dvec3(0.0));
    hand.set({0.0, 0.0, 0.0}, 0, 100 * kMs);
    hand.set({0.016, 0.0, 0.0}, 1, 116 * kMs);  // 16 mm in a 16 ms frame: 1 m/s
    sim::HandPose p = hand.at(116 * kMs);
    EXPECT_NEAR(p.position.x, 0.0, 1e-12) << "the move starts when the target arrives";
    EXPECT_EQ(p.buttons, 1u);
    p = hand.at(124 * kMs);
    EXPECT_NEAR(p.position.x, 0.008, 1e-9);
    EXPECT_NEAR(p.velocity.x, 1.0, 1e-9);
    p = hand.at(140 * kMs);
    EXPECT_NEAR(p.position.x, 0.016, 1e-12);
    EXPECT_EQ(p.velocity, glm::dvec3(0.0)) << "at rest once there";
    // A target half a frame into a move starts from where the hand is then.
    hand.set({0.016, 0.0, 0.0}, 0, 134 * kMs);
    hand.set({0.016, 0.016, 0.0}, 0, 150 * kMs);
    hand.set({0.016, 0.032, 0.0}, 0, 166 * kMs);
    hand.set({0.0, 0.032, 0.0}, 0, 174 * kMs);
    p = hand.at(174 * kMs);
    EXPECT_NEAR(p.position.y, 0.024, 1e-9);
    EXPECT_NEAR(p.position.x, 0.016, 1e-9);
    // After a pause the move takes at most kMaxMoveNs.
    hand.set({0.0, 0.0, 0.0}, 0, 5000 * kMs);
    EXPECT_NEAR(hand.at(5000 * kMs + sim::LiveHand::kMaxMoveNs).position.y, 0.0, 1e-12);
}

int64_t gClockNs = 0;
int64_t testClock() noexcept { return gClockNs; }

TEST(LiveHand, DrivesTheRealtimeStylusOnTheServoClock) {
    sim::SimulatedStylus stylus(sim::Hand{});
    sim::LiveHand hand(glm::dvec3(0.0));
    sim::RealtimeStylus device(stylus, &testClock);
    device.setLiveHand(&hand);
    gClockNs = 1'000 * kMs;
    haptics::DeviceState s;
    device.read(s);  // starts the stylus at this instant
    // The UI moves the target 2 cm along x at 60 Hz over 0.5 s; the servo reads at 1 kHz.
    int64_t nextFrame = gClockNs;
    for (int tick = 0; tick < 1500; ++tick) {
        gClockNs += kMs;
        if (gClockNs >= nextFrame && tick < 500) {
            hand.set({0.02 * std::min(1.0, tick / 450.0), 0.0, 0.0}, tick < 400 ? 1u : 0u, gClockNs);
            nextFrame += 16'666'667;
        }
        device.read(s);
        if (tick == 300) {
            EXPECT_EQ(s.buttons, 1u);
        }
    }
    EXPECT_NEAR(s.position.x, 0.02, 5e-4) << "the stylus followed the live hand";
    EXPECT_EQ(s.buttons, 0u);
    EXPECT_NEAR(stylus.time(), 1.5, 1e-6);
}

}  // namespace
}  // namespace kizamu
