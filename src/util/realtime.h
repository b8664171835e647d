// SPDX-License-Identifier: Apache-2.0
/// @file realtime.h
/// @brief What a real-time loop asks of the OS: FIFO priority, locked memory, a shallow C-state.
///
/// Called once by the haptic thread when it starts, and by the latency benchmarks; never per
/// tick. Each request may be refused (they need root, CAP_SYS_NICE / CAP_IPC_LOCK or matching
/// rlimits), so each reports a reason and never throws: the loop then runs without it and the
/// caller logs why. Linux; elsewhere every call fails with "not supported on this platform".
#pragma once

#include <string>

namespace kizamu::util {

/// Puts the calling thread under SCHED_FIFO at `priority` (1 lowest .. 99 highest on Linux;
/// sched_get_priority_min/max(SCHED_FIFO) bound it). Returns false and leaves the thread's
/// policy unchanged when refused; `why` (may be null) then says why, e.g. "no real-time
/// priority: needs root or CAP_SYS_NICE / RLIMIT_RTPRIO" on EPERM, or that the priority is
/// out of range. Undo with pthread_setschedparam(SCHED_OTHER, 0).
/// Complexity: one system call
/// Threading:  changes the calling thread only
/// Memory:     none (the reason string on failure)
bool setRealtimePriority(int priority, std::string* why = nullptr);

/// mlockall(MCL_CURRENT | MCL_FUTURE): no page of the process, present or future, is paged out,
/// so a tick never waits on a page fault to disk. Returns false with a reason in `why` (may be
/// null) when refused (needs CAP_IPC_LOCK or an RLIMIT_MEMLOCK large enough for the process).
/// Undo with munlockall().
/// Complexity: proportional to the process's mapped memory (it faults every page in)
/// Threading:  affects the whole process; call at start-up, before the pools allocate
/// Memory:     commits every mapped page
bool lockMemory(std::string* why = nullptr);

/// Holds /dev/cpu_dma_latency open with 0 written: while it is held, the kernel keeps every CPU
/// out of the C-states whose wake-up latency is above 0 us, so a core woken for a tick answers at
/// once (the PM QoS interface real-time loops use). Released when destroyed.
/// Owned by the thread setup of the app or a benchmark, one per process is enough; not
/// thread-safe (construct and destroy on one thread), movable.
class CpuDmaLatency {
public:
    /// Opens and writes the request; on failure active() is false and reason() says why.
    CpuDmaLatency();
    ~CpuDmaLatency();
    CpuDmaLatency(CpuDmaLatency&& other) noexcept;
    CpuDmaLatency& operator=(CpuDmaLatency&& other) noexcept;
    CpuDmaLatency(const CpuDmaLatency&) = delete;
    CpuDmaLatency& operator=(const CpuDmaLatency&) = delete;

    /// Whether the 0 us request is in force.
    bool active() const { return mFd >= 0; }
    /// Why the request is not in force; empty when active().
    const std::string& reason() const { return mReason; }

private:
    int mFd = -1;
    std::string mReason;
};

}  // namespace kizamu::util
