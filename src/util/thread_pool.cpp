// SPDX-License-Identifier: Apache-2.0
/// @file thread_pool.cpp
/// @brief ThreadPool: items are handed out by an atomic ticket; workers poll before they
/// sleep; the mutex only publishes a loop, wakes sleepers and keeps the first exception.
///
/// Why a ticket and not the mutex: handing items out under a lock costs two lock round trips
/// per item, and with two threads contending for them (a futex sleep and wake each time) a loop
/// over a few thousand small tiles (the mesher's assembly) would gain little from the second
/// thread (docs/decisions/0006-own-thread-pool.md).
#include "util/thread_pool.h"

#include "util/cpu_set.h"

#include <algorithm>
#include <chrono>
#include <stdexcept>
#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif
#include <utility>

namespace kizamu::util {

namespace {

/// Polls `done` for up to `limit`; true if it came true. Yields between rounds, so a thread
/// that needs the core (the haptic thread) gets it.
template <class Done>
bool pollFor(std::chrono::microseconds limit, Done done) {
    if (limit.count() <= 0) return done();
    const auto until = std::chrono::steady_clock::now() + limit;
    for (;;) {
        for (int i = 0; i < 64; ++i) {
            if (done()) return true;
#if defined(__x86_64__) || defined(__i386__)
            _mm_pause();
#endif
        }
        if (std::chrono::steady_clock::now() >= until) return false;
        std::this_thread::yield();
    }
}

/// How long a worker polls for the next loop, and the caller for a loop's last item, before
/// sleeping. Waking a sleeping thread costs tens of microseconds, and a job runs its loops back
/// to back with short serial steps between them (a LOD about 14, a dab about 20), so a worker
/// that polls across those steps starts the next loop at once
/// (docs/decisions/0006-own-thread-pool.md). The same trade as OpenMP's and TBB's workers,
/// which also spin before they sleep; after its last loop an idle pool costs at most this much CPU
/// per thread. With more threads than cores it may use (the affinity mask's, or the workers' set)
/// nobody polls: the pollers would take the cores from the threads still running items.
constexpr std::chrono::microseconds kPoll{500};

thread_local unsigned tThreadIndex = 0;  ///< set once by each worker (ThreadPool::threadIndex)

}  // namespace

unsigned ThreadPool::threadIndex() { return tThreadIndex; }

ThreadPool::ThreadPool(unsigned threads) : ThreadPool(threads, {}) {}

ThreadPool::ThreadPool(unsigned threads, std::vector<int> cpus) : mCpus(std::move(cpus)) {
    std::sort(mCpus.begin(), mCpus.end());
    mCpus.erase(std::unique(mCpus.begin(), mCpus.end()), mCpus.end());
    // The cores the pool's threads share: those allowed to the process, or the workers' set.
    const unsigned cores = mCpus.empty() ? allowedCpuCount() : unsigned(mCpus.size());
    if (threads == 0) threads = cores;
    mPoll = threads <= cores ? kPoll : std::chrono::microseconds(0);
    for (unsigned i = 1; i < threads; ++i)
        mWorkers.emplace_back([this, i] {
            tThreadIndex = i;
            // Pinned before the first poll: a worker must never spin on a CPU it was kept off.
            if (!mCpus.empty()) {
                std::string why;
                const bool pinned = pinCurrentThread(mCpus, &why);
                {
                    std::lock_guard lock(mMutex);
                    if (!pinned && mPinError.empty())
                        mPinError = "worker " + std::to_string(i) + ": " + why;
                    ++mStarted;
                }
                mDone.notify_all();
            }
            workerLoop();
        });
    if (!mCpus.empty()) {
        // No loop runs yet, so mDone has no other waiter.
        std::unique_lock lock(mMutex);
        mDone.wait(lock, [&] { return mStarted == mWorkers.size(); });
    }
}

ThreadPool::~ThreadPool() {
    {
        std::lock_guard lock(mMutex);
        mStop.store(true, std::memory_order_release);
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
    for (;;) {
        pollFor(mPoll, [&] {
            return mPublished.load(std::memory_order_acquire) != seen || mStop.load(std::memory_order_acquire);
        });
        std::unique_lock lock(mMutex);
        mWake.wait(lock, [&] { return mStop.load(std::memory_order_relaxed) || mLoop.generation != seen; });
        if (mStop.load(std::memory_order_relaxed)) return;
        seen = mLoop.generation;
        const Loop loop = mLoop;  // fn stays valid while an item of this generation is unfinished
        mActive.fetch_add(1, std::memory_order_relaxed);  // under the mutex, with the copy
        lock.unlock();
        runItems(loop);
        mActive.fetch_sub(1, std::memory_order_release);
    }
}

void ThreadPool::parallelFor(std::size_t n, const std::function<void(std::size_t)>& fn) {
    if (n > kIndexMask) throw std::length_error("thread pool: too many items in one loop");
    if (mPublished.load(std::memory_order_relaxed) == kGenerations) {
        // The generations wrap: first let every worker leave the loops it copied (outside the
        // mutex, which a finishing worker takes to notify). One that copies the last loop
        // meanwhile finds the new generation and takes nothing.
        while (mActive.load(std::memory_order_acquire) != 0) std::this_thread::yield();
    }
    Loop loop;
    {
        std::lock_guard lock(mMutex);
        loop = {&fn, n, mLoop.generation % kGenerations + 1};  // wraps, never 0 (a new worker's)
        mLoop = loop;
        mFinished.store(0, std::memory_order_relaxed);
        mError = nullptr;
        mTicket.store(loop.generation << kIndexBits, std::memory_order_release);
        mPublished.store(loop.generation, std::memory_order_release);
    }
    mWake.notify_all();
    runItems(loop);
    // Every item done is enough: a worker touches fn only for an item it took, and one that
    // wakes late finds none (or the next loop's). Waiting for it too would add its wake-up
    // latency to every loop the caller could finish alone (a small LOD runs a dozen).
    auto allDone = [&] { return mFinished.load(std::memory_order_acquire) == n; };
    pollFor(mPoll, allDone);
    std::unique_lock lock(mMutex);
    mDone.wait(lock, allDone);
    if (mError) std::rethrow_exception(std::exchange(mError, nullptr));
}

}  // namespace kizamu::util
