// SPDX-License-Identifier: Apache-2.0
// The pool hands out indices by an atomic ticket that names its loop: every index runs exactly
// once, a worker waking late never runs an old loop's function on a new loop's index, workers
// do take items, a caller asleep on the last item is woken, and the first exception (from any
// thread) reaches the caller after the loop. Run under ThreadSanitizer (scripts/test).
#include "util/thread_pool.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>
#include <vector>

using kizamu::util::ThreadPool;
using namespace std::chrono_literals;

namespace {

/// Waits up to 2 s for `flag`; true if it came.
bool waitFor(const std::atomic<bool>& flag) {
    const auto until = std::chrono::steady_clock::now() + 2s;
    while (!flag.load() && std::chrono::steady_clock::now() < until) std::this_thread::sleep_for(50us);
    return flag.load();
}

}  // namespace

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

TEST(ThreadPool, WorkersTakeItems) {
    ThreadPool pool(2);
    const std::thread::id caller = std::this_thread::get_id();
    std::atomic<bool> workerRan{false}, waited{false};
    // The caller's first item waits for a worker to run one: a pool whose workers never take
    // work leaves it alone.
    pool.parallelFor(16, [&](std::size_t) {
        if (std::this_thread::get_id() != caller) workerRan = true;
        else if (!waited.exchange(true)) waitFor(workerRan);
    });
    EXPECT_TRUE(workerRan.load());
}

TEST(ThreadPool, CallerSleepingOnTheLastItemIsWoken) {
    ThreadPool pool(2);
    const std::thread::id caller = std::this_thread::get_id();
    // The worker's item outlasts the caller's polling (500 us), so the caller sleeps on the
    // pool's condition variable and must be woken by the worker: a lost wake-up hangs here
    // (the test's timeout fails it).
    for (int loop = 0; loop < 100; ++loop) {
        std::atomic<bool> workerStarted{false};
        std::atomic<int> done{0};
        pool.parallelFor(2, [&](std::size_t) {
            if (std::this_thread::get_id() != caller) {
                workerStarted = true;
                std::this_thread::sleep_for(2ms);
            } else {
                waitFor(workerStarted);
            }
            done.fetch_add(1);
        });
        ASSERT_EQ(done.load(), 2) << "loop " << loop;
    }
}

TEST(ThreadPool, ExceptionOnAWorkerReachesTheCaller) {
    ThreadPool pool(2);
    const std::thread::id caller = std::this_thread::get_id();
    std::atomic<bool> workerRan{false}, waited{false};
    EXPECT_THROW(pool.parallelFor(8,
                                  [&](std::size_t) {
                                      if (std::this_thread::get_id() != caller) {
                                          workerRan = true;
                                          throw std::runtime_error("worker item failed");
                                      }
                                      if (!waited.exchange(true)) waitFor(workerRan);
                                  }),
                 std::runtime_error);
    EXPECT_TRUE(workerRan.load());
}

TEST(ThreadPool, PoolsEndWhileWorkersPollOrSleep) {
    // Destroyed right after a loop (workers polling) or after a pause (workers asleep).
    for (int i = 0; i < 200; ++i) {
        ThreadPool pool(3);
        std::atomic<int> runs{0};
        pool.parallelFor(4, [&](std::size_t) { runs.fetch_add(1); });
        ASSERT_EQ(runs.load(), 4);
        if (i % 2) std::this_thread::sleep_for(1ms);
    }
}

TEST(ThreadPool, HeaviestFirstRunsEveryItemOnceUnderItsOwnIndex) {
    // Items handed out heaviest first still reach fn under their own index, once each; serially
    // (no pool) they run in plain order.
    ThreadPool pool(3);
    auto weight = [](std::size_t i) { return (i * 7919) % 13; };
    for (std::size_t n : {0, 1, 2, 5, 64, 1000}) {
        std::vector<std::atomic<int>> runs(n);
        std::vector<std::atomic<std::size_t>> seen(n);
        kizamu::util::parallelForHeaviestFirst(&pool, n, weight, [&](std::size_t i) {
            runs[i].fetch_add(1, std::memory_order_relaxed);
            seen[i].store(weight(i), std::memory_order_relaxed);
        });
        for (std::size_t i = 0; i < n; ++i) {
            ASSERT_EQ(runs[i].load(), 1) << "n " << n << " index " << i;
            ASSERT_EQ(seen[i].load(), weight(i)) << "n " << n << " index " << i;
        }
    }
    std::vector<std::size_t> order;
    kizamu::util::parallelForHeaviestFirst(nullptr, 6, weight, [&](std::size_t i) { order.push_back(i); });
    EXPECT_EQ(order, (std::vector<std::size_t>{0, 1, 2, 3, 4, 5}));
}

