// SPDX-License-Identifier: Apache-2.0
/// @file servo_loop_test.cpp
/// @brief ServoTicker in lock-step on a virtual clock (force checks, disconnects, schedule) and
/// ServoLoop's real threads (stop, watchdog, a short 1 kHz run, no allocation while ticking).
#include "haptics/servo_loop.h"

#include "tests/util/counting_allocator.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace kizamu::haptics {
namespace {

using namespace std::chrono_literals;
constexpr int64_t kMs = 1'000'000;

/// Records every force written (lock-step tests: one thread).
class RecordingDevice : public Device {
public:
    RecordingDevice() {
        mSpec.name = "recording";
        mSpec.maxForce = 3.0;
    }
    const DeviceSpec& spec() const noexcept override { return mSpec; }
    bool read(DeviceState& out) noexcept override {
        ++reads;
        if (!answers) {
            out.connected = false;
            return false;
        }
        out = state;
        return true;
    }
    void write(const glm::dvec3& force) noexcept override { writes.push_back(force); }

    DeviceState state;
    bool answers = true;
    int reads = 0;
    std::vector<glm::dvec3> writes;

private:
    DeviceSpec mSpec;
};

/// Returns `force` every tick; counts ticks and restarts.
class ScriptedClient : public ServoClient {
public:
    void tick(const DeviceState&, double dt, glm::dvec3& out) noexcept override {
        ++ticks;
        lastDt = dt;
        out = force;
    }
    void restart(const DeviceState&) noexcept override { ++restarts; }
    glm::dvec3 force{0.0};
    int ticks = 0, restarts = 0;
    double lastDt = 0.0;
};

bool allFinite(const std::vector<glm::dvec3>& v) {
    for (const glm::dvec3& f : v)
        if (!std::isfinite(f.x) || !std::isfinite(f.y) || !std::isfinite(f.z)) return false;
    return true;
}

TEST(ServoTicker, NonFiniteForceNeverReachesTheDevice) {
    RecordingDevice dev;
    ScriptedClient client;
    ServoTicker t(dev, client, 1000.0);
    t.begin(kMs);
    const double inf = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
    const glm::dvec3 script[] = {{1, 0, 0}, {nan, 0, 0}, {0, inf, 0}, {0, 0, -inf}, {0.5, 0.5, 0}};
    for (const glm::dvec3& f : script) {
        client.force = f;
        t.step(t.deadline());
    }
    ASSERT_EQ(dev.writes.size(), 5u);
    EXPECT_TRUE(allFinite(dev.writes));
    EXPECT_EQ(dev.writes[0], glm::dvec3(1, 0, 0));
    for (int i = 1; i <= 3; ++i) EXPECT_EQ(dev.writes[std::size_t(i)], glm::dvec3(0.0)) << i;
    EXPECT_EQ(dev.writes[4], glm::dvec3(0.5, 0.5, 0));
    EXPECT_EQ(t.stats().counts().nonFinite, 3u);
    EXPECT_EQ(t.stats().events().recorded(), 3u) << "each non-finite force is logged";
    EXPECT_EQ(t.stats().counts().ticks, 5u);
    EXPECT_EQ(client.restarts, 1);  // before the first tick only
}

TEST(ServoTicker, ForceIsClampedToTheDevicesMaximum) {
    RecordingDevice dev;  // maxForce 3 N
    ScriptedClient client;
    ServoTicker t(dev, client, 1000.0);
    t.begin(0);
    const glm::dvec3 script[] = {{10, 0, 0}, {2, 2, 2}, {1e308, -1e308, 1e308}, {0, 3, 0}, {0, -2.9, 0}};
    for (const glm::dvec3& f : script) {
        client.force = f;
        t.step(t.deadline());
    }
    ASSERT_EQ(dev.writes.size(), 5u);
    EXPECT_TRUE(allFinite(dev.writes));
    for (const glm::dvec3& f : dev.writes) EXPECT_LE(glm::length(f), 3.0);
    EXPECT_NEAR(dev.writes[0].x, 3.0, 1e-12);
    EXPECT_NEAR(glm::length(dev.writes[1]), 3.0, 1e-12);
    EXPECT_NEAR(dev.writes[1].x, dev.writes[1].y, 1e-15);  // direction kept
    EXPECT_NEAR(glm::length(dev.writes[2]), 3.0, 1e-12);
    EXPECT_GT(dev.writes[2].x, 0.0);
    EXPECT_LT(dev.writes[2].y, 0.0);
    EXPECT_EQ(dev.writes[3], glm::dvec3(0, 3, 0));  // at the limit: untouched
    EXPECT_EQ(dev.writes[4], glm::dvec3(0, -2.9, 0));
    EXPECT_EQ(t.stats().counts().clamped, 3u);
    EXPECT_EQ(t.stats().counts().nonFinite, 0u);
}

TEST(ServoTicker, DisconnectMidContactZeroesForceAndResumes) {
    RecordingDevice dev;
    ScriptedClient client;
    client.force = {0, 0, 2};  // in contact
    ServoTicker t(dev, client, 1000.0);
    t.begin(0);
    for (int i = 0; i < 5; ++i) t.step(t.deadline());
    dev.answers = false;  // unplugged
    for (int i = 0; i < 3; ++i) t.step(t.deadline());
    EXPECT_FALSE(t.connected());
    dev.answers = true;  // plugged back
    for (int i = 0; i < 4; ++i) t.step(t.deadline());
    EXPECT_TRUE(t.connected());

    ASSERT_EQ(dev.writes.size(), 12u);  // every tick wrote
    for (int i = 0; i < 5; ++i) EXPECT_EQ(dev.writes[std::size_t(i)], glm::dvec3(0, 0, 2)) << i;
    for (int i = 5; i < 8; ++i) EXPECT_EQ(dev.writes[std::size_t(i)], glm::dvec3(0.0)) << i;
    for (int i = 8; i < 12; ++i) EXPECT_EQ(dev.writes[std::size_t(i)], glm::dvec3(0, 0, 2)) << i;
    const ServoCounts c = t.stats().counts();
    EXPECT_EQ(c.ticks, 12u);
    EXPECT_EQ(c.disconnects, 1u);
    EXPECT_EQ(c.disconnectedTicks, 3u);
    EXPECT_EQ(client.ticks, 9);     // the client is not asked while the device is away
    EXPECT_EQ(client.restarts, 2);  // at the start and on reconnection
    // The event log has both, time stamped.
    std::vector<haptics::ServoEvent> events;
    EXPECT_EQ(t.stats().events().read(0, events), 2u);
    ASSERT_EQ(events.size(), 2u);
    EXPECT_EQ(events[0].kind, haptics::ServoEventKind::Disconnected);
    EXPECT_EQ(events[0].timeNs, 5 * kMs);
    EXPECT_EQ(events[1].kind, haptics::ServoEventKind::Reconnected);
    EXPECT_EQ(events[1].timeNs, 8 * kMs);
}

TEST(ServoTicker, DeviceThatReportsDisconnectedCountsAsAway) {
    RecordingDevice dev;
    dev.state.connected = false;  // read() true but the state says it is gone
    ScriptedClient client;
    client.force = {1, 0, 0};
    ServoTicker t(dev, client, 1000.0);
    t.begin(0);
    t.step(0);
    ASSERT_EQ(dev.writes.size(), 1u);
    EXPECT_EQ(dev.writes[0], glm::dvec3(0.0));
    EXPECT_EQ(t.stats().counts().disconnects, 1u);
    EXPECT_EQ(client.ticks, 0);
}

TEST(ServoTicker, MissedDeadlineReanchorsInsteadOfBursting) {
    RecordingDevice dev;
    ScriptedClient client;
    ServoTicker t(dev, client, 1000.0);
    t.begin(10 * kMs);
    EXPECT_EQ(t.step(10 * kMs + 200'000), 11 * kMs);  // late by 0.2 ms: schedule kept
    EXPECT_NEAR(client.lastDt, 1e-3, 1e-12);             // first tick: the period
    EXPECT_EQ(t.step(11 * kMs + 900'000), 12 * kMs);   // late by 0.9 ms: still kept
    EXPECT_NEAR(client.lastDt, 1.7e-3, 1e-12);
    const int64_t late = 12 * kMs + 3'500'000;         // 3.5 ms late: missed
    EXPECT_EQ(t.step(late), late + kMs);                // re-anchored, no catch-up burst
    EXPECT_NEAR(client.lastDt, 2e-3, 1e-12);            // dt is capped at two periods
    EXPECT_EQ(t.step(late + kMs), late + 2 * kMs);
    const ServoCounts c = t.stats().counts();
    EXPECT_EQ(c.ticks, 4u);
    EXPECT_EQ(c.missed, 1u);
    EXPECT_NEAR(t.stats().periodError().maxNs(), 3.5e6, 1.0);
    std::vector<haptics::ServoEvent> events;
    t.stats().events().read(0, events);
    ASSERT_EQ(events.size(), 1u);
    EXPECT_EQ(events[0].kind, haptics::ServoEventKind::MissedDeadline);
    EXPECT_EQ(events[0].timeNs, late);
    EXPECT_EQ(events[0].valueNs, 3'500'000);
}

TEST(ServoEventLog, KeepsTheNewestAndSaysWhereToGoOn) {
    haptics::ServoEventLog log;
    const std::size_t n = haptics::ServoEventLog::kCapacity + 10;
    for (std::size_t i = 0; i < n; ++i) log.record(haptics::ServoEventKind::MissedDeadline, int64_t(i), int64_t(2 * i));
    std::vector<haptics::ServoEvent> events;
    const uint64_t next = log.read(0, events);
    EXPECT_EQ(next, n);
    ASSERT_EQ(events.size(), haptics::ServoEventLog::kCapacity) << "the oldest 10 were overwritten";
    EXPECT_EQ(events.front().index, 10u);
    EXPECT_EQ(events.front().timeNs, 10);
    EXPECT_EQ(events.back().valueNs, int64_t(2 * (n - 1)));
    log.record(haptics::ServoEventKind::Disconnected, 1000);
    events.clear();
    EXPECT_EQ(log.read(next, events), n + 1);
    ASSERT_EQ(events.size(), 1u);
    EXPECT_EQ(events[0].kind, haptics::ServoEventKind::Disconnected);
    EXPECT_STREQ(haptics::servoEventName(events[0].kind), "device disconnected");
}

TEST(ServoTicker, WatchdogTripZeroesAndRestartsTheClient) {
    RecordingDevice dev;
    ScriptedClient client;
    client.force = {1, 0, 0};
    ServoTicker t(dev, client, 1000.0);
    t.begin(0);
    t.step(0);
    EXPECT_TRUE(t.zeroForceFromWatchdog());  // lock-step stand-in for the watchdog thread
    ASSERT_EQ(dev.writes.size(), 2u);
    EXPECT_EQ(dev.writes[1], glm::dvec3(0.0));
    t.step(t.deadline());
    EXPECT_EQ(client.restarts, 2);
    EXPECT_EQ(t.stats().counts().watchdogTrips, 1u);
    std::vector<haptics::ServoEvent> events;
    t.stats().events().read(0, events);
    ASSERT_EQ(events.size(), 1u);
    EXPECT_EQ(events[0].kind, haptics::ServoEventKind::WatchdogRestart);
}

// ---- real threads ----

/// Thread-safe device: the last force in atomics, counts of writes, no allocation.
class AtomicDevice : public Device {
public:
    AtomicDevice() {
        mSpec.name = "atomic";
        mSpec.maxForce = 5.0;
    }
    const DeviceSpec& spec() const noexcept override { return mSpec; }
    bool read(DeviceState& out) noexcept override {
        out = DeviceState{};
        return true;
    }
    void write(const glm::dvec3& f) noexcept override {
        fx.store(f.x);
        fy.store(f.y);
        fz.store(f.z);
        writes.fetch_add(1);
        if (stalled && stalled->load() && f == glm::dvec3(0.0)) zeroWhileStalled.store(true);
    }
    glm::dvec3 last() const { return {fx.load(), fy.load(), fz.load()}; }

    std::atomic<double> fx{0}, fy{0}, fz{0};
    std::atomic<uint64_t> writes{0};
    std::atomic<bool>* stalled = nullptr;
    std::atomic<bool> zeroWhileStalled{false};

private:
    DeviceSpec mSpec;
};

/// A constant force; optionally one long stall; records the thread's allocations from tick 10 on.
class ThreadClient : public ServoClient {
public:
    void tick(const DeviceState&, double, glm::dvec3& out) noexcept override {
        const int n = ticks.fetch_add(1) + 1;
        if (n == 10) before = test::threadAllocationCounts();
        if (n > 10) {
            const test::AllocationCounts now = test::threadAllocationCounts();
            allocationsAfterStart.store(now.allocations - before.allocations);
        }
        if (n == stallAt) {
            stalled.store(true);
            std::this_thread::sleep_for(std::chrono::microseconds(stallUs));
            stalled.store(false);
        }
        out = {0, 2, 0};
    }
    void restart(const DeviceState&) noexcept override { restarts.fetch_add(1); }
    std::atomic<int> ticks{0}, restarts{0};
    std::atomic<bool> stalled{false};
    std::atomic<uint64_t> allocationsAfterStart{0};
    int stallAt = -1;
    int stallUs = 0;
    test::AllocationCounts before{};
};

ServoSettings testSettings(double rateHz = 1000.0) {
    ServoSettings s;
    s.rateHz = rateHz;
    s.realtimePriority = 0;  // tests need no privileges
    s.holdCpuDmaLatency = false;
    return s;
}

TEST(ServoLoop, StopZeroesForce) {
    AtomicDevice dev;
    ThreadClient client;
    {
        ServoLoop loop(dev, client, testSettings());
        loop.start();
        EXPECT_TRUE(loop.running());
        while (client.ticks.load() < 20) std::this_thread::sleep_for(1ms);
        EXPECT_EQ(dev.last(), glm::dvec3(0, 2, 0));
        loop.stop();
        EXPECT_FALSE(loop.running());
        EXPECT_EQ(dev.last(), glm::dvec3(0.0));
        loop.stop();  // idempotent
        // Restartable; destruction stops and zeroes too.
        loop.start();
        while (client.ticks.load() < 40) std::this_thread::sleep_for(1ms);
        EXPECT_EQ(dev.last(), glm::dvec3(0, 2, 0));
    }
    EXPECT_EQ(dev.last(), glm::dvec3(0.0));
}

TEST(ServoLoop, WatchdogZeroesForceOfAStalledLoop) {
    AtomicDevice dev;
    ThreadClient client;
    client.stallAt = 20;
    client.stallUs = 40'000;  // 40 ms inside the client
    dev.stalled = &client.stalled;
    ServoSettings s = testSettings();
    s.watchdogUs = 5'000;
    ServoLoop loop(dev, client, s);
    loop.start();
    while (client.ticks.load() < 60) std::this_thread::sleep_for(1ms);
    const glm::dvec3 resumed = dev.last();
    loop.stop();
    EXPECT_TRUE(dev.zeroWhileStalled.load()) << "no zero force was written while the client stalled";
    const ServoCounts c = loop.stats().counts();
    EXPECT_GE(c.watchdogTrips, 1u);
    EXPECT_GE(client.restarts.load(), 2);  // the first tick, and after the trip
    EXPECT_EQ(resumed, glm::dvec3(0, 2, 0));  // the loop went on after the stall
    EXPECT_GE(c.missed, 1u);
    EXPECT_EQ(dev.last(), glm::dvec3(0.0));
}

TEST(ServoLoop, RunsAtOneKilohertzAndAllocatesNothingWhileTicking) {
    AtomicDevice dev;
    ThreadClient client;
    ServoLoop loop(dev, client, testSettings());
    const ServoStartReport report = loop.start();
    std::this_thread::sleep_for(300ms);
    const ServoSummary live = loop.stats().summary();  // read while it runs: no locks
    loop.stop();
    const ServoSummary s = loop.stats().summary();
    std::printf("1 kHz for 0.3 s (no real-time priority): %llu ticks, %.1f Hz, period error p50 %.1f p99 %.1f max %.1f us, "
                "force p99.9 %.2f us, missed %llu\n",
                static_cast<unsigned long long>(s.counts.ticks), s.rateHz, s.periodErrorUs.p50, s.periodErrorUs.p99,
                s.periodErrorUs.max, s.forceUs.p999, static_cast<unsigned long long>(s.counts.missed));
    EXPECT_FALSE(report.realtime);
    EXPECT_GT(s.counts.ticks, 10u);
    EXPECT_GE(s.counts.ticks, live.counts.ticks);
    EXPECT_LE(s.counts.missed, s.counts.ticks);
    EXPECT_EQ(s.counts.disconnects, 0u);
    EXPECT_EQ(s.counts.nonFinite, 0u);
    EXPECT_LE(uint64_t(client.ticks.load()), s.counts.ticks);  // a watchdog trip may skip one
    EXPECT_GE(dev.writes.load(), s.counts.ticks + 1);  // every tick, and the zeros at the end
    EXPECT_GT(s.rateHz, 100.0);  // loose: a loaded CI machine must not fail this
    EXPECT_LT(s.rateHz, 1100.0);
    EXPECT_EQ(client.allocationsAfterStart.load(), 0u) << "the servo thread allocated while ticking";
}

TEST(ServoLoop, EachRequestIsGrantedOrWarned) {
    AtomicDevice dev;
    ThreadClient client;
    ServoSettings s = testSettings();
    s.realtimePriority = 1;  // the lowest FIFO priority, for a few ticks
    s.cpu = 0;
    s.holdCpuDmaLatency = true;
    ServoLoop loop(dev, client, s);
    const ServoStartReport r = loop.start();
    while (client.ticks.load() < 5) std::this_thread::sleep_for(1ms);
    loop.stop();
    std::printf("realtime %d, pinned %d, dma latency %d, %zu warnings\n", r.realtime, r.pinned, r.dmaLatency, r.warnings.size());
    for (const std::string& w : r.warnings) std::printf("  %s\n", w.c_str());
    const std::size_t refused = std::size_t(!r.realtime) + std::size_t(!r.pinned) + std::size_t(!r.dmaLatency);
    EXPECT_EQ(r.warnings.size(), refused) << "a refusal without a reason, or a reason without a refusal";
    EXPECT_EQ(dev.last(), glm::dvec3(0.0));
}

TEST(ServoLoop, RejectsSettingsOutOfRange) {
    AtomicDevice dev;
    ThreadClient client;
    ServoSettings s = testSettings();
    s.rateHz = 0.5;
    EXPECT_THROW((ServoLoop{dev, client, s}), std::invalid_argument);
    s = testSettings(4000.0);
    s.spinUs = 101;
    EXPECT_THROW((ServoLoop{dev, client, s}), std::invalid_argument);
    s = testSettings();
    s.watchdogUs = 1500;  // under two periods
    EXPECT_THROW((ServoLoop{dev, client, s}), std::invalid_argument);
    s = testSettings(10'000.0);
    s.spinUs = 100;  // spins a quarter of the period: 25 µs
    EXPECT_NO_THROW((ServoLoop{dev, client, s}));
}

}  // namespace
}  // namespace kizamu::haptics
