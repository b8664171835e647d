// SPDX-License-Identifier: Apache-2.0
// The pool hands out indices by an atomic ticket that names its loop: every index runs exactly
// once, a worker waking late never runs an old loop's function on a new loop's index, and the
// first exception reaches the caller after the loop. Run under ThreadSanitizer (scripts/test).
#include "util/thread_pool.h"

#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>
#include <vector>

using kizamu::util::ThreadPool;

TEST(ThreadPool, EveryIndexRunsOnceInManyShortLoops) {
    ThreadPool pool(4);
    // Many loops of a few tiny items: workers often wake after their loop is over.
    for (std::size_t loop = 0; loop < 20000; ++loop) {
        const std::size_t n = 1 + loop % 7;
        std::vector<std::atomic<int>> runs(n);
        pool.parallelFor(n, [&](std::size_t i) { runs[i].fetch_add(1, std::memory_order_relaxed); });
        for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(runs[i].load(), 1) << "loop " << loop << " index " << i;
    }
}

TEST(ThreadPool, ResultsWrittenByWorkersAreVisibleAfterTheLoop) {
    ThreadPool pool(2);
    std::vector<uint64_t> out(100000);  // plain writes: the loop's end must publish them
    for (int round = 0; round < 5; ++round) {
        pool.parallelFor(out.size(), [&](std::size_t i) { out[i] = i * i + uint64_t(round); });
        for (std::size_t i = 0; i < out.size(); ++i) ASSERT_EQ(out[i], i * i + uint64_t(round));
    }
}

TEST(ThreadPool, FirstExceptionReachesTheCallerAndThePoolGoesOn) {
    ThreadPool pool(3);
    std::atomic<int> ran{0};
    EXPECT_THROW(pool.parallelFor(64,
                                  [&](std::size_t i) {
                                      ran.fetch_add(1);
                                      if (i % 16 == 3) throw std::runtime_error("item failed");
                                  }),
                 std::runtime_error);
    EXPECT_EQ(ran.load(), 64);  // the other items still ran
    std::atomic<int> after{0};
    pool.parallelFor(10, [&](std::size_t) { after.fetch_add(1); });
    EXPECT_EQ(after.load(), 10);
}

TEST(ThreadPool, EmptyAndSingleLoops) {
    ThreadPool pool(2);
    int calls = 0;
    pool.parallelFor(0, [&](std::size_t) { ++calls; });
    EXPECT_EQ(calls, 0);
    kizamu::util::parallelFor(&pool, 1, [&](std::size_t i) { calls += int(i) + 1; });
    EXPECT_EQ(calls, 1);
}
