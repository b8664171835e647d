// SPDX-License-Identifier: Apache-2.0
/// @file thread_pool.cpp
/// @brief ThreadPool: a mutex hands out indices; items are coarse (tiles), so it never contends.
#include "util/thread_pool.h"

#include <algorithm>
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

void ThreadPool::runItems() {
    std::unique_lock lock(mMutex);
    while (mNext < mCount) {
        const std::size_t i = mNext++;
        const auto* fn = mFn;
        lock.unlock();
        try {
            (*fn)(i);
        } catch (...) {
            lock.lock();
            if (!mError) mError = std::current_exception();
            ++mFinished;
            continue;
        }
        lock.lock();
        ++mFinished;
    }
    if (mFinished == mCount) mDone.notify_all();
}

void ThreadPool::workerLoop() {
    uint64_t seen = 0;
    std::unique_lock lock(mMutex);
    for (;;) {
        mWake.wait(lock, [&] { return mStop || mGeneration != seen; });
        if (mStop) return;
        seen = mGeneration;
        lock.unlock();
        runItems();
        lock.lock();
    }
}

void ThreadPool::parallelFor(std::size_t n, const std::function<void(std::size_t)>& fn) {
    {
        std::lock_guard lock(mMutex);
        mFn = &fn;
        mCount = n;
        mNext = 0;
        mFinished = 0;
        mError = nullptr;
        ++mGeneration;
    }
    mWake.notify_all();
    runItems();
    std::unique_lock lock(mMutex);
    // Every item done is enough: a worker touches fn only for an item it took, and one that
    // wakes late finds none (or the next loop's). Waiting for it too would add its wake-up
    // latency to every loop the caller could finish alone (a small LOD runs a dozen).
    mDone.wait(lock, [&] { return mFinished == mCount; });
    mFn = nullptr;
    if (mError) std::rethrow_exception(std::exchange(mError, nullptr));
}

}  // namespace kizamu::util
