// SPDX-License-Identifier: Apache-2.0
/// @file realtime_test.cpp
/// @brief The real-time requests either take effect or say why not: the test machine may or
/// may not grant them (root, CAP_SYS_NICE, rlimits), so both outcomes pass, but not silence.
#include "util/realtime.h"

#include <gtest/gtest.h>

#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>

#include <thread>

namespace kizamu::util {
namespace {

TEST(Realtime, FifoPriorityTakesEffectOrHasAReason) {
    // On a thread of its own, so the test runner never runs under SCHED_FIFO.
    std::thread([] {
        const int priority = sched_get_priority_min(SCHED_FIFO);
        std::string why;
        if (setRealtimePriority(priority, &why)) {
            int policy = -1;
            sched_param param{};
            ASSERT_EQ(pthread_getschedparam(pthread_self(), &policy, &param), 0);
            EXPECT_EQ(policy, SCHED_FIFO);
            EXPECT_EQ(param.sched_priority, priority);
            sched_param normal{};
            EXPECT_EQ(pthread_setschedparam(pthread_self(), SCHED_OTHER, &normal), 0);
        } else {
            EXPECT_FALSE(why.empty());
            int policy = -1;
            sched_param param{};
            ASSERT_EQ(pthread_getschedparam(pthread_self(), &policy, &param), 0);
            EXPECT_EQ(policy, SCHED_OTHER);
        }
    }).join();
}

TEST(Realtime, OutOfRangePriorityIsRefusedWithAReason) {
    std::string why;
    EXPECT_FALSE(setRealtimePriority(sched_get_priority_max(SCHED_FIFO) + 1, &why));
    EXPECT_FALSE(why.empty());
    why.clear();
    EXPECT_FALSE(setRealtimePriority(0, &why));
    EXPECT_FALSE(why.empty());
    EXPECT_FALSE(setRealtimePriority(-5, nullptr));
}

TEST(Realtime, LockMemoryTakesEffectOrHasAReason) {
    std::string why;
    if (lockMemory(&why)) {
        EXPECT_EQ(munlockall(), 0);
    } else {
        EXPECT_FALSE(why.empty());
    }
}

TEST(Realtime, CpuDmaLatencyIsActiveOrHasAReason) {
    CpuDmaLatency latency;
    if (latency.active()) {
        EXPECT_TRUE(latency.reason().empty());
    } else {
        EXPECT_FALSE(latency.reason().empty());
    }
    const bool wasActive = latency.active();
    CpuDmaLatency moved(std::move(latency));
    EXPECT_EQ(moved.active(), wasActive);
    EXPECT_FALSE(
        latency.active());  // NOLINT(bugprone-use-after-move): moved-from state is specified
    CpuDmaLatency other;
    other = std::move(moved);
    EXPECT_EQ(other.active(), wasActive);
}

}  // namespace
}  // namespace kizamu::util
