// SPDX-License-Identifier: Apache-2.0
// The live engine with every thread it serves, under ThreadSanitizer (scripts/test): a pusher
// at 1 kHz (strokes with pauses between them), a haptic reader at 1 kHz, a mesh consumer, the
// edit thread, and the test's thread sending undo, redo and cancel at random times. Checked:
// readers see one consistent snapshot per guard and sequence numbers that never fall; at every
// quiet point (pusher between strokes, engine synced) the consumer's mirror equals the mesh of
// the published clay, compared canonically; the pusher and the haptic reader allocate nothing.
#include "engine/engine.h"

#include "adf/adf_file.h"
#include "adf/guarded_accessor.h"
#include "mesh/surface_nets.h"
#include "tests/util/counting_allocator.h"
#include "tests/util/mesh_check.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>
#include <random>
#include <thread>
#include <vector>

namespace kizamu {
namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

/// Quiet-point handshake between the pusher (which pauses between strokes), the consumer
/// (which hands its mirror over) and the checking thread.
struct Quiet {
    std::atomic<int> wanted{0};          ///< quiet points the pusher asked for
    std::atomic<int> consumerParked{0};  ///< quiet points the consumer has parked for
    std::atomic<int> done{0};            ///< quiet points checked
};

int64_t nowNs() { return std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now().time_since_epoch()).count(); }

