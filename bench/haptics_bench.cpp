// SPDX-License-Identifier: Apache-2.0
/// @file haptics_bench.cpp
/// @brief runHapticsBench: the servo loop's achieved rate, period error, force computation time
/// and missed deadlines, bare and under the live engine's load.
///
/// Each run starts a ServoLoop (SCHED_FIFO where the process may, /dev/cpu_dma_latency held)
/// for `seconds` and reads its ServoStats. The device is a stand-in that answers at once (a
/// Falcon-class spec); the client is the application's: EngineHapticClient running the proxy
/// renderer (haptics/proxy_renderer.h) on the published clay through a GuardedAccessor.
///  - bare: the test part in a SnapshotStore nobody writes, the point walking along its top;
///    no other thread of ours runs, so the period error is the machine's own timer floor.
///  - load: an engine::Engine on the test part while a producer thread pushes 1 kHz tool samples
///    with the primary button held, strokes of 2 s each along the top, 0.2 s apart, one line
///    over from the last, a little deeper each round: the edit thread and its pool carve and
///    re-mesh all the time. The device point follows the tool (the clay being carved).
/// Bare and loaded runs alternate `repeats` times at each rate; each figure is the median over
/// the runs (max: the largest; missed deadlines: all runs' missed ticks over all their ticks).
#include "bench/haptics_bench.h"

#include "adf/guarded_accessor.h"
#include "adf/snapshot_store.h"
#include "bench/figures.h"
#include "bench/timing.h"
#include "engine/engine.h"
#include "haptics/engine_client.h"
#include "haptics/proxy_renderer.h"
#include "haptics/servo_loop.h"
#include "sculpt/script_start.h"
#include "sim/simulated_stylus.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace kizamu::bench {

namespace {

using Clock = std::chrono::steady_clock;

sculpt::Script testPartScript(int level) {
    sculpt::Script s;
    s.domain.maxLevel = level;
    s.start.kind = sculpt::Shape::Kind::TestPart;
    return s;
}

/// Points along x at height of the clay's top surface (found from above by bisection), at y.
std::vector<glm::dvec3> surfaceLine(const adf::Adf& clay, double y, std::size_t n, double length) {
    const adf::Domain& d = clay.domain();
    const double h = d.finestCellSize();
    std::vector<glm::dvec3> out;
    for (std::size_t i = 0; i < n; ++i) {
        const double x = d.originWorld.x + d.sizeWorld * 0.5 - 0.5 * length + length * double(i) / double(n - 1);
        double hi = d.originWorld.z + d.sizeWorld - h, lo = hi;
        while (lo > d.originWorld.z && clay.distance(glm::vec3(glm::dvec3(x, y, lo))) > 0.0f) lo -= 4.0 * h;
        for (int k = 0; k < 40; ++k) {
            const double mid = 0.5 * (lo + hi);
            (clay.distance(glm::vec3(glm::dvec3(x, y, mid))) > 0.0f ? hi : lo) = mid;
        }
        out.emplace_back(x, y, 0.5 * (lo + hi));
    }
    return out;
}

/// Answers at once; its point walks along `path` (bare) or follows the producer's tool (load).
/// Its spec is the simulated stylus's (a Falcon-class device), so the renderer's gains are the
/// ones the application uses.
class StandInDevice : public haptics::Device {
public:
    explicit StandInDevice(const std::vector<glm::dvec3>* path) : mSpec(sim::SimulatedStylus(sim::Hand{}).spec()), mPath(path) {
        mSpec.name = "bench stand-in";
    }
    const haptics::DeviceSpec& spec() const noexcept override { return mSpec; }
    bool read(haptics::DeviceState& out) noexcept override {
        if (mPath) {
            out.position = (*mPath)[mNext];
            mNext = (mNext + 1) % mPath->size();
        } else {
            out.position = {tool[0].load(std::memory_order_relaxed), tool[1].load(std::memory_order_relaxed),
                            tool[2].load(std::memory_order_relaxed)};
        }
        return true;
    }
    void write(const glm::dvec3& force) noexcept override { mForce = force; }

