// SPDX-License-Identifier: Apache-2.0
/// @file thread_pool_affinity_test.cpp
/// @brief ThreadPool sized from the affinity mask, and its workers kept on a given CPU set.
/// (The pool's loop semantics are tested in tests/concurrency/thread_pool_test.cpp.)
#include "util/cpu_set.h"
#include "util/thread_pool.h"

#include <gtest/gtest.h>

#include <pthread.h>
#include <sched.h>

#include <chrono>
#include <mutex>
#include <thread>

namespace kizamu::util {
namespace {

std::vector<int> maskOfThisThread() {
    cpu_set_t set;
    CPU_ZERO(&set);
    EXPECT_EQ(sched_getaffinity(0, sizeof set, &set), 0);
    std::vector<int> cpus;
    for (int c = 0; c < CPU_SETSIZE; ++c)
        if (CPU_ISSET(c, &set)) cpus.push_back(c);
    return cpus;
}

/// Runs `body` on a thread restricted to `cpus` (what `taskset -c` does to a process), so the
/// test runner's own mask is never changed.
template <class Body>
void underMask(const std::vector<int>& cpus, Body body) {
    std::thread([&] {
        cpu_set_t set;
        CPU_ZERO(&set);
        for (const int c : cpus) CPU_SET(c, &set);
        ASSERT_EQ(sched_setaffinity(0, sizeof set, &set), 0);
        body();
    }).join();
}

/// Each worker's mask as it sees it from inside an item, indexed by threadIndex().
std::vector<std::vector<int>> workerMasks(ThreadPool& pool) {
    std::vector<std::vector<int>> masks(pool.threadCount());
    std::mutex mutex;
    // Items long enough that every worker wakes and takes some before the caller runs out.
    for (int round = 0; round < 20; ++round) {
        pool.parallelFor(64, [&](std::size_t) {
            const unsigned me = ThreadPool::threadIndex();
            std::vector<int> mask = maskOfThisThread();
            {
                std::lock_guard lock(mutex);
                masks[me] = std::move(mask);
            }
            std::this_thread::sleep_for(std::chrono::microseconds(200));
        });
        bool all = true;
        for (unsigned k = 1; k < masks.size(); ++k) all = all && !masks[k].empty();
        if (all) break;
    }
    return masks;
}

TEST(ThreadPoolAffinity, DefaultSizeIsTheAffinityMask) {
    const std::vector<int> cpus = allowedCpus();
    {
        ThreadPool pool;
        EXPECT_EQ(pool.threadCount(), allowedCpuCount());
        EXPECT_TRUE(pool.workerCpus().empty());
        EXPECT_TRUE(pool.pinError().empty());
    }
    underMask({cpus.front()}, [] {
        ThreadPool pool(0);
        EXPECT_EQ(pool.threadCount(), 1u);
        pool.parallelFor(10, [](std::size_t) {});
    });
    if (cpus.size() >= 2) {
        underMask({cpus[0], cpus[1]}, [] {
            ThreadPool pool(0);
            EXPECT_EQ(pool.threadCount(), 2u);
        });
    }
    EXPECT_EQ(maskOfThisThread(), cpus);  // the runner's mask untouched
}

TEST(ThreadPoolAffinity, WorkersRunOnlyOnTheirSet) {
    const std::vector<int> cpus = allowedCpus();
    // Keep the first CPU free, as the engine keeps the haptic thread's core (one CPU: pin there).
    std::vector<int> set = cpus.size() > 1 ? allowedCpusExcept({cpus.front()}) : cpus;
    ThreadPool pool(4, set);
    EXPECT_EQ(pool.threadCount(), 4u);
    EXPECT_EQ(pool.workerCpus(), set);
    EXPECT_TRUE(pool.pinError().empty()) << pool.pinError();
    const std::vector<std::vector<int>> masks = workerMasks(pool);
    for (unsigned k = 1; k < masks.size(); ++k) {
        ASSERT_FALSE(masks[k].empty()) << "worker " << k << " never ran an item";
        EXPECT_EQ(masks[k], set) << "worker " << k;
    }
    EXPECT_EQ(masks[0], cpus);  // the caller is not pinned
}

TEST(ThreadPoolAffinity, ZeroThreadsWithASetIsOnePerCpu) {
    const std::vector<int> cpus = allowedCpus();
    // Unsorted, with a duplicate: the set is what counts.
    std::vector<int> asked(cpus.rbegin(), cpus.rend());
    asked.push_back(cpus.front());
    ThreadPool pool(0, asked);
    EXPECT_EQ(pool.threadCount(), unsigned(cpus.size()));
    EXPECT_EQ(pool.workerCpus(), cpus);
    EXPECT_TRUE(pool.pinError().empty()) << pool.pinError();
}

TEST(ThreadPoolAffinity, ARefusedSetIsReportedAndThePoolStillWorks) {
    ThreadPool pool(3, {100000});
    EXPECT_EQ(pool.threadCount(), 3u);
    EXPECT_FALSE(pool.pinError().empty());
    std::atomic<int> sum{0};
    pool.parallelFor(100, [&](std::size_t i) { sum += int(i); });
    EXPECT_EQ(sum.load(), 4950);
}

TEST(ThreadPoolAffinity, AnEmptySetIsThePlainPool) {
    ThreadPool pool(2, {});
    EXPECT_EQ(pool.threadCount(), 2u);
    EXPECT_TRUE(pool.workerCpus().empty());
    const std::vector<std::vector<int>> masks = workerMasks(pool);
    ASSERT_FALSE(masks[1].empty()) << "the worker never ran an item";
    EXPECT_EQ(masks[1], allowedCpus());
}

}  // namespace
}  // namespace kizamu::util
