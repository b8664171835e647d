// SPDX-License-Identifier: Apache-2.0
/// @file cpu_set_test.cpp
/// @brief allowedCpus against sched_getaffinity, and pinCurrentThread moving a thread onto the
/// CPU it names.
#include "util/cpu_set.h"

#include <gtest/gtest.h>

#include <pthread.h>
#include <sched.h>

#include <algorithm>
#include <thread>

namespace kizamu::util {
namespace {

/// The calling thread's mask, read with a fixed-size cpu_set_t (enough on any test machine).
std::vector<int> maskOfThisThread() {
    cpu_set_t set;
    CPU_ZERO(&set);
    EXPECT_EQ(sched_getaffinity(0, sizeof set, &set), 0);
    std::vector<int> cpus;
    for (int c = 0; c < CPU_SETSIZE; ++c)
        if (CPU_ISSET(c, &set)) cpus.push_back(c);
    return cpus;
}

TEST(CpuSet, AllowedCpusAreTheAffinityMaskAscending) {
    const std::vector<int> cpus = allowedCpus();
    ASSERT_FALSE(cpus.empty());
    EXPECT_TRUE(std::is_sorted(cpus.begin(), cpus.end()));
    EXPECT_EQ(std::adjacent_find(cpus.begin(), cpus.end()), cpus.end());
    EXPECT_EQ(cpus, maskOfThisThread());
    EXPECT_EQ(allowedCpuCount(), unsigned(cpus.size()));
}

TEST(CpuSet, AllowedCpusExceptDropsTheReserved) {
    const std::vector<int> cpus = allowedCpus();
    EXPECT_EQ(allowedCpusExcept({}), cpus);
    EXPECT_TRUE(allowedCpusExcept(cpus).empty());
    std::vector<int> rest(cpus.begin() + 1, cpus.end());
    EXPECT_EQ(allowedCpusExcept({cpus.front(), -7}), rest);
}

TEST(CpuSet, APinnedThreadRunsOnItsCpu) {
    for (const int cpu : allowedCpus()) {
        std::thread([cpu] {
            std::string why;
            ASSERT_TRUE(pinCurrentThread(cpu, &why)) << why;
            EXPECT_EQ(sched_getcpu(), cpu);
            EXPECT_EQ(maskOfThisThread(), std::vector<int>{cpu});
            EXPECT_EQ(allowedCpus(), std::vector<int>{cpu});  // the thread's own mask
        }).join();
    }
}

TEST(CpuSet, PinningToASetGivesExactlyThatSet) {
    const std::vector<int> cpus = allowedCpus();
    std::thread([&] {
        std::vector<int> wanted(cpus.rbegin(), cpus.rend());  // any order, with a duplicate
        wanted.push_back(cpus.front());
        std::string why;
        ASSERT_TRUE(pinCurrentThread(wanted, &why)) << why;
        EXPECT_EQ(maskOfThisThread(), cpus);
    }).join();
}

TEST(CpuSet, ImpossiblePinsFailWithAReasonAndKeepTheMask) {
    std::thread([] {
        const std::vector<int> before = maskOfThisThread();
        std::string why;
        EXPECT_FALSE(pinCurrentThread(std::vector<int>{}, &why));
        EXPECT_FALSE(why.empty());
        why.clear();
        EXPECT_FALSE(pinCurrentThread(-1, &why));
        EXPECT_FALSE(why.empty());
        why.clear();
        // Far beyond any machine's CPUs (and beyond CPU_SETSIZE: the mask is sized dynamically).
        EXPECT_FALSE(pinCurrentThread(100000, &why));
        EXPECT_FALSE(why.empty());
        EXPECT_FALSE(pinCurrentThread(100000, nullptr));
        EXPECT_EQ(maskOfThisThread(), before);
    }).join();
}

TEST(CpuSet, TheServoThreadGetsTheHighestCpuAndTheRestGetTheOthers) {
    const CpuSplit one = splitCpusForServo({0});
    EXPECT_EQ(one.servoCpu, -1) << "one CPU: shared";
    EXPECT_EQ(one.otherCpus, std::vector<int>{0});
    const CpuSplit two = splitCpusForServo({0, 1});
    EXPECT_EQ(two.servoCpu, 1);
    EXPECT_EQ(two.otherCpus, std::vector<int>{0});
    const CpuSplit many = splitCpusForServo({0, 1, 2, 3, 8, 9});
    EXPECT_EQ(many.servoCpu, 9);
    EXPECT_EQ(many.otherCpus, (std::vector<int>{0, 1, 2, 3, 8}));
    EXPECT_EQ(formatCpuList(many.otherCpus), "0-3,8");
    EXPECT_EQ(formatCpuList(two.otherCpus), "0");
    EXPECT_EQ(formatCpuList({}), "");
    EXPECT_EQ(formatCpuList({1, 3, 4, 6}), "1,3-4,6");
}

}  // namespace
}  // namespace kizamu::util