    std::atomic<double> tool[3] = {0.5, 0.5, 0.5};  ///< the producer's latest tool point (load)

private:
    haptics::DeviceSpec mSpec;
    const std::vector<glm::dvec3>* mPath;
    std::size_t mNext = 0;
    glm::dvec3 mForce{0.0};
};

/// The application's force computation: the proxy renderer on the published clay through
/// EngineHapticClient (a 1 cm tool sphere; the device 1 mm past the touching level, about 3 N
/// at the renderer's 3200 N/m, a firm press; every tick a contact: march, bisection and slide),
/// pushing the proxy to `samples`.
struct Rendering {
    haptics::ProxyRenderer renderer;
    haptics::EngineHapticClient client;
    Rendering(adf::SnapshotStore& store, engine::SampleQueue& samples, const haptics::Device& device, double rateHz)
        : renderer(device.spec(), 1.0 / rateHz, proxySettings()), client(store, samples, renderer) {}
    static haptics::ProxySettings proxySettings() {
        haptics::ProxySettings ps;
        ps.toolRadius = 0.01;
        ps.kineticFriction = 0.2;
        ps.staticFriction = 0.3;
        return ps;
    }
};

/// m above a surface point (the top's normal is +z) where the stand-in device presses: 1 mm past
/// the 1 cm tool's touching level.
constexpr double kPress = 0.009;

struct Run {
    haptics::ServoSummary summary;
    bool realtime = false;
    std::vector<std::string> warnings;
    uint64_t segments = 0;  ///< live segments the engine applied (load)
};

Run runServo(haptics::Device& device, haptics::ServoClient& client, const HapticsBenchOptions& opt, double rateHz) {
    haptics::ServoSettings s;
    s.rateHz = rateHz;
    s.realtimePriority = opt.priority;
    s.cpu = opt.servoCpu;
    s.spinUs = opt.spinUs;
    haptics::ServoLoop loop(device, client, s);
    Run r;
    const haptics::ServoStartReport report = loop.start();
    r.realtime = report.realtime;
    r.warnings = report.warnings;
    std::this_thread::sleep_for(std::chrono::duration<double>(opt.seconds));
    loop.stop();
    r.summary = loop.stats().summary();
    return r;
}

Run bareRun(adf::SnapshotStore& store, const std::vector<glm::dvec3>& path, const HapticsBenchOptions& opt, double rateHz) {
    StandInDevice device(&path);
    engine::SampleQueue nobody;  // the proxies pushed go nowhere: no engine runs
    Rendering rendering(store, nobody, device, rateHz);
    return runServo(device, rendering.client, opt, rateHz);
}

Run loadRun(const HapticsBenchOptions& opt, double rateHz) {
    engine::EngineSettings settings;
    settings.start = testPartScript(opt.level);
    settings.correctAfterIdle = std::chrono::milliseconds(0);
    settings.producers = 2;  // 0: the carving producer, 1: the servo thread's proxies (no button: it feels only)
    engine::Engine engine(std::move(settings));
    engine::ToolSettings tool;
    tool.tool.radius = 0.01;  // 1 % of the 1 m domain
    engine.setTool(tool).get();
    constexpr int kLines = 8;
    constexpr std::size_t kStrokeSamples = 2000, kGapSamples = 200;  // 2 s held, 0.2 s released
    std::vector<std::vector<glm::dvec3>> lines;
    {
        adf::SnapshotStore::Reader reader(engine.snapshots());
        const auto g = reader.acquire();
        for (int k = 0; k < kLines; ++k) lines.push_back(surfaceLine(g.adf(), 0.43 + 0.02 * k, kStrokeSamples, 0.2));
    }
    StandInDevice device(nullptr);
    const glm::dvec3 start = lines[0][0];
    for (int a = 0; a < 3; ++a) device.tool[a].store(start[a]);
    Run r;
    {
        Rendering rendering(engine.snapshots(), engine.samples(1), device, rateHz);  // its Reader goes before the engine
        std::atomic<bool> stop{false};
        std::thread producer([&] {
            engine::SampleQueue& q = engine.samples();
            auto tick = Clock::now();
            for (std::size_t stroke = 0; !stop.load(std::memory_order_relaxed); ++stroke) {
                const std::vector<glm::dvec3>& line = lines[stroke % kLines];
                const double deeper = 0.004 * double(stroke / kLines);  // a little deeper each round
                for (std::size_t i = 0; i < kStrokeSamples + kGapSamples && !stop.load(std::memory_order_relaxed); ++i) {
                    tick += std::chrono::milliseconds(1);
                    std::this_thread::sleep_until(tick);
                    engine::ToolSample s;
                    s.timeNs = std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now().time_since_epoch()).count();
                    s.posWorld = line[std::min(i, kStrokeSamples - 1)] - glm::dvec3(0.0, 0.0, deeper);
                    s.buttons = i < kStrokeSamples ? engine::kButtonPrimary : 0u;
                    const glm::dvec3 felt = s.posWorld + glm::dvec3(0.0, 0.0, kPress);
                    for (int a = 0; a < 3; ++a) device.tool[a].store(felt[a], std::memory_order_relaxed);
                    q.push(s);
                }
            }
            engine::ToolSample up;  // release the button
            up.timeNs = std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now().time_since_epoch()).count();
            up.posWorld = {device.tool[0].load(), device.tool[1].load(), device.tool[2].load()};
            q.push(up);
            while (!q.flush()) std::this_thread::yield();
        });
        r = runServo(device, rendering.client, opt, rateHz);
        stop.store(true);
        producer.join();
    }
    engine.sync().get();
    r.segments = engine.stats().segments;
    return r;
}

