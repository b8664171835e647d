// SPDX-License-Identifier: Apache-2.0
/// @file servo_loop.h
/// @brief The haptic servo thread: read the device, compute the force, check it, write it, on
/// an absolute-deadline clock at 1 kHz (up to 10 kHz), with a watchdog that zeroes the force of
/// a stalled loop.
///
/// Where it sits (design brief, "Threads"): device --state--> ServoClient::tick (the proxy
/// renderer, proxy_renderer.h, reading the engine's published snapshot) --force--> device.
/// Threads: ServoLoop owns two: the servo thread (SCHED_FIFO when granted) runs a ServoTicker
/// once per period; the watchdog thread wakes every watchdog limit / 4 and zeroes the force
/// when the servo thread has not finished a tick for longer than the limit. Tests drive a
/// ServoTicker in lock-step on a virtual clock with no thread at all.
///
/// Backend checklist:
///  [X] absolute deadlines (clock_nanosleep TIMER_ABSTIME, CLOCK_MONOTONIC); a late tick is not
///      caught up: more than one period late counts as missed and re-anchors the schedule
///  [X] a bounded spin before each deadline (ServoSettings::spinUs, 50 µs, at most period / 4)
///  [X] SCHED_FIFO, pinning, mlockall, /dev/cpu_dma_latency: each asked for, each refusal a
///      warning in ServoStartReport
///  [X] non-finite force -> zero, |force| > maxForce -> scaled to maxForce, both counted
///  [X] device not answering -> force zero, loop keeps ticking, resumes when it answers again
///  [X] watchdog thread; force zero on stop(), on destruction and when the thread exits
///  [X] statistics in preallocated histograms (servo_stats.h), readable without locks
///  [X] a preallocated event log ring (time-stamped missed deadlines, disconnects, reconnects,
///      restarts after a trip, non-finite forces: ServoStats::events(), servo_stats.h)
///
/// Changes (breaking):
///  2026-12-06 first version (issue 32).
#pragma once

#include "haptics/device.h"
#include "haptics/servo_stats.h"

#include <glm/vec3.hpp>

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace kizamu::util {
class CpuDmaLatency;
}

