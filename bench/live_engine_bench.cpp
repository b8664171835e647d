// SPDX-License-Identifier: Apache-2.0
/// @file live_engine_bench.cpp
/// @brief The live engine's latency: a sample's push to the snapshot that contains it and to
/// the mesh delta that shows it, while a 1 kHz servo thread pushes and queries.
///
/// The stroke (issue 31): a sphere of radius 1 % of the domain carving along the test part's
/// top at 10 cm/s in a 1 m domain for 2 s, sampled at 1 kHz. One servo thread does what the
/// haptic thread will: every millisecond it reads the (scripted) device pose, queries the
/// published clay under it through a GuardedAccessor, and pushes the sample; it runs at
/// SCHED_FIFO where the process may (root), as the app's does. Latencies come from the
/// engine's observer: each sample's push time stamp against the steady_clock time of the
/// publish and of the posted mesh delta that first hold it. The live stroke's total edit time
/// is set against Sculptor::apply of the same poses as one stroke.
/// Configurations (docs/decisions/0030-live-engine-threads.md): the pool on every allowed CPU
/// with the servo thread sharing them under SCHED_FIFO preemption (the engine's default), the
/// servo thread on a CPU of its own with the pool and the edit thread on the rest, and the
/// default with mesh superseding on.
#include "bench/live_engine_bench.h"

#include "adf/guarded_accessor.h"
#include "bench/timing.h"
#include "engine/engine.h"
#include "sculpt/script_start.h"
#include "util/cpu_set.h"
#include "util/realtime.h"
#include "util/thread_pool.h"

#include <atomic>
#include <chrono>
#include <cstdio>
#include <string>
#include <thread>
#include <vector>

