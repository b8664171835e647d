// SPDX-License-Identifier: Apache-2.0
/// @file sample_queue_test.cpp
/// @brief SampleQueue on one thread: FIFO order, capacity, wrap-around, the pending buffer's
/// hand-over order, simplification when the ring is full (button edges, the first and the last
/// sample kept, merged samples within the tolerance), coarsening, refusal, and no allocation
/// on the producer's or the consumer's side. The two-thread test is in tests/concurrency/.
#include "engine/sample_queue.h"
#include "tests/util/counting_allocator.h"
#include "tests/util/sample_path_check.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

namespace kizamu::engine {
namespace {

ToolSample sampleAt(int64_t i, uint32_t buttons = 0) {
    ToolSample s;
    s.timeNs = i * 250'000;
    s.posWorld = glm::dvec3(1e-3 * double(i), 0.0, 0.0);
    s.buttons = buttons;
    return s;
}

/// A zigzag whose corners are 1 mm apart: no sample can merge at the default tolerances.
ToolSample zigzagAt(int64_t i, uint32_t buttons = 0) {
    ToolSample s = sampleAt(i, buttons);
    s.posWorld.y = (i % 2) ? 1e-3 : 0.0;
    return s;
}

/// Everything handed over and pending, drained in order (flushing between drains).
std::vector<ToolSample> drainEverything(SampleQueue& q) {
    std::vector<ToolSample> out, buf(1000);
    for (;;) {
        const bool allHanded = q.flush();
        const std::size_t n = q.drain(buf.data(), buf.size());
        out.insert(out.end(), buf.begin(), buf.begin() + std::ptrdiff_t(n));
        if (allHanded && n == 0 && q.sizeApprox() == 0) return out;
    }
}

TEST(SampleQueue, RejectsBadSettings) {
    SampleQueueSettings s;
    s.capacity = 2048;
    EXPECT_THROW(SampleQueue{s}, std::invalid_argument);
    s.capacity = 5000;
    EXPECT_THROW(SampleQueue{s}, std::invalid_argument);
    s = {};
    s.pendingCapacity = 3;
    EXPECT_THROW(SampleQueue{s}, std::invalid_argument);
    s = {};
    s.positionTolerance = -1.0;
    EXPECT_THROW(SampleQueue{s}, std::invalid_argument);
    s = {};
    s.angleTolerance = NAN;
    EXPECT_THROW(SampleQueue{s}, std::invalid_argument);
    EXPECT_EQ(SampleQueue().capacity(), SampleQueue::kMinCapacity);
}

TEST(SampleQueue, FifoOrderAndCapacity) {
    SampleQueue q;
    for (int64_t i = 0; i < 4096; ++i) ASSERT_TRUE(q.push(sampleAt(i)));
    EXPECT_EQ(q.sizeApprox(), 4096u);  // one second at 4 kHz fits
    EXPECT_EQ(q.pendingCount(), 0u);
    ASSERT_TRUE(q.push(sampleAt(4096)));  // the ring is full: it waits
    EXPECT_EQ(q.pendingCount(), 1u);
    std::vector<ToolSample> out(5000);
    ASSERT_EQ(q.drain(out.data(), out.size()), 4096u);
    for (int64_t i = 0; i < 4096; ++i) ASSERT_EQ(out[std::size_t(i)].timeNs, sampleAt(i).timeNs);
    EXPECT_EQ(q.drain(out.data(), out.size()), 0u);  // the pending one is not handed over yet
    EXPECT_TRUE(q.flush());
    ASSERT_EQ(q.drain(out.data(), out.size()), 1u);
    EXPECT_EQ(out[0].timeNs, sampleAt(4096).timeNs);
    EXPECT_EQ(q.stats().merged, 0u);
}

TEST(SampleQueue, WrapsAroundInOrder) {
    SampleQueue q;
    std::vector<ToolSample> out(4096);
    int64_t pushed = 0, taken = 0;
    for (int round = 0; round < 40; ++round) {
        const int64_t n = 1 + (round * 997) % 4000;
        for (int64_t i = 0; i < n; ++i) ASSERT_TRUE(q.push(sampleAt(pushed++)));
        // Drain in small uneven pieces so reads straddle the end of the ring.
        while (taken < pushed) {
            const std::size_t got = q.drain(out.data(), std::size_t(1 + (taken * 31) % 700));
            ASSERT_GT(got, 0u);
            for (std::size_t k = 0; k < got; ++k)
                ASSERT_EQ(out[k].timeNs, sampleAt(taken++).timeNs);
        }
    }
    EXPECT_GT(pushed, int64_t(3 * 4096));
    // popAll takes everything handed over, in order.
    for (int64_t i = 0; i < 3000; ++i) ASSERT_TRUE(q.push(sampleAt(pushed++)));
    const std::size_t seen =
        q.popAll([&](const ToolSample& s) { EXPECT_EQ(s.timeNs, sampleAt(taken++).timeNs); });
    EXPECT_EQ(seen, 3000u);
    EXPECT_EQ(q.sizeApprox(), 0u);
    EXPECT_EQ(q.pendingCount(), 0u);
}

TEST(SampleQueue, PendingSamplesAreHandedOverFirstAndInOrder) {
    SampleQueueSettings settings;
    settings.pendingCapacity = 64;
    SampleQueue q(settings);
    int64_t i = 0;
    for (; i < 4096; ++i) ASSERT_TRUE(q.push(zigzagAt(i)));
    for (; i < 4096 + 40; ++i) ASSERT_TRUE(q.push(zigzagAt(i)));
    EXPECT_EQ(q.pendingCount(), 40u);  // a zigzag cannot merge
    std::vector<ToolSample> out(8192);
    ASSERT_EQ(q.drain(out.data(), 10), 10u);
    // The next push first hands over 10 pending samples, then waits behind the other 30.
    ASSERT_TRUE(q.push(zigzagAt(i++)));
    EXPECT_EQ(q.pendingCount(), 31u);
    ASSERT_EQ(q.drain(out.data(), 100), 100u);
    EXPECT_TRUE(q.flush());
    EXPECT_EQ(q.pendingCount(), 0u);
    const std::vector<ToolSample> rest = drainEverything(q);
    ASSERT_EQ(rest.size(), 4096u + 41u - 110u);
    for (std::size_t k = 0; k < rest.size(); ++k)
        ASSERT_EQ(rest[k].timeNs, zigzagAt(int64_t(110 + k)).timeNs);
    EXPECT_EQ(q.stats().merged, 0u);
    EXPECT_EQ(q.coarsening(), 0);
}

TEST(SampleQueue, StraightRunMergesToItsEnds) {
    SampleQueueSettings settings;
    settings.pendingCapacity = 16;
    SampleQueue q(settings);
    std::vector<ToolSample> pushed;
    for (int64_t i = 0; i < 4096 + 1000; ++i) {
        pushed.push_back(sampleAt(i));
        ASSERT_TRUE(q.push(pushed.back()));
    }
    // The pending run is one straight line: only its oldest and its latest sample wait.
    EXPECT_EQ(q.pendingCount(), 2u);
    EXPECT_EQ(q.stats().merged, 998u);
    EXPECT_EQ(q.coarsening(), 0);
    const test::DeliveredReport r = test::checkDelivered(pushed, drainEverything(q), settings, 0);
    EXPECT_EQ(r.error, "");
    EXPECT_EQ(r.kept, 4096u + 2u);
}

TEST(SampleQueue, FullQueueSimplificationKeepsEdgesAndStaysWithinTolerance) {
    // The ring fills and nothing is drained for 20 s of a smooth path with 8 strokes: the
    // pending buffer holds it all, simplified; at the default size (512) without coarsening, in a
    // small one with a few doublings.
    for (const std::size_t pendingCapacity :
         {SampleQueueSettings{}.pendingCapacity, std::size_t(128)}) {
        SampleQueueSettings settings;
        settings.pendingCapacity = pendingCapacity;
        SampleQueue q(settings);
        const std::vector<ToolSample> pushed = test::smoothToolPath(4096 + 80000, 10000, 8000);
        for (const ToolSample& s : pushed) ASSERT_TRUE(q.push(s));
        EXPECT_GT(q.stats().merged, 70000u);
        EXPECT_EQ(q.stats().refused, 0u);
        const int k = q.stats().maxCoarsening;
        if (pendingCapacity != 128)
            EXPECT_EQ(k, 0);
        else
            EXPECT_TRUE(k > 0 && k <= 6) << "coarsening " << k;  // 5 when written (3.2 mm)
        const test::DeliveredReport r =
            test::checkDelivered(pushed, drainEverything(q), settings, k);
        EXPECT_EQ(r.error, "");
        EXPECT_EQ(q.coarsening(), 0);  // everything handed over: back to the settings' tolerances
        std::printf("pending %zu: kept %zu of %zu; worst %.3g m, %.3g rad, %.3g; coarsening %d\n",
                    pendingCapacity, r.kept, pushed.size(), r.worstPosition, r.worstAngle,
                    r.worstStrength, k);
    }
}

TEST(SampleQueue, WithoutCoarseningTheSettingsToleranceHolds) {
    // A large pending buffer: the smooth path fits at the settings' tolerances (k = 0).
    SampleQueueSettings settings;
    settings.pendingCapacity = 8192;
    SampleQueue q(settings);
    const std::vector<ToolSample> pushed = test::smoothToolPath(4096 + 40000);
    for (const ToolSample& s : pushed) ASSERT_TRUE(q.push(s));
    ASSERT_EQ(q.stats().maxCoarsening, 0);
    const test::DeliveredReport r = test::checkDelivered(pushed, drainEverything(q), settings, 0);
    EXPECT_EQ(r.error, "");
    EXPECT_GT(r.merged, 30000u);
}

TEST(SampleQueue, TurningInPlaceIsKept) {
    // The position never moves but the tool turns: the orientation bound keeps the turn.
    SampleQueueSettings settings;
    SampleQueue q(settings);
    std::vector<ToolSample> pushed;
    for (int64_t i = 0; i < 4096 + 4000; ++i) {
        ToolSample s;
        s.timeNs = i * 250'000;
        const double t = double(i) / 4000.0;
        s.orientation =
            glm::quat(glm::angleAxis(0.5 * std::sin(5.0 * t), glm::dvec3(0.0, 0.0, 1.0)));
        pushed.push_back(s);
        ASSERT_TRUE(q.push(s));
    }
    const test::DeliveredReport r = test::checkDelivered(pushed, drainEverything(q), settings, 0);
    EXPECT_EQ(r.error, "");
    EXPECT_GT(r.kept, 4096u + 20u);  // not merged to a single segment
    EXPECT_GT(r.merged, 1000u);
}

TEST(SampleQueue, CoarseningDoublesAndResets) {
    SampleQueueSettings settings;
    settings.pendingCapacity = 8;
    SampleQueue q(settings);
    for (int64_t i = 0; i < 4096; ++i) ASSERT_TRUE(q.push(sampleAt(i)));
    // Corners growing 0.15 mm, 0.3 mm, ...: each time the buffer fills, a coarser tolerance.
    std::vector<ToolSample> pushed;
    for (int64_t i = 0; i < 4096; ++i) pushed.push_back(sampleAt(i));
    for (int64_t i = 0; i < 40; ++i) {
        ToolSample s = sampleAt(4096 + i);
        s.posWorld.y = (i % 2) ? 1.5e-4 * double(1 + i / 8) : 0.0;
        pushed.push_back(s);
        ASSERT_TRUE(q.push(s));
        EXPECT_LE(q.pendingCount(), 8u);
    }
    EXPECT_GT(q.coarsening(), 0);
    EXPECT_GE(q.stats().coarsenings, 2u);
    const int k = q.stats().maxCoarsening;
    const test::DeliveredReport r = test::checkDelivered(pushed, drainEverything(q), settings, k);
    EXPECT_EQ(r.error, "");
    EXPECT_GT(r.merged, 20u);
    EXPECT_GT(r.worstPosition, settings.positionTolerance);  // the coarser tolerance was used
    EXPECT_EQ(q.coarsening(), 0);
}

TEST(SampleQueue, ButtonEdgesAreNeverMergedAndRefusalKeepsTheState) {
    SampleQueueSettings settings;
    settings.pendingCapacity = 8;
    SampleQueue q(settings);
    std::vector<ToolSample> accepted;
    for (int64_t i = 0; i < 4096; ++i) {
        accepted.push_back(sampleAt(i));
        ASSERT_TRUE(q.push(accepted.back()));
    }
    // Every sample presses or releases: all are pinned, none can merge.
    int64_t i = 4096;
    for (; i < 4096 + 8; ++i) {
        accepted.push_back(sampleAt(i, uint32_t(i % 2)));
        ASSERT_TRUE(q.push(accepted.back()));
    }
    EXPECT_EQ(q.pendingCount(), 8u);
    EXPECT_FALSE(q.push(sampleAt(i++, 1u)));  // refused, nothing dropped
    EXPECT_FALSE(q.push(sampleAt(i++, 0u)));
    EXPECT_EQ(q.stats().refused, 2u);
    EXPECT_EQ(q.stats().merged, 0u);
    // Room again: the next sample with other buttons than the last accepted one is the edge.
    std::vector<ToolSample> out(4096);
    ASSERT_EQ(q.drain(out.data(), 100), 100u);
    accepted.push_back(sampleAt(i++, 0u));  // the last accepted sample held 1: an edge
    ASSERT_TRUE(q.push(accepted.back()));
    std::vector<ToolSample> delivered(out.begin(), out.begin() + 100);
    const std::vector<ToolSample> rest = drainEverything(q);
    delivered.insert(delivered.end(), rest.begin(), rest.end());
    ASSERT_EQ(delivered.size(), accepted.size());
    const test::DeliveredReport r = test::checkDelivered(accepted, delivered, settings, 0);
    EXPECT_EQ(r.error, "");
}

TEST(SampleQueue, PushFlushAndDrainAllocateNothing) {
    SampleQueueSettings settings;
    settings.pendingCapacity = 16;
    SampleQueue q(settings);
    const std::vector<ToolSample> path = test::smoothToolPath(60000, 3000, 2000);
    std::vector<ToolSample> out(2048);
    const test::AllocationCounts before = test::threadAllocationCounts();
    std::size_t drained = 0;
    for (std::size_t i = 0; i < path.size(); ++i) {
        q.push(path[i]);  // the ring fills, the pending buffer fills and coarsens
        if (i % 7000 == 6999) drained += q.drain(out.data(), out.size());
        if (i % 9000 == 8999) q.flush();
    }
    while (!q.flush() || q.sizeApprox() > 0) drained += q.drain(out.data(), out.size());
    drained += q.popAll([](const ToolSample&) {});
    const test::AllocationCounts after = test::threadAllocationCounts();
    EXPECT_EQ(after.allocations, before.allocations);
    EXPECT_EQ(after.frees, before.frees);
    EXPECT_GT(q.stats().coarsenings, 0u);  // every path was taken
    EXPECT_EQ(drained + q.stats().merged + q.stats().refused, path.size());
}

}  // namespace
}  // namespace kizamu::engine