namespace kizamu::haptics {

/// The force computation the servo thread calls once per tick. Requirements:
///  - tick() and restart() run on the servo thread only (or the lock-step driver's thread);
///  - they are noexcept, never allocate, never take a lock another thread may hold, never do
///    file or log I/O, and return within a small fraction of the period (budget: 5 µs p99.9);
///  - they read the clay through a SnapshotStore::Reader and adf::GuardedAccessor (never the
///    tree being edited);
///  - the force may be anything: the loop replaces non-finite values by zero and clamps the
///    magnitude to DeviceSpec::maxForce, counting both.
/// Owned by the application; outlives the ServoLoop or ServoTicker that calls it.
class ServoClient {
public:
    virtual ~ServoClient() = default;
    /// Computes the force (N, device frame) for `state`; `dt` (s) is the time since the previous
    /// tick, at most two periods (the period on the first tick and after a restart).
    virtual void tick(const DeviceState& state, double dt, glm::dvec3& force) noexcept = 0;
    /// Called before the first tick, and before the first tick after the loop forced the force
    /// to zero (the device stopped answering, the watchdog tripped): the renderer re-seats its
    /// proxy at `state` and ramps force on again instead of jumping to where it was.
    virtual void restart(const DeviceState& /*state*/) noexcept {}
};

/// What a ServoLoop asks for. Validated by the ServoLoop constructor.
struct ServoSettings {
    double rateHz = 1000.0;       ///< ticks per second, 1..10000
    int realtimePriority = 80;    ///< SCHED_FIFO priority of the servo thread; 0: do not ask
    int cpu = -1;                 ///< pin the servo thread to this CPU; -1: do not pin
    /// Bounded busy-wait before each deadline (µs, 0..100; the loop spins at most a quarter of
    /// the period, so 50 becomes 25 at 10 kHz): the thread sleeps until deadline - spin, then
    /// spins to the deadline, which hides the timer's wake-up latency (about 40 µs median on the
    /// project's VMs) at the cost of spin / period of a core (5 % at 1 kHz, 20 % at 4 kHz).
    /// Measured: docs/decisions/0031-servo-loop.md.
    int spinUs = 50;
    /// The watchdog zeroes the force when no tick has started for this long (µs, at least two
    /// periods, at most 10 s): above the longest stall measured on the project's machines, so it
    /// trips on a broken loop, not on scheduling noise (docs/decisions/0031-servo-loop.md).
    int64_t watchdogUs = 20'000;
    bool lockMemory = false;       ///< mlockall (process-wide, kept after stop)
    bool holdCpuDmaLatency = true;  ///< hold /dev/cpu_dma_latency at 0 while running
};

/// What start() got. Each refused request is a warning, never a failure.
struct ServoStartReport {
    bool realtime = false;      ///< SCHED_FIFO granted to the servo thread
    bool pinned = false;        ///< the servo thread runs on ServoSettings::cpu
    bool memoryLocked = false;  ///< mlockall succeeded
    bool dmaLatency = false;    ///< /dev/cpu_dma_latency held at 0
    std::vector<std::string> warnings;  ///< why each request that was asked for was refused
};

/// One servo tick's work, without a thread or a clock of its own: the caller says when each tick
/// runs. ServoLoop's thread drives one with CLOCK_MONOTONIC; tests drive one in lock-step on a
/// virtual clock (deterministic: forces, counts and restarts depend only on the times given and
/// on what the device and client return).
///
/// Device access goes through a gate (an atomic flag, try-acquire only, never waited on) shared
/// with zeroForceFromWatchdog(): the servo side skips the device for one tick when the watchdog
/// holds it (counted as gateBusy), and the watchdog retries at its next check when the servo side
/// holds it. So Device::read/write never run on two threads at once, and the gate's
/// acquire/release order them: a device's write() may run on the watchdog's thread (a zero
/// force), never at the same time as another of its calls, so a device needs no lock of its own.
/// Owned by ServoLoop (or a test); one driving thread, plus zeroForceFromWatchdog() from one other.
class ServoTicker {
public:
    /// @param rateHz ticks per second (> 0). Device and client must outlive the ticker.
    ServoTicker(Device& device, ServoClient& client, double rateHz);
    ServoTicker(const ServoTicker&) = delete;
    ServoTicker& operator=(const ServoTicker&) = delete;

    /// Sets the first deadline (servo clock, ns) and forgets the previous tick. Driving thread.
    void begin(int64_t firstDeadlineNs) noexcept;
    /// The deadline of the next tick (ns).
    int64_t deadline() const noexcept { return mDeadlineNs; }
    int64_t periodNs() const noexcept { return mPeriodNs; }

    /// Runs one tick that starts at `nowNs` (servo clock, ns; normally >= deadline()): reads
    /// the device, calls the client (or restart() then tick()), checks the force, writes it,
    /// records statistics; then moves the deadline one period on, or, when this tick started
    /// more than one period late (a missed deadline), to nowNs + period. Returns the new deadline.
    /// Complexity: O(1) plus the client's tick. Threading: the driving thread. Memory: none.
    /// Never blocks (the gate is only tried).
    int64_t step(int64_t nowNs) noexcept;

    /// Writes zero force if the gate is free (the driving thread, when the loop ends).
    /// Returns whether it wrote.
    bool zeroForce() noexcept;
    /// The watchdog's call: writes zero and counts a trip when the gate is free, so the next
    /// tick restarts the client and the tick in progress (if any) writes zero, not what it
    /// computed. Returns whether it wrote (false: the servo side held the device; retry).
    /// Threading: one thread other than the driving one. Never blocks.
    bool zeroForceFromWatchdog() noexcept;

