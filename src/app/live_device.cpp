// SPDX-License-Identifier: Apache-2.0
/// @file live_device.cpp
/// @brief runDeviceLive: a haptic device (app/device_open.h), the servo ticker or loop, and the
/// live engine.
///
/// Lock step (--rate 0, the simulated stylus only): one thread; each 1 ms tick reads the stylus,
/// renders, writes, steps the stylus, and waits for the engine to apply the sample (sync), so the
/// same hand file gives the same trace and the same clay. Real time: the servo loop's thread
/// drives the device (the simulated stylus on the wall clock, sim/realtime_stylus.h, or a real
/// one) while this thread drains the trace ring every few ms.
#include "app/live_device.h"

#include "app/commands.h"
#include "app/device_open.h"
#include "engine/engine.h"
#include "engine/trajectory.h"
#include "haptics/engine_client.h"
#include "haptics/haptic_trace.h"
#include "haptics/servo_loop.h"
#include "sculpt/session.h"
#include "sim/hand_file.h"
#include "sim/realtime_stylus.h"
#include "sim/simulated_stylus.h"
#include "util/file_error.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <optional>
#include <stdexcept>
#include <thread>

namespace kizamu::app {

namespace {

/// The clay the example hand files are written for: a 3 cm sphere at the centre of the
/// simulated stylus's 10 cm workspace (docs/HAND.md).
sculpt::Script defaultStart(int level) {
    sculpt::Script s;
    s.domain.originWorld = glm::dvec3(-0.05);
    s.domain.sizeWorld = 0.1;
    s.domain.maxLevel = level > 0 ? level : 9;
    s.domain.tileSpanLevels = 4;
    s.start.kind = sculpt::Shape::Kind::Sphere;
    s.start.centre = glm::dvec3(0.0);
    s.start.radius = 0.03;
    return s;
}

/// What the run saw, from the trace records (world frame).
struct Tally {
    uint64_t ticks = 0, contactTicks = 0, carvingTicks = 0;
    double maxForce = 0.0;
    void add(const haptics::TraceRecord& r) {
        ++ticks;
        if (r.contact) ++contactTicks;
        if (r.buttons & engine::kButtonPrimary) ++carvingTicks;
        maxForce = std::max(maxForce, glm::length(r.force));
    }
};

/// Collects the tool samples for --record-trajectory (time stamps from the first record).
struct TrajectoryRecorder {
    engine::Trajectory trajectory;
    int64_t t0Ns = -1;
    void add(const haptics::TraceRecord& r) {
        if (t0Ns < 0) t0Ns = r.timeNs;
        engine::ToolSample s;
        s.timeNs = r.timeNs - t0Ns;
        s.posWorld = r.proxy;
        s.orientation = glm::quat(r.orientation);
        s.buttons = r.buttons;
        trajectory.add(s);
    }
};

}  // namespace

void runDeviceLive(const DeviceLiveOptions& o) {
    DeviceOpenOptions open;
    open.firmware = o.firmware;
    if (!o.hand.empty()) open.hand = sim::readHand(o.hand);
    const OpenedDevice opened = openDevice(o.device, open, o.rate > 0.0);
    const haptics::DeviceSpec& spec = opened.device().spec();
    if (!opened.stylus && !o.hand.empty()) std::fprintf(stderr, "warning: --hand drives the simulated stylus only\n");

    engine::EngineSettings settings;
    settings.sessionDir = o.session;
    settings.threads = o.threads;
    const bool resume = !o.session.empty() && sculpt::isSessionDir(o.session);
    if (resume && o.level != 0) throw FileError(o.session, "--level applies to a new session, not one reopened");
    settings.start = defaultStart(o.level);
    engine::Engine engine(std::move(settings));

    engine::ToolSettings carve;
    carve.tool.radius = o.toolRadius;  // the engine carves the haptic tool's own sphere
    if (const engine::CommandResult r = engine.setTool(carve).get(); !r.ok) throw std::runtime_error(r.message);

    // The device's workspace fitted into the clay's domain (identity for the default clay).
    adf::Domain domain;
    {
        adf::SnapshotStore::Reader reader(engine.snapshots());
        domain = reader.acquire().adf().domain();
    }
    haptics::HapticToolSettings tool;
    tool.mapping = haptics::WorkspaceMapping::fit(spec, domain.originWorld, domain.originWorld + glm::dvec3(domain.sizeWorld));
    tool.planar = opened.planar;
    const double servoRate = o.rate > 0.0 ? o.rate : 1000.0;
    haptics::ProxySettings ps;
    ps.toolRadius = o.toolRadius;
    ps.stiffness = o.stiffness;
    ps.forceScale = o.forceScale;
    haptics::ProxyRenderer renderer(tool.mapping.worldSpec(spec), 1.0 / servoRate, ps);
    haptics::EngineHapticClient client(engine.snapshots(), engine.samples(), renderer, tool);

    haptics::TraceRing ring(1u << 16);
    client.setTrace(&ring);
    std::optional<haptics::TraceFile> trace;
    if (!o.record.empty()) {
        haptics::TraceHeader h;
        h.device = spec.name;
        h.maxForce = renderer.maxForce();
        h.stiffness = renderer.gains().stiffness * tool.mapping.scale;  // as the device feels it
        h.damping = renderer.gains().damping * tool.mapping.scale;
        h.rate = servoRate;
        h.deviceDamping = spec.damping;
        h.scale = tool.mapping.scale;
        trace.emplace(o.record, h);
    }
    Tally tally;
    TrajectoryRecorder recorder;
    if (!o.recordTrajectory.empty()) {
        recorder.trajectory.device = spec.name + " (kizamu live --device " + opened.id + ")";
        if (!resume) recorder.trajectory.start = engine::TrajectoryStart{defaultStart(o.level).domain, defaultStart(o.level).start};
        engine::ToolChange change;
        change.tool = carve.tool;
        recorder.trajectory.add(change);
    }
    const auto drain = [&] {
        const auto each = [&](const haptics::TraceRecord& r) {
            tally.add(r);
            if (!o.recordTrajectory.empty()) recorder.add(r);
        };
        if (trace) {
            trace->drain(ring, each);
        } else {
            haptics::TraceRecord r;
            while (ring.pop(r)) each(r);
        }
    };

    // The hand's script and a moment to settle, or as long as asked for a person's hand.
    const double duration = opened.stylus ? opened.stylus->hand().duration() + 0.2 : (o.seconds > 0.0 ? o.seconds : 10.0);
    const auto started = std::chrono::steady_clock::now();
    std::optional<haptics::ServoSummary> timing;
    if (o.rate == 0.0) {
        sim::SimulatedStylus& stylus = *opened.stylus;  // lock step: openDevice allows only the simulated stylus
        haptics::ServoTicker ticker(stylus, client, servoRate);
        ticker.begin(0);
        const int64_t period = ticker.periodNs();
        const int64_t ticks = int64_t(duration * servoRate);
        for (int64_t i = 0; i < ticks; ++i) {
            ticker.step(i * period);
            stylus.step(1.0 / servoRate);
            while (!engine.samples().flush()) std::this_thread::yield();
            engine.sync().get();
            drain();
        }
        ticker.zeroForce();
    } else {
        haptics::ServoSettings ss;
        ss.rateHz = o.rate;
        haptics::ServoLoop loop(opened.device(), client, ss);
        const haptics::ServoStartReport report = loop.start();
        for (const std::string& w : report.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
        const auto end = started + std::chrono::duration<double>(duration);
        while (std::chrono::steady_clock::now() < end) {
            std::this_thread::sleep_for(std::chrono::milliseconds(5));
            drain();
        }
        loop.stop();
        timing = loop.stats().summary();
    }
    drain();
    while (!engine.samples().flush()) std::this_thread::yield();
    if (const engine::CommandResult r = engine.sync().get(); !r.ok) throw std::runtime_error(r.message);
    for (const std::string& n : engine.takeNotices()) std::fprintf(stderr, "warning: %s\n", n.c_str());

    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    const engine::EngineStats st = engine.stats();
    std::printf("live: %s, %llu servo ticks in %.2f s (%s): %llu in contact, %llu carving, max force %.2f N of %.2f; "
                "%llu strokes, %llu segments\n",
                spec.name.c_str(), (unsigned long long)tally.ticks, seconds, o.rate == 0.0 ? "lock step" : "real time",
                (unsigned long long)tally.contactTicks, (unsigned long long)tally.carvingTicks, tally.maxForce,
                renderer.maxForce(), (unsigned long long)st.strokes, (unsigned long long)st.segments);
    if (timing)
        std::printf("servo: %.1f Hz, period error p50 %.1f / p99 %.1f / p99.9 %.1f / max %.1f us, missed %.3f %%, force p99.9 %.2f us\n",
                    timing->rateHz, timing->periodErrorUs.p50, timing->periodErrorUs.p99, timing->periodErrorUs.p999,
                    timing->periodErrorUs.max, 100.0 * timing->missedFraction, timing->forceUs.p999);
    if (ring.dropped() > 0)
        std::fprintf(stderr, "warning: %llu servo ticks were not traced (the trace ring was full)\n",
                     (unsigned long long)ring.dropped());
    if (trace) {
        trace->close();
        std::printf("wrote %s\n", o.record.c_str());
    }
    if (!o.recordTrajectory.empty()) {
        engine::writeTrajectory(recorder.trajectory, o.recordTrajectory);
        std::printf("wrote %s\n", o.recordTrajectory.c_str());
    }
    if (!o.out.empty()) {
        const engine::CommandResult w = isAdfPath(o.out) ? engine.save(o.out).get() : engine.exportMesh(o.out, o.units).get();
        if (!w.ok) throw std::runtime_error(w.message);
        std::printf("wrote %s\n", o.out.c_str());
    }
}

}  // namespace kizamu::app
