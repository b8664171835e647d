// SPDX-License-Identifier: Apache-2.0
/// @file realtime_stylus.cpp
/// @brief RealtimeStylus: the simulated stylus advanced to the servo clock on each read.
#include "sim/realtime_stylus.h"

#include <algorithm>

namespace kizamu::sim {

RealtimeStylus::RealtimeStylus(SimulatedStylus& stylus, int64_t (*clock)() noexcept) : mStylus(stylus), mClock(clock) {}

bool RealtimeStylus::read(haptics::DeviceState& out) noexcept {
    const int64_t now = mClock();
    if (mStartNs < 0) mStartNs = now - int64_t(mStylus.time() * 1e9);
    double behind = double(now - mStartNs - mSkippedNs) * 1e-9 - mStylus.time();
    if (behind > kMaxCatchUp) {
        mSkippedNs += int64_t((behind - kMaxStep) * 1e9);
        behind = kMaxStep;
    }
    // Stylus time t is servo time mStartNs + mSkippedNs + t: where the live hand's targets are.
    if (mLive) mStylus.setLiveHand(mLive, mStartNs + mSkippedNs);
    while (behind > 1e-9) {
        const double step = std::min(behind, kMaxStep);
        mStylus.step(step);
        behind -= step;
    }
    return mStylus.read(out);
}

}  // namespace kizamu::sim
