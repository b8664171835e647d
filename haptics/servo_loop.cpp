// SPDX-License-Identifier: Apache-2.0
/// @file servo_loop.cpp
/// @brief ServoTicker (one tick: device, client, force checks, schedule) and ServoLoop (the
/// servo thread on absolute deadlines, and the watchdog thread).
///
/// Why a watchdog *thread* (not a check on the device side): the Device interface has no
/// timeout of its own, a simulated device has none, and a stalled servo thread cannot check
/// anything itself; only another thread can act while it is not running. It sleeps between
/// checks (every limit / 4) on a condition variable, at a SCHED_FIFO priority one above the
/// servo thread's when granted, so a servo thread spinning under FIFO cannot starve it. It
/// reaches the device only through the ticker's try-only gate, so device calls never overlap.
#include "haptics/servo_loop.h"

#include "util/cpu_set.h"
#include "util/realtime.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <ctime>
#include <stdexcept>
#include <string>

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif
#if defined(__linux__)
#include <sys/prctl.h>
#endif

namespace kizamu::haptics {

namespace {

int64_t monotonicNs() noexcept {
    timespec ts{};
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return int64_t(ts.tv_sec) * 1'000'000'000 + int64_t(ts.tv_nsec);
}

/// Sleeps until `ns` on CLOCK_MONOTONIC (absolute, so a late wake-up never shifts the schedule).
void sleepUntilNs(int64_t ns) noexcept {
    timespec ts{};
    ts.tv_sec = time_t(ns / 1'000'000'000);
    ts.tv_nsec = long(ns % 1'000'000'000);
    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
    }
}

inline void cpuRelax() noexcept {
#if defined(__x86_64__) || defined(__i386__)
    _mm_pause();
#endif
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// ServoTicker

namespace {

int64_t periodOf(double rateHz) {
    if (!(rateHz > 0.0) || !std::isfinite(rateHz) || rateHz > 1e9) throw std::invalid_argument("servo rate must be positive");
    return int64_t(std::llround(1e9 / rateHz));
}

}  // namespace

ServoTicker::ServoTicker(Device& device, ServoClient& client, double rateHz)
    : mDevice(device), mClient(client), mPeriodNs(periodOf(rateHz)), mMaxForce(device.spec().maxForce) {
    if (!(mMaxForce > 0.0) || !std::isfinite(mMaxForce)) mMaxForce = 0.0;  // no force at all
}

void ServoTicker::begin(int64_t firstDeadlineNs) noexcept {
    mDeadlineNs = firstDeadlineNs;
    mPrevTickNs = -1;
    mNeedRestart = true;
    mHeartbeatNs.store(firstDeadlineNs - mPeriodNs, std::memory_order_release);
}

bool ServoTicker::tryGate() noexcept {
    bool expected = false;
    return mGate.compare_exchange_strong(expected, true, std::memory_order_acquire, std::memory_order_relaxed);
}

glm::dvec3 ServoTicker::checked(const glm::dvec3& f) noexcept {
    if (!std::isfinite(f.x) || !std::isfinite(f.y) || !std::isfinite(f.z)) {
        mStats.countNonFinite();
        mStats.events().record(ServoEventKind::NonFiniteForce, mHeartbeatNs.load(std::memory_order_relaxed));
        return glm::dvec3(0.0);
    }
    const double a = std::max({std::abs(f.x), std::abs(f.y), std::abs(f.z)});
    if (a == 0.0) return f;
    const double length = a * glm::length(f / a);  // no overflow for huge finite components
    if (length <= mMaxForce) return f;
    mStats.countClamped();
    if (mMaxForce == 0.0) return glm::dvec3(0.0);
    glm::dvec3 out = (f / a) * (mMaxForce / (length / a));
    if (glm::length(out) > mMaxForce) out *= std::nextafter(1.0, 0.0);  // the last ulp
    return out;
}

int64_t ServoTicker::step(int64_t nowNs) noexcept {
    mHeartbeatNs.store(nowNs, std::memory_order_release);
    const int64_t errorNs = nowNs - mDeadlineNs;
    const bool missed = errorNs > mPeriodNs;
    double dt = double(mPeriodNs) * 1e-9;
    if (mPrevTickNs >= 0 && nowNs > mPrevTickNs) dt = double(std::min(nowNs - mPrevTickNs, 2 * mPeriodNs)) * 1e-9;
    mPrevTickNs = nowNs;

    // A trip since the last tick: the force was zeroed behind the client's back.
    const uint64_t trips = mTrips.load(std::memory_order_acquire);
    if (trips != mSeenTrips) {
        mSeenTrips = trips;
        mNeedRestart = true;
        mStats.events().record(ServoEventKind::WatchdogRestart, nowNs);
    }
    if (missed) mStats.events().record(ServoEventKind::MissedDeadline, nowNs, errorNs);

    int64_t forceNs = -1;
    glm::dvec3 force(0.0);
    if (!tryGate()) {  // the watchdog is writing zero this instant: leave the device to it
        mStats.countGateBusy();
        mNeedRestart = true;
    } else {
        DeviceState state;
        const bool answered = mDevice.read(state) && state.connected;
        releaseGate();
        state.timeNs = nowNs;
        if (!answered) {
            if (mConnected.load(std::memory_order_relaxed)) {
                mConnected.store(false, std::memory_order_relaxed);
                mStats.countDisconnect();
                mStats.events().record(ServoEventKind::Disconnected, nowNs);
            }
            mStats.countDisconnectedTick();
            mNeedRestart = true;
        } else {
            if (!mConnected.load(std::memory_order_relaxed)) mStats.events().record(ServoEventKind::Reconnected, nowNs);
            mConnected.store(true, std::memory_order_relaxed);
            if (mNeedRestart) {
                mClient.restart(state);
                mNeedRestart = false;
                dt = double(mPeriodNs) * 1e-9;
            }
            glm::dvec3 computed(0.0);
            const int64_t t0 = monotonicNs();
            mClient.tick(state, dt, computed);
            forceNs = monotonicNs() - t0;
            force = checked(computed);
        }
        if (tryGate()) {
            if (mTrips.load(std::memory_order_acquire) != mSeenTrips) {  // tripped during this tick
                force = glm::dvec3(0.0);
                mNeedRestart = true;
            }
            mDevice.write(force);
            mLastForce = force;
            releaseGate();
        } else {
            mStats.countGateBusy();
            mNeedRestart = true;
        }
    }

    mStats.recordTick(nowNs, errorNs, forceNs, missed);
    // A missed deadline re-anchors the schedule instead of catching up with a burst of ticks.
    mDeadlineNs = missed ? nowNs + mPeriodNs : mDeadlineNs + mPeriodNs;
    return mDeadlineNs;
}

bool ServoTicker::zeroForce() noexcept {
    if (!tryGate()) return false;
    mDevice.write(glm::dvec3(0.0));
    mLastForce = glm::dvec3(0.0);
    releaseGate();
    return true;
}

bool ServoTicker::zeroForceFromWatchdog() noexcept {
    if (!tryGate()) return false;
    mDevice.write(glm::dvec3(0.0));
    mTrips.store(mTrips.load(std::memory_order_relaxed) + 1, std::memory_order_relaxed);
    releaseGate();  // release: the servo side's acquire of the gate (or of mTrips) sees the trip
    mStats.countWatchdogTrip();
    return true;
}

// ---------------------------------------------------------------------------------------------
// ServoLoop

namespace {

ServoSettings validated(ServoSettings s) {
    if (!(s.rateHz >= 1.0 && s.rateHz <= 10'000.0)) throw std::invalid_argument("servo rate must be 1..10000 Hz");
    if (s.realtimePriority < 0 || s.realtimePriority > 99)
        throw std::invalid_argument("servo real-time priority must be 0 (none) .. 99");
    if (s.cpu < -1) throw std::invalid_argument("servo CPU must be -1 (none) or a CPU number");
    const double periodUs = 1e6 / s.rateHz;
    if (s.spinUs < 0 || s.spinUs > 100) throw std::invalid_argument("servo spin must be 0..100 us");
    if (double(s.watchdogUs) < 2.0 * periodUs || s.watchdogUs > 10'000'000)
        throw std::invalid_argument("servo watchdog limit must be at least two periods and at most 10 s");
    return s;
}

}  // namespace

ServoLoop::ServoLoop(Device& device, ServoClient& client, ServoSettings settings)
    : mSettings(validated(settings)), mTicker(device, client, mSettings.rateHz) {}

ServoLoop::~ServoLoop() { stop(); }

int64_t ServoLoop::clockNs() noexcept { return monotonicNs(); }

ServoStartReport ServoLoop::start() {
    if (mRunning.load() || mServo.joinable()) throw std::logic_error("ServoLoop::start: already running");
    ServoStartReport report;
    std::string why;
    if (mSettings.lockMemory) {
        report.memoryLocked = util::lockMemory(&why);
        if (!report.memoryLocked) report.warnings.push_back(why);
    }
    if (mSettings.holdCpuDmaLatency) {
        mDmaLatency = std::make_unique<util::CpuDmaLatency>();
        report.dmaLatency = mDmaLatency->active();
        if (!report.dmaLatency) report.warnings.push_back(mDmaLatency->reason());
    }
    mTicker.stats().clear();
    mServoReady = false;
    mStopWatchdog = false;
    mRunning.store(true, std::memory_order_release);
    try {
        mServo = std::thread([this, &report] { servoMain(report); });
    } catch (...) {
        mRunning.store(false);
        mDmaLatency.reset();
        throw;
    }
    {
        std::unique_lock lock(mMutex);
        mWake.wait(lock, [this] { return mServoReady; });
    }
    try {
        mWatchdog = std::thread([this] { watchdogMain(); });
    } catch (...) {
        stop();
        throw;
    }
    return report;
}

void ServoLoop::stop() noexcept {
    mRunning.store(false, std::memory_order_release);
    if (mServo.joinable()) mServo.join();
    {
        std::lock_guard lock(mMutex);
        mStopWatchdog = true;
    }
    mWake.notify_all();
    if (mWatchdog.joinable()) mWatchdog.join();
    mTicker.zeroForce();  // both threads are gone: the gate is free
    mDmaLatency.reset();
}

void ServoLoop::servoMain(ServoStartReport& report) noexcept {
    // Start-up requests: these may allocate (reasons), before the first tick only.
    try {
        std::string why;
        if (mSettings.cpu >= 0) {
            report.pinned = util::pinCurrentThread(mSettings.cpu, &why);
            if (!report.pinned) report.warnings.push_back("servo thread not pinned: " + why);
        }
        if (mSettings.realtimePriority > 0) {
            report.realtime = util::setRealtimePriority(mSettings.realtimePriority, &why);
            if (!report.realtime) report.warnings.push_back("servo thread: " + why);
        }
    } catch (...) {  // out of memory for a reason string: run without it
    }
#if defined(__linux__)
    // A SCHED_OTHER thread's timed sleeps are stretched by its timer slack (50 µs by default);
    // 1 ns asks for none (SCHED_FIFO threads have none anyway).
    prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL);
#endif
    const int64_t period = mTicker.periodNs();
    int64_t deadline = 0;
    {
        std::lock_guard lock(mMutex);
        deadline = monotonicNs() + period;
        mTicker.begin(deadline);
        mServoReady = true;
    }
    mWake.notify_all();  // `report` belongs to start() again from here on
    const int64_t spinNs = std::min(int64_t(mSettings.spinUs) * 1000, period / 4);
    while (mRunning.load(std::memory_order_relaxed)) {
        sleepUntilNs(deadline - spinNs);
        int64_t now = monotonicNs();
        while (now < deadline) {  // at most spinNs: the sleep ended at deadline - spinNs or later
            cpuRelax();
            now = monotonicNs();
        }
        deadline = mTicker.step(now);
    }
    mTicker.zeroForce();  // if the watchdog holds the gate, it is writing zero itself
}

void ServoLoop::watchdogMain() noexcept {
    if (mSettings.realtimePriority > 0) util::setRealtimePriority(std::min(mSettings.realtimePriority + 1, 99), nullptr);
    const int64_t limitNs = mSettings.watchdogUs * 1000;
    const auto checkEvery = std::chrono::nanoseconds(std::max<int64_t>(limitNs / 4, 100'000));
    int64_t trippedOn = -1;  // the heartbeat the last trip was for: one trip per stall
    std::unique_lock lock(mMutex);
    while (!mStopWatchdog) {
        mWake.wait_for(lock, checkEvery);
        if (mStopWatchdog) break;
        const int64_t beat = mTicker.heartbeatNs();
        if (beat == 0 || beat == trippedOn) continue;
        if (monotonicNs() - beat > limitNs && mTicker.zeroForceFromWatchdog()) trippedOn = beat;
    }
}

}  // namespace kizamu::haptics
