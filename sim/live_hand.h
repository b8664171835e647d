// SPDX-License-Identifier: Apache-2.0
/// @file live_hand.h
/// @brief A hand the user moves live (the mouse, through interact::MouseTool): the UI thread
/// sets a target each frame, the servo thread reads a smooth hand pose from it for the
/// simulated stylus (simulated_stylus.h), with no lock between them (util::TripleBuffer).
///
/// Targets arrive at the frame rate (about 60 Hz) and the stylus integrates at 10 kHz: a hand
/// that jumped at each frame would ring the hand spring. So the hand moves from the previous
/// target to the newest one in a straight line over one frame interval, starting when the newest
/// arrived (one frame of latency, the same a screen adds), and rests there after. Buttons change
/// when the target carrying them arrives. Times are the servo clock (ns; ServoLoop::clockNs).
/// Threading: set() from one thread (the UI), at() from one other (the servo thread); both
/// wait-free, no allocation.
#pragma once

#include "sim/hand.h"
#include "util/triple_buffer.h"

#include <glm/vec3.hpp>

#include <cstdint>

namespace kizamu::sim {

class LiveHand {
public:
    /// Starts at rest at `position`.
    explicit LiveHand(const glm::dvec3& position = glm::dvec3(0.0));

    /// UI thread: the hand should be at `position` (m, device frame) holding `buttons`, as of
    /// `timeNs` (servo clock).
    void set(const glm::dvec3& position, uint32_t buttons, int64_t timeNs) noexcept;
    /// Servo thread: the hand at `timeNs` (servo clock).
    HandPose at(int64_t timeNs) noexcept;

    /// The longest a move between two targets is stretched over (a target after a pause moves
    /// the hand in this time, not over the pause): 0.1 s.
    static constexpr int64_t kMaxMoveNs = 100'000'000;

private:
    struct Segment {
        glm::dvec3 from{0.0}, to{0.0};
        int64_t startNs = 0;  ///< when the move to `to` begins
        int64_t spanNs = 0;   ///< how long it takes (0: already there)
        uint32_t buttons = 0;
    };
    util::TripleBuffer<Segment> mShared;
    Segment mWriter;           ///< the UI thread's last segment (its `to` is the next one's `from`)
    int64_t mLastSetNs = -1;   ///< UI thread
};

}  // namespace kizamu::sim
