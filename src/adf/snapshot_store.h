// SPDX-License-Identifier: Apache-2.0
/// @file snapshot_store.h
/// @brief The published ADF: one writer swaps in new snapshots, any number of readers query
/// the current one without locks, and retired snapshots are freed once no reader sees them.
///
/// Threads (design brief): the edit thread is the single writer (publish, reclaim); the haptic,
/// mesher and render threads are readers. A reader's acquire/release never blocks, never
/// allocates, never frees and never touches a reference count: the writer owns every
/// std::shared_ptr and drops them only after the epoch test says no reader can see them.
#pragma once

#include "adf/adf.h"
#include "adf/epoch.h"

#include <atomic>
#include <cstddef>
#include <deque>
#include <stdexcept>

namespace kizamu::adf {

/// Owned by the application (one per sculpture). Not copyable.
class SnapshotStore {
public:
    /// @param initial     first published snapshot (not null)
    /// @param maxReaders  reader threads that may be registered at once
    explicit SnapshotStore(AdfPtr initial, std::size_t maxReaders = 16);
    /// All readers must be gone.
    ~SnapshotStore();
    SnapshotStore(const SnapshotStore&) = delete;
    SnapshotStore& operator=(const SnapshotStore&) = delete;

    // ---- writer (one thread) ----

    /// Makes `next` the current snapshot; the previous one is retired and freed later.
    /// Complexity: O(maxReaders) for the reclaim pass. Memory: one retire-list entry.
    void publish(AdfPtr next);
    /// The current snapshot, as an owning pointer (writer side only).
    const AdfPtr& current() const { return mCurrentOwner; }
    /// Frees every retired snapshot no reader can still see; returns how many remain.
    std::size_t reclaim();
    /// Retired snapshots not yet freed.
    std::size_t retiredCount() const { return mRetired.size(); }

    // ---- readers ----

    /// One per reader thread. Construction registers a slot (cold path: call it before the
    /// real-time loop starts); throws std::runtime_error when all slots are taken.
    class Reader {
    public:
        explicit Reader(SnapshotStore& store);
        ~Reader();
        Reader(const Reader&) = delete;
        Reader& operator=(const Reader&) = delete;

        /// Keeps the snapshot current at acquire() alive and readable until destroyed.
        /// Lock-free, O(1), allocates nothing. One guard per Reader at a time.
        class Guard {
        public:
            const Adf& adf() const { return *mAdf; }
            const Adf* operator->() const { return mAdf; }
            ~Guard() { mReader->mStore.mEpochs.exit(mReader->mSlot); }
            Guard(const Guard&) = delete;
            Guard& operator=(const Guard&) = delete;

        private:
            friend class Reader;
            Guard(const Reader* r, const Adf* a) : mReader(r), mAdf(a) {}
            const Reader* mReader;
            const Adf* mAdf;
        };

        /// Enters the epoch and loads the current snapshot.
        [[nodiscard]] Guard acquire() const noexcept {
            mStore.mEpochs.enter(mSlot);
            return Guard(this, mStore.mCurrent.load(std::memory_order_seq_cst));
        }

    private:
        SnapshotStore& mStore;
        int mSlot;
    };

private:
    struct Retired {
        AdfPtr snapshot;
        uint64_t epoch;
    };
    EpochDomain mEpochs;
    std::atomic<const Adf*> mCurrent;
    AdfPtr mCurrentOwner;
    std::deque<Retired> mRetired;
};

}  // namespace kizamu::adf
