// SPDX-License-Identifier: Apache-2.0
/// @file live_bench.cpp
/// @brief runLiveBench: SampleQueue::push timed one by one, on a tool path sampled at 4 kHz.
///
/// Each push is timed alone between two steady_clock reads (the percentiles include one clock
/// read, about 20 ns): the figure that matters is the tail a servo tick sees, which batching
/// would hide. Pushes run back to back, faster than any device, so the consumer (another
/// thread calling popAll) is as busy as it can be.
#include "bench/live_bench.h"

#include "bench/figures.h"
#include "bench/live_engine_bench.h"
#include "bench/timing.h"
#include "engine/sample_queue.h"

#include <glm/gtc/quaternion.hpp>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <thread>
#include <vector>

namespace kizamu::bench {

namespace {

/// Sample i of a hand moving at about 0.2 m/s on a 3 cm helix, turning slowly, a stroke held
/// for 2000 samples out of every 2500.
engine::ToolSample helixSample(std::size_t i) {
    const double t = double(i) / 4000.0;  // s, 4 kHz
    engine::ToolSample s;
    s.timeNs = int64_t(i) * 250'000;
    s.posWorld = glm::dvec3(0.03 * std::cos(6.0 * t), 0.03 * std::sin(6.0 * t), 0.01 * t);
    s.orientation = glm::quat(glm::angleAxis(0.5 * t, glm::dvec3(0.0, 0.0, 1.0)));
    s.strength = float(0.5 + 0.4 * std::sin(t));
    s.buttons = i % 2500 >= 500 ? engine::kButtonPrimary : 0u;
    return s;
}

/// Pushes path[first..] into `q`, each timed alone; µs per push into `out`.
void timedPushes(engine::SampleQueue& q, const std::vector<engine::ToolSample>& path,
                 std::size_t first, std::vector<double>& out) {
    out.clear();
    out.reserve(path.size() - first);
    for (std::size_t i = first; i < path.size(); ++i) {
        const auto t0 = std::chrono::steady_clock::now();
        q.push(path[i]);
        const auto t1 = std::chrono::steady_clock::now();
        out.push_back(std::chrono::duration<double, std::micro>(t1 - t0).count());
    }
}

double maxOf(const std::vector<double>& v) {
    double m = 0.0;
    for (const double x : v) m = std::max(m, x);
    return m;
}

}  // namespace

int runLiveBench(const LiveBenchOptions& opt) {
    FigureSink out(opt.json);
    if (!opt.json)
        std::printf(
            "kizamu bench live: SampleQueue push, each timed alone (includes one clock read), 4 "
            "kHz tool path\n");

    out.section("push with a consumer draining on another thread (" + std::to_string(opt.pushes) +
                " pushes)");
    std::vector<double> us;
    {
        engine::SampleQueue q;
        constexpr std::size_t kWarmUp = 10'000;  // the ring's pages and the code paths
        std::vector<engine::ToolSample> path(kWarmUp + opt.pushes);
        for (std::size_t i = 0; i < path.size(); ++i) path[i] = helixSample(i);
        std::atomic<bool> stop{false};
        std::thread consumer([&] {
            for (;;) {
                const bool last = stop.load(std::memory_order_acquire);
                const std::size_t got = q.popAll([](const engine::ToolSample&) {});
                if (last && got == 0) break;
                if (got == 0) std::this_thread::yield();
            }
        });
        for (std::size_t i = 0; i < kWarmUp; ++i) q.push(path[i]);
        timedPushes(q, path, kWarmUp, us);
        while (!q.flush()) std::this_thread::yield();
        stop.store(true, std::memory_order_release);
        consumer.join();
        out.add("live.push_us.p50", quantile(us, 0.5), "us");
        out.add("live.push_us.p99", quantile(us, 0.99), "us");
        out.add("live.push_us.p999", quantile(us, 0.999), "us", "budget 1 us");
        out.add("live.push_us.max", maxOf(us), "us", "includes preemption of the pushing thread");
        out.add("live.push_merged_fraction", double(q.stats().merged) / double(path.size()), "",
                "samples simplified away because the consumer fell a ring behind");
    }

    out.section("push into a full ring, nobody draining (" + std::to_string(opt.fullPushes) +
                " pushes): pending buffer, simplification, coarsening");
    {
        engine::SampleQueue q;
        std::size_t i = 0;
        for (; i < q.capacity(); ++i) q.push(helixSample(i));
        std::vector<engine::ToolSample> path(opt.fullPushes);
        for (std::size_t k = 0; k < path.size(); ++k) path[k] = helixSample(i + k);
        timedPushes(q, path, 0, us);
        out.add("live.push_full_us.p50", quantile(us, 0.5), "us");
        out.add("live.push_full_us.p999", quantile(us, 0.999), "us");
        out.add("live.push_full_us.max", maxOf(us), "us",
                "a coarsening pass over the pending buffer");
        out.add("live.push_full_pending", double(q.pendingCount()), "samples",
                "what " + std::to_string(opt.fullPushes) + " samples became");
        out.add("live.push_full_coarsening", double(q.stats().maxCoarsening), "k",
                "tolerances x 2^k");
    }
    if (!opt.levels.empty()) liveEngineFigures(out, {opt.levels, opt.placement, opt.repeats});
    return 0;
}

}  // namespace kizamu::bench