/// Each figure over the runs: medians, the largest max, missed over all ticks.
struct Figures {
    double rate = 0, p50 = 0, p99 = 0, p999 = 0, max = 0, force50 = 0, force999 = 0, missed = 0, segments = 0;
    bool realtime = true;
};

Figures combine(const std::vector<Run>& runs) {
    Figures f;
    auto med = [&](auto get) {
        std::vector<double> v;
        for (const Run& r : runs) v.push_back(get(r.summary));
        return median(v);
    };
    f.rate = med([](const haptics::ServoSummary& s) { return s.rateHz; });
    f.p50 = med([](const haptics::ServoSummary& s) { return s.periodErrorUs.p50; });
    f.p99 = med([](const haptics::ServoSummary& s) { return s.periodErrorUs.p99; });
    f.p999 = med([](const haptics::ServoSummary& s) { return s.periodErrorUs.p999; });
    f.force50 = med([](const haptics::ServoSummary& s) { return s.forceUs.p50; });
    f.force999 = med([](const haptics::ServoSummary& s) { return s.forceUs.p999; });
    uint64_t ticks = 0, missed = 0;
    std::vector<double> segments;
    for (const Run& r : runs) {
        f.max = std::max(f.max, r.summary.periodErrorUs.max);
        ticks += r.summary.counts.ticks;
        missed += r.summary.counts.missed;
        f.realtime = f.realtime && r.realtime;
        segments.push_back(double(r.segments));
    }
    f.missed = ticks > 0 ? double(missed) / double(ticks) : 0.0;
    f.segments = median(segments);
    return f;
}

/// The force computation alone, with no thread or deadline around it: `ticks` back-to-back
/// updates on the calling thread along `path`, each timed. Separates what the renderer costs from
/// what the servo thread's scheduling adds to its measured force time (a tick preempted midway).
std::vector<double> forceAlone(adf::SnapshotStore& store, const std::vector<glm::dvec3>& path, std::size_t ticks) {
    StandInDevice device(&path);
    engine::SampleQueue nobody;
    Rendering rendering(store, nobody, device, 1000.0);
    std::vector<double> us;
    us.reserve(ticks);
    haptics::DeviceState state;
    glm::dvec3 force;
    for (std::size_t i = 0; i < ticks; ++i) {
        device.read(state);
        const auto t0 = Clock::now();
        rendering.client.tick(state, 1e-3, force);
        us.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count());
    }
    return us;
}

std::string hz(double rate) { return std::to_string(int(std::lround(rate))) + " Hz"; }

}  // namespace

