// SPDX-License-Identifier: Apache-2.0
/// @file realtime_stylus.h
/// @brief The simulated stylus on the wall clock: a Device whose read() first advances the
/// stylus to the servo clock's time, so the real-time servo loop (servo_loop.h) can drive it
/// like hardware (`kizamu live --device sim --rate HZ`, `kizamu bench haptics`).
///
/// The rendered force is held from one write() to the next read(), the zero-order hold a real
/// device applies. The stylus advances in steps of at most kMaxStep (1 ms), so a late tick
/// integrates the time it missed with the force held; of a gap longer than kMaxCatchUp (1 s: a
/// debugger, a suspended process) only one step is integrated: the simulation pauses for it.
/// Threading: the Device contract (servo thread; write() also from the watchdog, never at once).
/// read() and write() allocate nothing and take no lock.
#pragma once

#include "sim/simulated_stylus.h"

#include <cstdint>

namespace kizamu::sim {

class RealtimeStylus final : public haptics::Device {
public:
    /// `clock` returns the servo clock in ns (ServoLoop::clockNs in the application; a test's
    /// virtual clock). The stylus starts at the first read().
    RealtimeStylus(SimulatedStylus& stylus, int64_t (*clock)() noexcept);

    const haptics::DeviceSpec& spec() const noexcept override { return mStylus.spec(); }
    bool read(haptics::DeviceState& out) noexcept override;
    void write(const glm::dvec3& force) noexcept override { mStylus.write(force); }

    static constexpr double kMaxStep = 1e-3;    ///< s
    static constexpr double kMaxCatchUp = 1.0;  ///< s

    /// Drives the stylus with `live` (the mouse), on the servo clock. Before the loop starts.
    void setLiveHand(LiveHand* live) noexcept { mLive = live; }

    /// Whether the hand has finished its script (time past its last waypoint). Servo thread.
    bool handFinished() const noexcept { return mStylus.time() >= mStylus.hand().duration(); }

private:
    SimulatedStylus& mStylus;
    int64_t (*mClock)() noexcept;
    int64_t mStartNs = -1;
    int64_t mSkippedNs = 0;  ///< wall time not integrated (gaps beyond kMaxCatchUp)
    LiveHand* mLive = nullptr;
};

}  // namespace kizamu::sim