namespace kizamu::bench {

namespace {

using Clock = std::chrono::steady_clock;

int64_t nowNs() { return std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now().time_since_epoch()).count(); }

struct Config {
    std::string name;
    bool dedicatedServoCpu = false;
    bool supersede = false;
};

struct RunResult {
    std::vector<double> toSnapshotMs, toMeshMs, servoErrorUs;
    double liveEditMs = 0.0, wholeEditMs = 0.0;
    uint64_t segments = 0, superseded = 0;
    std::string realtime;  ///< why the servo thread has no real-time priority, or empty
};

sculpt::Script testPartScript(int level) {
    sculpt::Script s;
    s.domain.maxLevel = level;
    s.start.kind = sculpt::Shape::Kind::TestPart;
    return s;
}

/// The stroke's poses: along x at y = 0.5 on the test part's top surface, found from above.
std::vector<glm::dvec3> strokePath(const adf::Adf& clay, std::size_t n, double length) {
    const adf::Domain& d = clay.domain();
    const double h = d.finestCellSize();
    std::vector<glm::dvec3> out;
    for (std::size_t i = 0; i < n; ++i) {
        const double x = d.originWorld.x + d.sizeWorld * 0.5 - 0.5 * length + length * double(i) / double(n - 1);
        const double y = d.originWorld.y + d.sizeWorld * 0.5;
        double hi = d.originWorld.z + d.sizeWorld - h, lo = hi;
        while (lo > d.originWorld.z && clay.distance(glm::vec3(glm::dvec3(x, y, lo))) > 0.0f) lo -= 4.0 * h;
        for (int k = 0; k < 40; ++k) {  // bisect: outside at hi, inside at lo
            const double mid = 0.5 * (lo + hi);
            (clay.distance(glm::vec3(glm::dvec3(x, y, mid))) > 0.0f ? hi : lo) = mid;
        }
        out.emplace_back(x, y, 0.5 * (lo + hi));
    }
    return out;
}

RunResult runStroke(int level, const Config& config, util::ThreadPool& wholePool) {
    constexpr std::size_t kSamples = 2000;  // 2 s at 1 kHz
    RunResult r;
    const std::vector<int> cpus = util::allowedCpus();
    const bool dedicated = config.dedicatedServoCpu && cpus.size() >= 2;
    engine::EngineSettings settings;
    settings.start = testPartScript(level);
    settings.correctAfterIdle = std::chrono::milliseconds(0);
    settings.supersedeMesh = config.supersede;
    if (dedicated) settings.poolCpus.assign(cpus.begin(), cpus.end() - 1);
    r.toSnapshotMs.reserve(kSamples);
    r.toMeshMs.reserve(kSamples);
    settings.observer = [&r](const engine::EngineEvent& e) {
        std::vector<double>& v = e.kind == engine::EngineEvent::Kind::Published ? r.toSnapshotMs : r.toMeshMs;
        for (const engine::ToolSample& s : e.samples) v.push_back(double(e.atNs - s.timeNs) * 1e-6);
        if (e.kind == engine::EngineEvent::Kind::Published) r.liveEditMs += e.ms;
    };
    engine::Engine engine(std::move(settings));
    engine::ToolSettings tool;
    tool.tool.radius = 0.01;  // 1 % of the 1 m domain
    engine.setTool(tool).get();
    std::vector<glm::dvec3> path;
    {
        adf::SnapshotStore::Reader reader(engine.snapshots());
        const auto g = reader.acquire();
        path = strokePath(g.adf(), kSamples, 0.2);  // 10 cm/s for 2 s
    }
    std::vector<double> servoError;
    servoError.reserve(kSamples + 1);
    const util::CpuDmaLatency noDeepIdle;  // as the app's servo loop holds it: no deep C-states while it runs
    std::thread servo([&] {
        std::string why;
        if (dedicated) util::pinCurrentThread(cpus.back(), &why);
        if (!util::setRealtimePriority(80, &why)) r.realtime = why;
        adf::SnapshotStore::Reader reader(engine.snapshots());
        std::optional<adf::GuardedAccessor> acc;
        {
            const auto g = reader.acquire();
            acc.emplace(g);
        }
        engine::SampleQueue& q = engine.samples();
        float sink = 0.0f;
        auto tick = Clock::now();
        for (std::size_t i = 0; i <= kSamples; ++i) {
            tick += std::chrono::milliseconds(1);
            std::this_thread::sleep_until(tick);
            servoError.push_back(std::chrono::duration<double, std::micro>(Clock::now() - tick).count());
            const glm::dvec3 p = path[std::min(i, kSamples - 1)];
            {
                const auto g = reader.acquire();
                sink += acc->sample(g, glm::vec3(p)).distance;
            }
            engine::ToolSample s;
            s.timeNs = nowNs();
            s.posWorld = p;
            s.buttons = i < kSamples ? engine::kButtonPrimary : 0u;
            q.push(s);
        }
        while (!q.flush()) std::this_thread::yield();
        if (sink == 12345.0f) std::printf(" ");  // keeps the queries
    });
    servo.join();
    engine.sync().get();
    r.segments = engine.stats().segments;
    r.superseded = engine.stats().superseded;
    r.servoErrorUs = std::move(servoError);
    // The same poses as one stroke, applied whole.
    auto whole = sculpt::makeSculptor(testPartScript(level), 0, &wholePool);
    sculpt::Stroke stroke;
    stroke.tool = tool.tool;
    for (const glm::dvec3& p : path) stroke.samples.push_back({p, glm::dquat(1.0, 0.0, 0.0, 0.0)});
    const auto t0 = Clock::now();
    whole->apply(stroke);
    r.wholeEditMs = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    return r;
}

/// One run's figures; across runs, each figure's median.
struct Summary {
    double snapshotP50 = 0, snapshotP99 = 0, meshP50 = 0, meshP99 = 0, segments = 0, superseded = 0;
    double liveEditMs = 0, wholeEditMs = 0, vsWhole = 0, servoP999 = 0;
};

Summary summarise(const RunResult& r) {
    return {quantile(r.toSnapshotMs, 0.5), quantile(r.toSnapshotMs, 0.99), quantile(r.toMeshMs, 0.5), quantile(r.toMeshMs, 0.99),
            double(r.segments), double(r.superseded), r.liveEditMs, r.wholeEditMs, r.liveEditMs / r.wholeEditMs,
            quantile(r.servoErrorUs, 0.999)};
}

/// Runs the stroke `repeats` times and takes each figure's median over the runs.
Summary medianRun(int level, const Config& config, int repeats, util::ThreadPool& pool, FigureSink& out) {
    std::vector<Summary> runs;
    for (int i = 0; i < repeats; ++i) {
        out.progress("live stroke at level " + std::to_string(level) + ", " + config.name + ", run " + std::to_string(i + 1) + "/" +
                     std::to_string(repeats));
        const RunResult r = runStroke(level, config, pool);
        if (i == 0 && !r.realtime.empty()) out.progress("servo thread: " + r.realtime);
        runs.push_back(summarise(r));
    }
    auto med = [&](double Summary::*f) {
        std::vector<double> v;
        for (const Summary& s : runs) v.push_back(s.*f);
        return median(v);
    };
    return {med(&Summary::snapshotP50), med(&Summary::snapshotP99), med(&Summary::meshP50), med(&Summary::meshP99),
            med(&Summary::segments), med(&Summary::superseded), med(&Summary::liveEditMs), med(&Summary::wholeEditMs),
            med(&Summary::vsWhole), med(&Summary::servoP999)};
}

}  // namespace