    /// Servo clock (ns) at which the latest tick started (begin(): one period before the first
    /// deadline; 0 before begin()). The watchdog trips when it is older than its limit, which
    /// also catches a tick stuck in the client. Any thread.
    int64_t heartbeatNs() const noexcept { return mHeartbeatNs.load(std::memory_order_acquire); }
    /// Whether the device answered on the latest tick. Any thread.
    bool connected() const noexcept { return mConnected.load(std::memory_order_relaxed); }
    /// The force written on the latest tick (N). Driving thread (tests).
    const glm::dvec3& lastForce() const noexcept { return mLastForce; }

    ServoStats& stats() noexcept { return mStats; }
    const ServoStats& stats() const noexcept { return mStats; }

private:
    bool tryGate() noexcept;
    void releaseGate() noexcept { mGate.store(false, std::memory_order_release); }
    /// Non-finite -> zero, above maxForce -> scaled down; counted.
    glm::dvec3 checked(const glm::dvec3& force) noexcept;

    Device& mDevice;
    ServoClient& mClient;
    int64_t mPeriodNs;
    double mMaxForce;
    int64_t mDeadlineNs = 0;
    int64_t mPrevTickNs = -1;  ///< start of the previous tick; -1: none since begin()
    bool mNeedRestart = true;
    uint64_t mSeenTrips = 0;   ///< watchdog trips this side has acted on
    glm::dvec3 mLastForce{0.0};
    std::atomic<bool> mGate{false};
    std::atomic<uint64_t> mTrips{0};  ///< written under the gate by the watchdog
    std::atomic<int64_t> mHeartbeatNs{0};
    std::atomic<bool> mConnected{true};  ///< so a device that never answers counts one disconnect
    ServoStats mStats;
};

/// The servo thread and its watchdog. Owned by the application (one per device); start() and
/// stop() from one controlling thread; stats() and the queries from any thread.
/// The servo thread never allocates, never takes a lock, never does I/O once it ticks (the
/// start-up requests before the first tick may).
class ServoLoop {
public:
    /// @throw std::invalid_argument for settings out of range (see ServoSettings).
    ServoLoop(Device& device, ServoClient& client, ServoSettings settings = {});
    /// stop(): the device's force is zero when it returns.
    ~ServoLoop();
    ServoLoop(const ServoLoop&) = delete;
    ServoLoop& operator=(const ServoLoop&) = delete;

    /// Starts the servo and watchdog threads and returns once the servo thread has made its
    /// requests (priority, pinning) and is about to tick; the first deadline is one period
    /// after that. Refusals are warnings in the report; the loop runs without them.
    /// @throw std::logic_error when already running; std::system_error when a thread cannot start.
    /// Complexity: thread start-up; mlockall when asked (proportional to mapped memory). Cold path.
    ServoStartReport start();
    /// Ends both threads (the servo thread within one period), then writes zero force.
    /// Idempotent. Controlling thread. Cold path.
    void stop() noexcept;
    bool running() const noexcept { return mRunning.load(std::memory_order_acquire); }

    const ServoSettings& settings() const noexcept { return mSettings; }
    const ServoStats& stats() const noexcept { return mTicker.stats(); }
    /// Whether the device answered on the latest tick. Any thread.
    bool connected() const noexcept { return mTicker.connected(); }

    /// CLOCK_MONOTONIC in ns: the servo clock (DeviceState::timeNs, ServoCounts' times).
    static int64_t clockNs() noexcept;

private:
    void servoMain(ServoStartReport& report) noexcept;
    void watchdogMain() noexcept;

    ServoSettings mSettings;
    ServoTicker mTicker;
    std::atomic<bool> mRunning{false};
    std::unique_ptr<util::CpuDmaLatency> mDmaLatency;  ///< held while running when asked for
    std::thread mServo, mWatchdog;
    std::mutex mMutex;  ///< start-up hand-shake and the watchdog's sleep; never on the servo thread's tick path
    std::condition_variable mWake;
    bool mServoReady = false;
    bool mStopWatchdog = false;
};

}  // namespace kizamu::haptics
