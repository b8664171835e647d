// SPDX-License-Identifier: Apache-2.0
/// @file thread_pool.h
/// @brief A fixed set of worker threads running blocking parallel loops.
///
/// Used by generation, regeneration, the mesher and the point sampler. We keep our own small pool rather
/// than TBB so that every thread Kizamu starts is visible and nameable, and so ThreadSanitizer
/// sees plain std::thread/mutex synchronisation. Never used by the haptic thread. Sized from the
/// affinity mask (util/cpu_set.h); optionally kept off the haptic thread's core.
#pragma once

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <cstddef>
#include <functional>
#include <memory>
#include <mutex>
#include <numeric>
#include <string>
#include <thread>
#include <vector>

namespace kizamu::util {

/// Owned by whoever runs parallel work (the app's edit thread, a benchmark, a test).
/// One parallelFor at a time; calling it from two threads at once is a bug.
class ThreadPool {
public:
    /// `threads` workers in total, the calling thread included (0: allowedCpuCount(), the CPUs
    /// in the calling thread's affinity mask, not the machine's core count). Workers inherit
    /// the constructing thread's mask.
    explicit ThreadPool(unsigned threads = 0);
    /// As above, but the workers (not the calling thread, whose mask is left alone) run only on
    /// the CPUs in `cpus`, so a core kept for the haptic thread (allowedCpusExcept({core})) never
    /// runs or polls a worker. 0 threads: cpus.size(). Empty `cpus`: no pinning, the same as
    /// ThreadPool(threads). Each worker pins itself before it takes any work, and the
    /// constructor returns once all have tried; one refused (a CPU absent or outside the
    /// process's cpuset) keeps its inherited mask, and pinError() says why.
    ThreadPool(unsigned threads, std::vector<int> cpus);
    ~ThreadPool();
    ThreadPool(const ThreadPool&) = delete;
    ThreadPool& operator=(const ThreadPool&) = delete;

    /// Runs fn(i) for i in [0, n) across the workers and the caller; returns when all are done.
    /// Indices are handed out one by one by an atomic ticket (no lock per item), so uneven
    /// items balance and small ones cost a compare-and-swap each. Exceptions thrown by fn are
    /// rethrown here (the first one) after the loop finishes.
    /// Workers poll for the next loop for a while before they sleep, and the caller for the last
    /// item (thread_pool.cpp says why). Complexity: O(n) calls plus at most one wake-up per
    /// worker. Memory: none per item.
    void parallelFor(std::size_t n, const std::function<void(std::size_t)>& fn);

    unsigned threadCount() const { return unsigned(mWorkers.size()) + 1; }
    /// The CPUs the workers were asked to run on, ascending, no duplicates; empty: not pinned.
    const std::vector<int>& workerCpus() const { return mCpus; }
    /// Empty when every worker runs on workerCpus() (or none was asked for); otherwise why the
    /// first refused worker keeps the mask it inherited.
    const std::string& pinError() const { return mPinError; }
    /// The calling thread's place in its pool: k for worker k (1..threadCount() - 1), 0 for a
    /// thread that is no pool's worker (the caller of parallelFor runs items as thread 0). A
    /// worker of another pool answers its index there (a home is only a preference).
    static unsigned threadIndex();

private:
    /// One parallelFor: what a worker copies when it wakes.
    struct Loop {
        const std::function<void(std::size_t)>* fn = nullptr;
        std::size_t count = 0;
        uint64_t generation = 0;
    };
    static constexpr int kIndexBits = 40;
    static constexpr uint64_t kIndexMask = (uint64_t(1) << kIndexBits) - 1;
    /// Generations 1..kGenerations fit the ticket's high bits. Before they wrap, parallelFor
    /// waits until no worker is inside an earlier loop (mActive), so a worker stalled between
    /// copying a loop and taking an item can never meet its generation again.
    static constexpr uint64_t kGenerations = (uint64_t(1) << (64 - kIndexBits)) - 1;

    void workerLoop();
    void runItems(const Loop& loop);

