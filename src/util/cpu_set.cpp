// SPDX-License-Identifier: Apache-2.0
/// @file cpu_set.cpp
/// @brief allowedCpus and pinCurrentThread over Linux's dynamically sized cpu_set_t
/// (CPU_ALLOC), so the number of CPUs has no compile-time limit.
#include "util/cpu_set.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <memory>
#include <thread>

#if defined(__linux__)
#include <pthread.h>
#include <sched.h>
#endif

namespace kizamu::util {

namespace {

std::vector<int> allCpusByCount() {
    const unsigned n = std::max(1u, std::thread::hardware_concurrency());
    std::vector<int> cpus(n);
    for (unsigned i = 0; i < n; ++i) cpus[i] = int(i);
    return cpus;
}

#if defined(__linux__)
/// A CPU_ALLOC'd mask for CPUs 0..count-1, freed on scope exit.
struct CpuMask {
    explicit CpuMask(int count) : cpus(count), set(CPU_ALLOC(count)), bytes(CPU_ALLOC_SIZE(count)) {
        if (set) CPU_ZERO_S(bytes, set);
    }
    ~CpuMask() {
        if (set) CPU_FREE(set);
    }
    CpuMask(const CpuMask&) = delete;
    CpuMask& operator=(const CpuMask&) = delete;

    int cpus;
    cpu_set_t* set;
    std::size_t bytes;
};

std::string errorText(int error) {
    return std::strerror(error);
}
#endif

}  // namespace

std::vector<int> allowedCpus() {
#if defined(__linux__)
    // The kernel answers EINVAL while the mask is smaller than its own (nr_cpu_ids bits), so
    // grow until it fits; 1 << 22 CPUs is far past any machine and ends the loop regardless.
    for (int count = 1024; count <= (1 << 22); count *= 2) {
        CpuMask mask(count);
        if (!mask.set) break;
        if (sched_getaffinity(0, mask.bytes, mask.set) == 0) {
            std::vector<int> cpus;
            const int inMask = CPU_COUNT_S(mask.bytes, mask.set);
            cpus.reserve(std::size_t(inMask));
            // CPU_ALLOC_SIZE rounds up to whole words: scan every bit it holds.
            const int bits = int(mask.bytes * 8);
            for (int c = 0; c < bits && int(cpus.size()) < inMask; ++c)
                if (CPU_ISSET_S(std::size_t(c), mask.bytes, mask.set)) cpus.push_back(c);
            if (!cpus.empty()) return cpus;
            break;
        }
        if (errno != EINVAL) break;
    }
#endif
    return allCpusByCount();
}

unsigned allowedCpuCount() {
    return unsigned(allowedCpus().size());
}

std::vector<int> allowedCpusExcept(std::vector<int> reserved) {
    std::sort(reserved.begin(), reserved.end());
    std::vector<int> out;
    for (const int c : allowedCpus())
        if (!std::binary_search(reserved.begin(), reserved.end(), c)) out.push_back(c);
    return out;
}

CpuSplit splitCpusForServo(const std::vector<int>& allowed) {
    CpuSplit split;
    split.otherCpus = allowed;
    if (allowed.size() < 2) return split;
    split.servoCpu = split.otherCpus.back();
    split.otherCpus.pop_back();
    return split;
}

std::string formatCpuList(const std::vector<int>& cpus) {
    std::string out;
    for (std::size_t i = 0; i < cpus.size();) {
        std::size_t j = i;
        while (j + 1 < cpus.size() && cpus[j + 1] == cpus[j] + 1) ++j;
        if (!out.empty()) out += ',';
        out += std::to_string(cpus[i]);
        if (j > i) out += '-' + std::to_string(cpus[j]);
        i = j + 1;
    }
    return out;
}

bool pinCurrentThread(int cpu, std::string* why) {
    return pinCurrentThread(std::vector<int>{cpu}, why);
}

bool pinCurrentThread(const std::vector<int>& cpus, std::string* why) {
    auto fail = [&](std::string reason) {
        if (why) *why = std::move(reason);
        return false;
    };
    if (cpus.empty()) return fail("no CPU given to pin the thread to");
    const int lowest = *std::min_element(cpus.begin(), cpus.end());
    if (lowest < 0) return fail("CPU " + std::to_string(lowest) + " does not exist (negative)");
#if defined(__linux__)
    const int highest = *std::max_element(cpus.begin(), cpus.end());
    CpuMask mask(highest + 1);
    if (!mask.set) return fail("cannot allocate a CPU mask for CPU " + std::to_string(highest));
    for (const int c : cpus) CPU_SET_S(std::size_t(c), mask.bytes, mask.set);
    const int error = pthread_setaffinity_np(pthread_self(), mask.bytes, mask.set);
    if (error == 0) return true;
    if (error == EINVAL)
        return fail(cpus.size() == 1
                        ? "CPU " + std::to_string(cpus[0]) +
                              " is not usable (offline, absent or outside this process's cpuset)"
                        : "none of the CPUs given is usable (offline, absent or outside this "
                          "process's cpuset)");
    return fail("cannot set the thread's CPU affinity: " + errorText(error));
#else
    return fail("pinning a thread to CPUs is not supported on this platform");
#endif
}

}  // namespace kizamu::util
