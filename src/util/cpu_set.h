// SPDX-License-Identifier: Apache-2.0
/// @file cpu_set.h
/// @brief The CPUs this process may run on (its affinity mask), and pinning a thread to some.
///
/// Every pool is sized from allowedCpuCount(), not std::thread::hardware_concurrency(): under
/// `taskset`, a container's cpuset or a CPU reserved for the haptic thread, the machine's core
/// count overstates what we get, and workers beyond it (or pollers on a reserved core) take the
/// cores from the threads that do the work. Called at setup (pool construction, thread start),
/// never per tick. Linux: sched_getaffinity / pthread_setaffinity_np; elsewhere allowedCpus()
/// is 0..hardware_concurrency-1 and pinning reports that it is unsupported.
#pragma once

#include <string>
#include <vector>

namespace kizamu::util {

/// The CPUs in the calling thread's affinity mask (which is the process's unless a thread
/// narrowed its own), ascending, never empty. Uses a dynamically sized mask, so machines with
/// more than CPU_SETSIZE (1024) CPUs work. If the mask cannot be read: 0..hardware_concurrency-1
/// (at least {0}).
/// Complexity: O(highest CPU number), one system call (a few more on machines with > 1024 CPUs)
/// Threading:  any thread; reads only the calling thread's mask
/// Memory:     allocates the result and a temporary mask
std::vector<int> allowedCpus();

/// allowedCpus().size(): how many threads can run at once. At least 1.
/// Complexity, Threading, Memory: as allowedCpus()
unsigned allowedCpuCount();

/// allowedCpus() without the CPUs in `reserved` (say the haptic thread's core): the set to keep
/// a pool on. Empty when `reserved` covers every allowed CPU; the caller decides what then.
/// Complexity: O(A log R) for A allowed and R reserved CPUs
/// Threading:  any thread
/// Memory:     allocates the result
std::vector<int> allowedCpusExcept(std::vector<int> reserved);

/// How a process with a haptic servo thread shares its CPUs: the servo thread alone on one,
/// every other thread (the UI thread, the edit pool, and the GL driver's threads, such as Mesa
/// llvmpipe's, which inherit the mask of the thread that creates the context) on the rest.
struct CpuSplit {
    int servoCpu = -1;           ///< the servo thread's CPU; -1: one CPU only, which everything shares
    std::vector<int> otherCpus;  ///< every other thread's CPUs, ascending
};

/// Splits `allowed` (ascending, not empty; allowedCpus()): the highest CPU goes to the servo
/// thread (the lowest ones take most device interrupts), the rest to everything else; with one
/// CPU the servo thread shares it (servoCpu -1, otherCpus = allowed).
/// Complexity: O(A). Threading: pure. Memory: allocates the result.
CpuSplit splitCpusForServo(const std::vector<int>& allowed);

/// `cpus` (ascending) as ranges, "0-3,6" ("" when empty). Complexity: O(n). Threading: pure.
std::string formatCpuList(const std::vector<int>& cpus);

/// Restricts the calling thread to CPU `cpu` (>= 0). On return the thread runs there. Returns
/// false and leaves the thread's mask as it was when the CPU does not exist, is offline or is
/// outside this process's cpuset; `why` (may be null) then says so.
/// Complexity: one system call (plus a migration)
/// Threading:  changes the calling thread only
/// Memory:     allocates a mask sized to `cpu`
bool pinCurrentThread(int cpu, std::string* why = nullptr);

/// Restricts the calling thread to the CPUs in `cpus` (each >= 0, any order, duplicates
/// allowed); the kernel may drop those outside the process's cpuset. False with a reason in
/// `why` (may be null) when `cpus` is empty, holds a negative number, or names no usable CPU.
/// Complexity, Threading, Memory: as pinCurrentThread(int)
bool pinCurrentThread(const std::vector<int>& cpus, std::string* why = nullptr);

}  // namespace kizamu::util
