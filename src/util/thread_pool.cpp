// SPDX-License-Identifier: Apache-2.0
/// @file thread_pool.cpp
/// @brief ThreadPool: items are handed out by an atomic ticket; the mutex only wakes workers,
/// finishes a loop and keeps the first exception.
///
/// Why a ticket and not the mutex: a loop over a few thousand small tiles (the mesher's
/// assembly) took two lock round trips per item, and with two threads contending for them
/// (a futex sleep and wake each time) such a loop gained little from the second thread.
#include "util/thread_pool.h"

#include <algorithm>
#include <stdexcept>
#include <utility>

namespace kizamu::util {

ThreadPool::ThreadPool(unsigned threads) {
    if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
    for (unsigned i = 1; i < threads; ++i) mWorkers.emplace_back([this] { workerLoop(); });
}

ThreadPool::~ThreadPool() {
    {
        std::lock_guard lock(mMutex);
        mStop = true;
    }
    mWake.notify_all();
    for (auto& t : mWorkers) t.join();
}

void ThreadPool::runItems(const Loop& loop) {
    std::size_t done = 0;
    uint64_t ticket = mTicket.load(std::memory_order_acquire);
    for (;;) {
        // The ticket names its loop: a worker that wakes after its loop finished (and another
        // began) sees a different generation and takes nothing.
        if ((ticket >> kIndexBits) != loop.generation || (ticket & kIndexMask) >= loop.count) break;
        if (!mTicket.compare_exchange_weak(ticket, ticket + 1, std::memory_order_acq_rel, std::memory_order_acquire))
            continue;
        try {
            (*loop.fn)(std::size_t(ticket & kIndexMask));
        } catch (...) {
            std::lock_guard lock(mMutex);
            if (!mError) mError = std::current_exception();
        }
        ++done;
        ticket = mTicket.load(std::memory_order_acquire);
    }
    if (done == 0) return;
    // The last item's finisher wakes the caller; taking the mutex first means the caller is
    // either not yet waiting (it will see the count) or already asleep (it gets the signal).
    if (mFinished.fetch_add(done, std::memory_order_acq_rel) + done == loop.count) {
        { std::lock_guard lock(mMutex); }
        mDone.notify_all();
    }
}

void ThreadPool::workerLoop() {
    uint64_t seen = 0;
    std::unique_lock lock(mMutex);
    for (;;) {
        mWake.wait(lock, [&] { return mStop || mLoop.generation != seen; });
        if (mStop) return;
        seen = mLoop.generation;
        const Loop loop = mLoop;  // fn stays valid while an item of this generation is unfinished
        lock.unlock();
        runItems(loop);
        lock.lock();
    }
}

void ThreadPool::parallelFor(std::size_t n, const std::function<void(std::size_t)>& fn) {
    if (n > kIndexMask) throw std::length_error("thread pool: too many items in one loop");
    Loop loop;
    {
        std::lock_guard lock(mMutex);
        loop = {&fn, n, mLoop.generation % kGenerations + 1};  // wraps, never 0 (a new worker's)
        mLoop = loop;
        mFinished.store(0, std::memory_order_relaxed);
        mError = nullptr;
        mTicket.store(loop.generation << kIndexBits, std::memory_order_release);
    }
    mWake.notify_all();
    runItems(loop);
    // Every item done is enough: a worker touches fn only for an item it took, and one that
    // wakes late finds none (or the next loop's). Waiting for it too would add its wake-up
    // latency to every loop the caller could finish alone (a small LOD runs a dozen).
    std::unique_lock lock(mMutex);
    mDone.wait(lock, [&] { return mFinished.load(std::memory_order_acquire) == n; });
    if (mError) std::rethrow_exception(std::exchange(mError, nullptr));
}

}  // namespace kizamu::util
