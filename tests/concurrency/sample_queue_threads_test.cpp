// SPDX-License-Identifier: Apache-2.0
// SampleQueue across two threads: a producer pushes a smooth 4 kHz tool path with button
// presses as fast as it can (no sleeping, no pacing), the consumer drains in bursts of random
// size and now and then sleeps, so the ring fills and empties many times. What the consumer
// receives must be the pushed path within the tolerance in force (every button edge, in
// order), and the producer must allocate nothing. Run under ThreadSanitizer (scripts/test).
#include "engine/sample_queue.h"
#include "tests/util/counting_allocator.h"
#include "tests/util/sample_path_check.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <random>
#include <thread>
#include <vector>

using namespace kizamu;
using namespace std::chrono_literals;

namespace {

struct ProducerReport {
    uint64_t refused = 0;
    test::AllocationCounts before{}, after{};
};

/// The producer's loop: nothing in here may allocate (no gtest macros, no containers).
void produce(engine::SampleQueue& q, const std::vector<engine::ToolSample>& path,
             std::atomic<bool>& done, ProducerReport& out) {
    out.before = test::threadAllocationCounts();
    // A refusal (the pending buffer full of button edges: the consumer stalled while the
    // producer ran far ahead of any real 4 kHz device, which a loaded machine allows) is
    // counted and the sample pushed again once the consumer has made room; the delivered path
    // is then checked in full.
    for (const engine::ToolSample& s : path)
        while (!q.push(s)) {
            ++out.refused;
            std::this_thread::yield();
        }
    while (!q.flush()) std::this_thread::yield();  // the tail of the path, as room frees
    out.after = test::threadAllocationCounts();
    done.store(true, std::memory_order_release);
}

}  // namespace

TEST(SampleQueueThreads, BurstyConsumerGetsThePathWithinToleranceAndEveryEdge) {
    for (const std::size_t pendingCapacity :
         {engine::SampleQueueSettings{}.pendingCapacity, std::size_t(64)}) {
        engine::SampleQueueSettings settings;
        settings.pendingCapacity = pendingCapacity;
        engine::SampleQueue q(settings);
        const std::vector<engine::ToolSample> path = test::smoothToolPath(200'000);
        std::vector<engine::ToolSample> received;
        received.reserve(path.size());
        std::atomic<bool> done{false};
        ProducerReport report;

        std::thread producer([&] { produce(q, path, done, report); });
        std::minstd_rand rng(7);
        std::vector<engine::ToolSample> buf(4096);
        std::size_t bursts = 0;
        for (;;) {
            const bool last =
                done.load(std::memory_order_acquire);  // everything handed over before
            const std::size_t n = q.drain(buf.data(), 1 + rng() % buf.size());
            received.insert(received.end(), buf.begin(), buf.begin() + std::ptrdiff_t(n));
            if (last && n == 0) break;
            ++bursts;
            if (rng() % 8 == 0)
                std::this_thread::sleep_for(1ms);  // the edit thread busy with a stroke
            else
                std::this_thread::yield();
        }
        producer.join();

        const engine::SampleQueueStats& stats = q.stats();  // the producer has finished
        EXPECT_EQ(report.after.allocations, report.before.allocations) << "push/flush allocated";
        EXPECT_EQ(report.after.frees, report.before.frees) << "push/flush freed";
        EXPECT_EQ(received.size() + stats.merged, path.size());
        EXPECT_LT(stats.maxCoarsening, engine::SampleQueue::kMaxCoarsening);
        const test::DeliveredReport r =
            test::checkDelivered(path, received, settings, stats.maxCoarsening);
        EXPECT_EQ(r.error, "") << "pending capacity " << pendingCapacity;
        std::printf(
            "pending %zu: %zu bursts; delivered %zu of %zu, merged %llu, refused and pushed again %llu, "
            "coarsening up to %d (%llu times), worst %.3g m %.3g rad %.3g\n",
            pendingCapacity, bursts, received.size(), path.size(), (unsigned long long)stats.merged,
            (unsigned long long)report.refused,
            stats.maxCoarsening, (unsigned long long)stats.coarsenings, r.worstPosition,
            r.worstAngle, r.worstStrength);
    }
}
