// SPDX-License-Identifier: Apache-2.0
/// @file thread_pool.h
/// @brief A fixed set of worker threads running blocking parallel loops.
///
/// Used by generation, regeneration and (later) the mesher. We keep our own small pool rather
/// than TBB so that every thread Kizamu starts is visible and nameable, and so ThreadSanitizer
/// sees plain std::thread/mutex synchronisation. Never used by the haptic thread.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <exception>
#include <cstddef>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace kizamu::util {

/// Owned by whoever runs parallel work (the app's edit thread, a benchmark, a test).
/// One parallelFor at a time; calling it from two threads at once is a bug.
class ThreadPool {
public:
    /// `threads` workers in total, the calling thread included (0: hardware concurrency).
    explicit ThreadPool(unsigned threads = 0);
    ~ThreadPool();
    ThreadPool(const ThreadPool&) = delete;
    ThreadPool& operator=(const ThreadPool&) = delete;

    /// Runs fn(i) for i in [0, n) across the workers and the caller; returns when all are done.
    /// Indices are handed out one by one, so uneven items balance. Exceptions thrown by fn are
    /// rethrown here (the first one) after the loop finishes.
    /// Complexity: O(n) calls plus one wake-up per worker. Memory: none per item.
    void parallelFor(std::size_t n, const std::function<void(std::size_t)>& fn);

    unsigned threadCount() const { return unsigned(mWorkers.size()) + 1; }

private:
    void workerLoop();
    void runItems();

    std::vector<std::thread> mWorkers;
    std::mutex mMutex;
    std::condition_variable mWake, mDone;
    const std::function<void(std::size_t)>* mFn = nullptr;
    std::size_t mCount = 0, mNext = 0, mFinished = 0;
    uint64_t mGeneration = 0;
    bool mStop = false;
    std::exception_ptr mError;
};

/// Runs fn(i) for i in [0, n) on `pool`, or serially when `pool` is null.
inline void parallelFor(ThreadPool* pool, std::size_t n, const std::function<void(std::size_t)>& fn) {
    if (pool && pool->threadCount() > 1 && n > 1) {
        pool->parallelFor(n, fn);
    } else {
        for (std::size_t i = 0; i < n; ++i) fn(i);
    }
}

}  // namespace kizamu::util