TEST(EngineStress, AllThreadsTogetherThousandsOfSegmentsWithUndoRedoCancel) {
    engine::EngineSettings settings;
    settings.start.domain.maxLevel = 6;
    settings.start.domain.tileSpanLevels = 3;  // 8 x 8 x 8 tiles: a segment rebuilds a few
    settings.start.start.kind = sculpt::Shape::Kind::Box;
    settings.start.start.centre = {0.5, 0.5, 0.4};
    settings.start.start.halfSize = {0.35, 0.35, 0.1};
    settings.threads = 2;
    settings.correctAfterIdle = 0ms;  // no idle corrections: a quiet point compares a fixed clay
    engine::Engine e(settings);
    {
        engine::ToolSettings tool;
        tool.tool.radius = 0.03;
        ASSERT_TRUE(e.setTool(tool).get().ok);
    }
    // Strokes in groups of kQuietEvery until kSegments segments were applied (a slower machine,
    // or a sanitizer, cuts fewer and longer segments) or kMaxStrokes.
    constexpr uint64_t kSegments = 2000;
    constexpr int kMaxStrokes = 1200;
    constexpr int kQuietEvery = 6;
    std::atomic<bool> pushing{true};
    std::atomic<int> strokesPushed{0};
    std::atomic<double> toolX{0.5};
    Quiet quiet;

    // ---- pusher: 1 kHz, strokes of 100..199 samples, 10 released samples between them ----
    test::AllocationCounts pusherDuring{};
    std::thread pusher([&] {
        std::mt19937 rng(7);
        std::vector<int> lengths(kMaxStrokes);
        for (int& l : lengths) l = 100 + int(rng() % 100);
        engine::SampleQueue& q = e.samples();
        const test::AllocationCounts before = test::threadAllocationCounts();
        auto tick = Clock::now();
        int64_t i = 0;
        for (int k = 0; k < kMaxStrokes && !(k % kQuietEvery == 0 && e.stats().segments >= kSegments); ++k) {
            const double y = 0.25 + 0.5 * double(k % 9) / 8.0;
            for (int j = 0; j < lengths[std::size_t(k)] + 10; ++j, ++i) {
                tick += 1ms;
                std::this_thread::sleep_until(tick);
                engine::ToolSample s;
                s.timeNs = nowNs();
                const double u = double(j) / double(lengths[std::size_t(k)]);
                s.posWorld = {0.25 + 0.5 * std::min(u, 1.0), y + 0.05 * std::sin(9.0 * u), 0.5};
                s.buttons = j < lengths[std::size_t(k)] ? engine::kButtonPrimary : 0u;
                toolX.store(s.posWorld.x, std::memory_order_relaxed);
                while (!q.push(s)) std::this_thread::yield();
            }
            while (!q.flush()) std::this_thread::yield();
            if ((k + 1) % kQuietEvery == 0) {
                const int n = quiet.wanted.fetch_add(1) + 1;
                while (quiet.done.load() < n) std::this_thread::sleep_for(1ms);
                tick = Clock::now();
            }
            strokesPushed.store(k + 1);
        }
        const test::AllocationCounts after = test::threadAllocationCounts();
        pusherDuring = {after.allocations - before.allocations, after.frees - before.frees};
        pushing.store(false);
    });

    // ---- haptic reader: 1 kHz, distance and gradient under the tool ----
    struct HapticReport {
        uint64_t ticks = 0, regressions = 0, inconsistent = 0;
        test::AllocationCounts during{};
    } haptic;
    std::thread reader([&] {
        adf::SnapshotStore::Reader r(e.snapshots());
        std::optional<adf::GuardedAccessor> acc;
        {
            const auto g = r.acquire();
            acc.emplace(g);
        }
        const test::AllocationCounts before = test::threadAllocationCounts();
        uint64_t last = 0;
        auto tick = Clock::now();
        while (pushing.load(std::memory_order_relaxed)) {
            tick += 1ms;
            std::this_thread::sleep_until(tick);
            const auto g = r.acquire();
            if (g.sequence() < last) ++haptic.regressions;
            last = g.sequence();
            const glm::vec3 p(float(toolX.load(std::memory_order_relaxed)), 0.5f, 0.5f);
            const adf::Sample a = acc->sample(g, p);
            const adf::Sample b = g.adf().sample(p);  // uncached, the same snapshot
            if (a.distance != b.distance || a.gradient != b.gradient) ++haptic.inconsistent;
            ++haptic.ticks;
        }
        const test::AllocationCounts after = test::threadAllocationCounts();
        haptic.during = {after.allocations - before.allocations, after.frees - before.frees};
    });

    // ---- mesh consumer: takes deltas every few ms, resyncs when it missed one ----
    mesh::MeshMirror mirror;
    std::atomic<uint64_t> applied{0}, resyncs{0};
    std::thread consumer([&] {
        int parked = 0;
        while (pushing.load() || quiet.consumerParked.load() < quiet.wanted.load()) {
            if (quiet.wanted.load() > parked) {  // hand the mirror to the checker until it is done
                quiet.consumerParked.store(++parked);
                while (quiet.done.load() < parked) std::this_thread::sleep_for(1ms);
                continue;
            }
            if (std::optional<mesh::MeshDelta> d = e.takeMeshDelta()) {
                if (mirror.apply(std::move(*d)))
                    applied.fetch_add(1);
                else {
                    resyncs.fetch_add(1);
                    e.requestFullMesh();
                }
            }
            std::this_thread::sleep_for(3ms);
        }
    });

    // ---- this thread: random undo / redo / cancel, and the quiet-point checks ----
    std::mt19937 rng(11);
    int checked = 0, commands = 0;
    while (pushing.load()) {
        if (quiet.wanted.load() > checked && quiet.consumerParked.load() > checked) {
            ASSERT_TRUE(e.sync().get().ok);
            // The consumer is parked: its mirror is this thread's until done is raised.
            for (int tries = 0; tries < 2000; ++tries) {
                if (std::optional<mesh::MeshDelta> d = e.takeMeshDelta()) {
                    if (!mirror.apply(std::move(*d))) {
                        e.requestFullMesh();
                        ASSERT_TRUE(e.sync().get().ok);
                        continue;
                    }
                }
                if (mirror.generation() > 0) break;
            }
            adf::SnapshotStore::Reader r(e.snapshots());
            std::vector<std::byte> bytes;
            {
                const auto g = r.acquire();
                bytes = adf::encodeAdf(g.adf());
            }
            mesh::MeshBuffers want = mesh::meshAdf(adf::decodeAdf(std::string(reinterpret_cast<const char*>(bytes.data()), bytes.size()), "published"));
            want.colours.clear();
            EXPECT_TRUE(test::canonical(mirror.flatten()) == test::canonical(want)) << "quiet point " << checked;
            quiet.done.store(++checked);
            continue;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(50 + rng() % 200));
        switch (rng() % 5) {
        case 0: e.undo(); break;
        case 1: e.redo(); break;
        case 2: e.cancelStroke(); break;
        default: continue;
        }
        ++commands;
    }
    pusher.join();
    reader.join();
    consumer.join();

    const engine::EngineStats st = e.stats();
    std::printf("[ stress ] %llu segments, %llu strokes, %llu cancelled, %llu mesh deltas (%llu applied, %llu resyncs), "
                "%d commands, %d quiet points, %llu haptic ticks, %d strokes pushed\n",
                (unsigned long long)st.segments, (unsigned long long)st.strokes, (unsigned long long)st.cancelled,
                (unsigned long long)st.meshUpdates, (unsigned long long)applied.load(), (unsigned long long)resyncs.load(),
                commands, checked, (unsigned long long)haptic.ticks, strokesPushed.load());
    EXPECT_GE(st.segments, kSegments);
    EXPECT_EQ(checked, strokesPushed.load() / kQuietEvery);
    EXPECT_GT(commands, 10);
    EXPECT_EQ(haptic.regressions, 0u);
    EXPECT_EQ(haptic.inconsistent, 0u);
    EXPECT_GT(haptic.ticks, 1000u);
    EXPECT_EQ(haptic.during.allocations, 0u);
    EXPECT_EQ(haptic.during.frees, 0u);
    EXPECT_EQ(pusherDuring.allocations, 0u);
    EXPECT_EQ(pusherDuring.frees, 0u);
    for (const std::string& n : e.takeNotices()) std::printf("[ stress ] notice: %s\n", n.c_str());
}

}  // namespace
}  // namespace kizamu