int runHapticsBench(const HapticsBenchOptions& opt) {
    FigureSink out(opt.json);
    if (!opt.json)
        std::printf(
            "kizamu bench haptics: the servo thread bare and while the live engine carves a level-%d test part; %d runs "
            "of %.3g s each, interleaved; figures are medians over the runs (max: the largest)\n"
            "force computation: the proxy renderer (1 cm tool, in contact every tick) on the published clay, "
            "the proxy pushed to the engine\n",
            opt.level, opt.repeats, opt.seconds);
    // The bare runs' clay: the same test part, in a store nobody writes.
    adf::SnapshotStore bareStore(sculpt::startAdf(testPartScript(opt.level), 0));
    std::vector<glm::dvec3> barePath;
    {
        adf::SnapshotStore::Reader reader(bareStore);
        const auto g = reader.acquire();
        barePath = surfaceLine(g.adf(), 0.5, 2000, 0.2);
        for (glm::dvec3& p : barePath) p.z += kPress;  // the top's normal is +z
        const std::vector<glm::dvec3> back(barePath.rbegin(), barePath.rend());
        barePath.insert(barePath.end(), back.begin(), back.end());
    }

    out.progress("the force computation alone");
    const std::vector<double> alone = forceAlone(bareStore, barePath, 200'000);

    bool realtime = true, warned = false;
    auto measure = [&](double rateHz, Figures& bare, Figures& load) {
        std::vector<Run> bareRuns, loadRuns;
        for (int i = 0; i < opt.repeats; ++i) {
            const std::string of = " run " + std::to_string(i + 1) + "/" + std::to_string(opt.repeats) + " at " + hz(rateHz);
            out.progress("bare" + of);
            bareRuns.push_back(bareRun(bareStore, barePath, opt, rateHz));
            out.progress("under load" + of);
            loadRuns.push_back(loadRun(opt, rateHz));
            for (const Run* r : {&bareRuns.back(), &loadRuns.back()})
                if (!warned && !r->warnings.empty()) {
                    for (const std::string& w : r->warnings) out.progress("warning: " + w);
                    warned = true;
                }
        }
        bare = combine(bareRuns);
        load = combine(loadRuns);
        realtime = realtime && bare.realtime && load.realtime;
    };

    Figures bare, load;
    measure(opt.rateHz, bare, load);
    out.section("servo loop at " + hz(opt.rateHz) + " under load: the engine carving and re-meshing (" +
                std::to_string(int(load.segments)) + " live segments per run)");
    out.add("haptics.rate_hz", load.rate, "Hz", "target >= 999 Hz at 1 kHz");
    out.add("haptics.period_error_us.p50", load.p50, "us");
    out.add("haptics.period_error_us.p99", load.p99, "us", "target <= 100 us, within 25 us of bare");
    out.add("haptics.period_error_us.p999", load.p999, "us", "target <= 250 us");
    out.add("haptics.period_error_us.max", load.max, "us");
    out.add("haptics.force_us.p50", load.force50, "us");
    out.add("haptics.force_us.p999", load.force999, "us", "target <= 5 us");
    out.add("haptics.missed_deadlines", load.missed, "", "fraction of ticks more than a period late; target <= 0.0005");
    out.add("haptics.force_us.alone.p50", quantile(alone, 0.5), "us", "the same update back to back, no servo thread");
    out.add("haptics.force_us.alone.p99", quantile(alone, 0.99), "us");
    out.add("haptics.force_us.alone.p999", quantile(alone, 0.999), "us", "every update does the same work: the tail is the vCPU");
    out.add("haptics.engine_segments", load.segments, "segments", "live segments applied per run");
    out.section("servo loop at " + hz(opt.rateHz) + " bare: nothing else running (the machine's timer floor)");
    out.add("haptics.bare.rate_hz", bare.rate, "Hz");
    out.add("haptics.bare.period_error_us.p50", bare.p50, "us");
    out.add("haptics.bare.period_error_us.p99", bare.p99, "us");
    out.add("haptics.bare.period_error_us.p999", bare.p999, "us");
    out.add("haptics.bare.period_error_us.max", bare.max, "us");
    out.add("haptics.bare.force_us.p999", bare.force999, "us");
    out.add("haptics.bare.missed_deadlines", bare.missed, "");
    if (opt.highRateHz > 0.0) {
        Figures bare4, load4;
        measure(opt.highRateHz, bare4, load4);
        out.section("servo loop at " + hz(opt.highRateHz) + ", under load and bare");
        out.add("haptics.rate_hz.4k", load4.rate, "Hz", "target >= 3996 Hz at 4 kHz");
        out.add("haptics.period_error_us.4k.p50", load4.p50, "us");
        out.add("haptics.period_error_us.4k.p99", load4.p99, "us", "target <= 100 us");
        out.add("haptics.period_error_us.4k.p999", load4.p999, "us");
        out.add("haptics.period_error_us.4k.max", load4.max, "us");
        out.add("haptics.force_us.4k.p999", load4.force999, "us");
        out.add("haptics.missed_deadlines.4k", load4.missed, "");
        out.add("haptics.bare.rate_hz.4k", bare4.rate, "Hz");
        out.add("haptics.bare.period_error_us.4k.p99", bare4.p99, "us");
        out.add("haptics.bare.period_error_us.4k.max", bare4.max, "us");
    }
    out.section("real-time priority");
    out.add("haptics.realtime_priority", realtime ? 1.0 : 0.0, "", realtime ? "SCHED_FIFO granted" : "SCHED_FIFO refused: figures without it");
    out.add("haptics.spin_us", double(opt.spinUs), "us", "busy-wait before each deadline (at most a quarter period)");
    return 0;
}

}  // namespace kizamu::bench