TEST(ThreadPool, HomesRunEveryItemOnce) {
    // Homes beyond the thread count wrap; serially (no pool) items run in plain order.
    ThreadPool pool(3);
    for (std::size_t loop = 0; loop < 2000; ++loop) {
        const std::size_t n = loop % 37;
        std::vector<std::atomic<int>> runs(n);
        kizamu::util::parallelForHomes(&pool, n, [&](std::size_t i) { return (i * 7 + loop) % 5; },
                                       [&](std::size_t i) { runs[i].fetch_add(1, std::memory_order_relaxed); });
        for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(runs[i].load(), 1) << "loop " << loop << " index " << i;
    }
    std::vector<std::size_t> order;
    kizamu::util::parallelForHomes(nullptr, 5, [](std::size_t i) { return 4 - i; }, [&](std::size_t i) { order.push_back(i); });
    EXPECT_EQ(order, (std::vector<std::size_t>{0, 1, 2, 3, 4}));
}

TEST(ThreadPool, HomesRunOnTheirThreadFirst) {
    // A thread takes its own items (home = its index) before anyone else's: in the order each
    // thread ran its items, none of its own comes after one of another's. Item 0 (home 0) holds
    // whoever runs it until the items of home 1 are done (or 2 s), so that usually the worker
    // runs those while the caller waits, and a thread that went to another home first would
    // take item 1 (home 0) ahead of its own. Which thread runs what is left to the scheduler.
    ThreadPool pool(2);
    EXPECT_EQ(ThreadPool::threadIndex(), 0u);
    auto homeOf = [](std::size_t i) { return i < 2 ? 0u : 1u; };
    for (int round = 0; round < 20; ++round) {
        constexpr std::size_t n = 9;
        std::vector<std::atomic<unsigned>> ranOn(n);
        std::vector<std::atomic<int>> ranAt(n), runs(n);
        std::atomic<int> clock{0}, homeOneDone{0};
        kizamu::util::parallelForHomes(&pool, n, homeOf, [&](std::size_t i) {
            ranOn[i].store(ThreadPool::threadIndex());
            ranAt[i].store(clock.fetch_add(1));
            runs[i].fetch_add(1);
            if (i == 0) {
                const auto until = std::chrono::steady_clock::now() + 2s;
                while (homeOneDone.load() < int(n - 2) && std::chrono::steady_clock::now() < until) std::this_thread::yield();
            } else if (homeOf(i) == 1) {
                homeOneDone.fetch_add(1);
            }
        });
        for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(runs[i].load(), 1) << "round " << round << " item " << i;
        for (unsigned thread = 0; thread < 2; ++thread) {
            int lastOwn = -1, firstForeign = int(n);
            for (std::size_t i = 0; i < n; ++i) {
                if (ranOn[i].load() != thread) continue;
                if (homeOf(i) == thread) lastOwn = std::max(lastOwn, ranAt[i].load());
                else firstForeign = std::min(firstForeign, ranAt[i].load());
            }
            EXPECT_LT(lastOwn, firstForeign) << "round " << round << " thread " << thread;
        }
    }
}

TEST(ThreadPool, HeaviestFirstOrdersByWeightAndTiesByIndex) {
    const std::vector<unsigned> w{3, 9, 0, 9, 5, 3};
    EXPECT_EQ(kizamu::util::heaviestFirst(w.size(), [&](std::size_t i) { return w[i]; }),
              (std::vector<std::size_t>{1, 3, 4, 0, 5, 2}));
    EXPECT_TRUE(kizamu::util::heaviestFirst(0, [](std::size_t) { return 1u; }).empty());
}

TEST(ThreadPool, EmptyAndSingleLoops) {
    ThreadPool pool(2);
    int calls = 0;
    pool.parallelFor(0, [&](std::size_t) { ++calls; });
    EXPECT_EQ(calls, 0);
    kizamu::util::parallelFor(&pool, 1, [&](std::size_t i) { calls += int(i) + 1; });
    EXPECT_EQ(calls, 1);
}
