// SPDX-License-Identifier: Apache-2.0
/// @file live_hand.cpp
/// @brief LiveHand: targets into straight one-frame moves.
#include "sim/live_hand.h"

#include <algorithm>

namespace kizamu::sim {

LiveHand::LiveHand(const glm::dvec3& position) : mShared(Segment{position, position, 0, 0, 0}) {
    mWriter.from = mWriter.to = position;
}

void LiveHand::set(const glm::dvec3& position, uint32_t buttons, int64_t timeNs) noexcept {
    Segment s;
    // From where the hand is at `timeNs` on the last segment (its end unless a target came
    // sooner than a frame after the one before), to the new target.
    const double u = mWriter.spanNs > 0 ? std::clamp(double(timeNs - mWriter.startNs) / double(mWriter.spanNs), 0.0, 1.0) : 1.0;
    s.from = mWriter.from + (mWriter.to - mWriter.from) * u;
    s.to = position;
    s.startNs = timeNs;
    s.spanNs = mLastSetNs < 0 ? 0 : std::clamp(timeNs - mLastSetNs, int64_t(0), kMaxMoveNs);
    s.buttons = buttons;
    mLastSetNs = timeNs;
    mWriter = s;
    mShared.write(s);
}

HandPose LiveHand::at(int64_t timeNs) noexcept {
    mShared.take();
    const Segment& s = mShared.read();
    HandPose pose;
    pose.buttons = s.buttons;
    if (s.spanNs <= 0 || timeNs >= s.startNs + s.spanNs) {
        pose.position = s.to;
        return pose;
    }
    if (timeNs <= s.startNs) {
        pose.position = s.from;
        return pose;
    }
    const double span = double(s.spanNs) * 1e-9;
    const double u = double(timeNs - s.startNs) / double(s.spanNs);
    pose.position = s.from + (s.to - s.from) * u;
    pose.velocity = (s.to - s.from) / span;
    return pose;
}

}  // namespace kizamu::sim
