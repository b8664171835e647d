// SPDX-License-Identifier: Apache-2.0
// The haptic pipeline on real threads, the way the application runs it (and under
// ThreadSanitizer in the tsan preset): the servo loop's thread drives the simulated stylus on the
// wall clock and the proxy renderer on the engine's published clay, the watchdog thread watches
// it, the engine's edit thread carves what the proxy pushes, and this thread drains the trace
// ring and reads the mesh deltas. No real-time priority is asked for (tests never need it).
#include "engine/engine.h"
#include "haptics/engine_client.h"
#include "haptics/haptic_trace.h"
#include "haptics/servo_loop.h"
#include "sim/realtime_stylus.h"
#include "sim/simulated_stylus.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <thread>
#include <vector>

namespace kizamu {
namespace {

TEST(HapticServoEngine, TheServoThreadFeelsAndCarvesWhileTheEngineEditsAndTheAppReads) {
    sculpt::Script start;
    start.domain.originWorld = glm::dvec3(-0.05);
    start.domain.sizeWorld = 0.1;
    start.domain.maxLevel = 7;
    start.domain.tileSpanLevels = 4;
    start.start.kind = sculpt::Shape::Kind::Sphere;
    start.start.centre = glm::dvec3(0.0);
    start.start.radius = 0.03;
    engine::EngineSettings settings;
    settings.start = start;
    settings.threads = 2;
    engine::Engine e(settings);
    engine::ToolSettings carve;
    carve.tool.radius = 0.003;
    ASSERT_TRUE(e.setTool(carve).get().ok);

    // Press onto the top of the sphere, then carve 4 mm in, 1.2 s in all.
    sim::Hand hand;
    hand.add(0.0, {0.0, 0.0, 0.045});
    hand.add(0.3, {0.0, 0.0, 0.045});
    hand.add(0.6, {0.0, 0.0, 0.029});
    hand.add(0.7, {0.0, 0.0, 0.029}, engine::kButtonPrimary);
    hand.add(1.0, {0.0, 0.0, 0.029}, engine::kButtonPrimary);
    hand.add(1.0, {0.0, 0.0, 0.029}, 0);
    hand.add(1.2, {0.0, 0.0, 0.045}, 0);
    sim::SimulatedStylus stylus(hand);
    sim::RealtimeStylus device(stylus, &haptics::ServoLoop::clockNs);
    haptics::ProxySettings ps;
    ps.toolRadius = 0.003;
    haptics::ProxyRenderer renderer(stylus.spec(), 1e-3, ps);
    haptics::EngineHapticClient client(e.snapshots(), e.samples(), renderer);
    haptics::TraceRing ring(1u << 14);
    client.setTrace(&ring);
    haptics::ServoSettings ss;
    ss.realtimePriority = 0;
    ss.holdCpuDmaLatency = false;
    ss.watchdogUs = 200'000;  // sanitizers slow the servo thread; the watchdog is not what is tested here
    haptics::ServoLoop loop(device, client, ss);
    loop.start();
    uint64_t records = 0, contacts = 0, deltas = 0, eventsSeen = 0;
    std::vector<haptics::ServoEvent> events;
    double maxForce = 0.0;
    const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(1400);
    while (std::chrono::steady_clock::now() < end) {
        haptics::TraceRecord r;
        while (ring.pop(r)) {
            ++records;
            contacts += r.contact ? 1 : 0;
            maxForce = std::max(maxForce, glm::length(r.force));
        }
        if (e.takeMeshDelta()) ++deltas;
        events.clear();
        eventsSeen = loop.stats().events().read(eventsSeen, events);  // what a status line does
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    loop.stop();
    haptics::TraceRecord r;
    while (ring.pop(r)) ++records;
    while (!e.samples().flush()) std::this_thread::yield();
    ASSERT_TRUE(e.sync().get().ok);
    const haptics::ServoSummary s = loop.stats().summary();
    std::printf("[ servo ] %llu ticks, %llu traced, %llu in contact, max force %.2f N, %llu mesh deltas, %llu strokes\n",
                (unsigned long long)s.counts.ticks, (unsigned long long)records, (unsigned long long)contacts, maxForce,
                (unsigned long long)deltas, (unsigned long long)e.stats().strokes);
    EXPECT_GT(s.counts.ticks, 500u);
    EXPECT_EQ(records + ring.dropped(), s.counts.ticks);
    EXPECT_GT(contacts, 100u) << "the stylus pressed onto the clay";
    EXPECT_LE(maxForce, renderer.maxForce() + 1e-9);
    EXPECT_EQ(s.counts.nonFinite, 0u);
    EXPECT_EQ(e.stats().strokes, 1u) << "the carve press is one stroke";
    EXPECT_GT(deltas, 0u);
    // The carve went in: the clay's top is below where it started.
    adf::SnapshotStore::Reader reader(e.snapshots());
    EXPECT_GT(double(reader.acquire().adf().distance(glm::vec3(0.0f, 0.0f, 0.0295f))), 0.0) << "the top was carved";
}

}  // namespace
}  // namespace kizamu