    std::vector<std::thread> mWorkers;
    std::mutex mMutex;  ///< guards mLoop and mError, and orders mStop for sleepers
    std::condition_variable mWake, mDone;
    Loop mLoop;
    /// The loop's generation (high bits) and its next index (low kIndexBits bits).
    std::atomic<uint64_t> mTicket{0};
    std::atomic<std::size_t> mFinished{0};
    /// mLoop.generation, readable without the mutex: what a polling worker watches.
    std::atomic<uint64_t> mPublished{0};
    /// Workers that copied a loop and have not left runItems (counted under the mutex).
    std::atomic<unsigned> mActive{0};
    std::chrono::microseconds mPoll{0};  ///< 0 when there are more threads than cores
    std::atomic<bool> mStop{false};      ///< set under the mutex; read by sleeping and polling workers
    std::exception_ptr mError;
    std::vector<int> mCpus;  ///< the workers' CPUs; empty: not pinned
    std::string mPinError;   ///< written under the mutex before the constructor returns
    unsigned mStarted = 0;   ///< workers that have tried to pin (under the mutex)
};

/// Runs fn(i) for i in [0, n) on `pool`, or serially when `pool` is null.
inline void parallelFor(ThreadPool* pool, std::size_t n, const std::function<void(std::size_t)>& fn) {
    if (pool && pool->threadCount() > 1 && n > 1) {
        pool->parallelFor(n, fn);
    } else {
        for (std::size_t i = 0; i < n; ++i) fn(i);
    }
}

/// parallelFor where item i has a home thread, home(i) % threadCount() (0: the caller, k: the
/// pool's worker k): each thread runs its own items first, in the order given, then helps with
/// the others' that are left. For loops over the same things (a mesh's tiles, phase after
/// phase) whose items read what the same item wrote in an earlier loop: a cache line written by
/// another core is slow to reach (docs/decisions/0012-mesher-homes-and-place-table.md). As
/// with parallelFor, no result may depend on which thread runs an item. An exception ends the share of the thread it was thrown on (items it had not taken
/// may then not run) and reaches the caller after the loop. Serially: index order.
/// Complexity: O(n) plus one parallelFor of threadCount() items.
template <class Home>
void parallelForHomes(ThreadPool* pool, std::size_t n, Home home, const std::function<void(std::size_t)>& fn) {
    if (!pool || pool->threadCount() < 2 || n < 2) return parallelFor(pool, n, fn);
    const unsigned threads = pool->threadCount();
    std::vector<std::vector<std::size_t>> own(threads);
    for (std::size_t i = 0; i < n; ++i) own[std::size_t(home(i)) % threads].push_back(i);
    // One cache line each: a shared line would cross between the cores at every item taken.
    struct alignas(64) Cursor {
        std::atomic<std::size_t> next{0};
    };
    const std::unique_ptr<Cursor[]> cursor(new Cursor[threads]);
    pool->parallelFor(threads, [&](std::size_t) {
        const unsigned me = ThreadPool::threadIndex() % threads;
        for (unsigned k = 0; k < threads; ++k) {
            const unsigned g = (me + k) % threads;
            for (std::size_t j; (j = cursor[g].next.fetch_add(1, std::memory_order_relaxed)) < own[g].size();) fn(own[g][j]);
        }
    });
}

/// Indices 0..n-1 by `weight(i)` (an estimate of item i's work, any unsigned number), heaviest
/// first; ties keep index order.
template <class Weight>
std::vector<std::size_t> heaviestFirst(std::size_t n, Weight weight) {
    std::vector<uint64_t> w(n);
    for (std::size_t i = 0; i < n; ++i) w[i] = uint64_t(weight(i));
    std::vector<std::size_t> order(n);
    std::iota(order.begin(), order.end(), std::size_t(0));
    std::stable_sort(order.begin(), order.end(), [&](std::size_t l, std::size_t r) { return w[l] > w[r]; });
    return order;
}

/// parallelFor with the items handed out in heaviestFirst order. When a few items hold most of
/// the work (a dab's crater tile, one of a LOD's 8 tiles), one started last keeps a thread busy
/// alone after the others ran out. fn still gets the item's own index; serially the plain order.
template <class Weight>
void parallelForHeaviestFirst(ThreadPool* pool, std::size_t n, Weight weight,
                              const std::function<void(std::size_t)>& fn) {
    if (!pool || pool->threadCount() < 2 || n < 2) return parallelFor(pool, n, fn);
    const std::vector<std::size_t> order = heaviestFirst(n, weight);
    pool->parallelFor(n, [&](std::size_t k) { fn(order[k]); });
}

}  // namespace kizamu::util