void liveEngineFigures(FigureSink& out, const LiveEngineBenchOptions& opt) {
    util::ThreadPool pool;
    for (std::size_t li = 0; li < opt.levels.size(); ++li) {
        const int level = opt.levels[li];
        const std::string lv = "level" + std::to_string(level);
        out.section("a 2 s carving stroke at 1 kHz through the live engine, test part, " + lv + " (medians of " +
                    std::to_string(opt.repeats) + " runs)");
        const Summary r = medianRun(level, {"shared", false, false}, opt.repeats, pool, out);
        out.add("live.sample_to_snapshot_ms." + lv + ".p50", r.snapshotP50, "ms");
        out.add("live.sample_to_snapshot_ms." + lv + ".p99", r.snapshotP99, "ms");
        out.add("live.sample_to_mesh_ms." + lv + ".p50", r.meshP50, "ms", level == 10 ? "budget 4 ms" : "");
        out.add("live.sample_to_mesh_ms." + lv + ".p99", r.meshP99, "ms", level == 10 ? "budget 11 ms" : level == 12 ? "budget 50 ms" : "");
        out.add("live.segments." + lv, r.segments, "segments");
        out.add("live.live_edit_ms." + lv, r.liveEditMs, "ms", "the segments' edits, summed");
        out.add("live.whole_edit_ms." + lv, r.wholeEditMs, "ms", "Sculptor::apply of the same poses");
        out.add("live.vs_whole_stroke." + lv, r.vsWhole, "x");
        out.add("live.servo_period_error_us." + lv + ".p999", r.servoP999, "us", "budget 100 us");
        if (li != 0 || !opt.placement) continue;
        out.section("the same stroke at " + lv + ": servo thread on a CPU of its own; mesh superseding");
        const Summary d = medianRun(level, {"dedicated", true, false}, opt.repeats, pool, out);
        out.add("live.placement.dedicated.sample_to_mesh_ms." + lv + ".p50", d.meshP50, "ms");
        out.add("live.placement.dedicated.sample_to_mesh_ms." + lv + ".p99", d.meshP99, "ms");
        out.add("live.placement.dedicated.live_edit_ms." + lv, d.liveEditMs, "ms", "shared: live.live_edit_ms");
        out.add("live.placement.dedicated.servo_period_error_us." + lv + ".p999", d.servoP999, "us");
        const Summary s = medianRun(level, {"supersede", false, true}, opt.repeats, pool, out);
        out.add("live.supersede.sample_to_mesh_ms." + lv + ".p50", s.meshP50, "ms");
        out.add("live.supersede.sample_to_mesh_ms." + lv + ".p99", s.meshP99, "ms");
        out.add("live.supersede.superseded." + lv, s.superseded, "mesh updates skipped");
    }
}

}  // namespace kizamu::bench
