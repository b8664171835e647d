// SPDX-License-Identifier: Apache-2.0
/// @file snapshot_store.h
/// @brief The published ADF: one writer swaps in new snapshots, each under a sequence number
/// that only grows, any number of readers query the current one without locks, and retired
/// snapshots are freed once no reader sees them.
///
/// Threads (design brief): the edit thread is the single writer (publish, reclaim); the haptic,
/// mesher and render threads are readers. A reader's acquire/release never blocks, never
/// allocates, never frees and never touches a reference count: the writer owns every
/// std::shared_ptr and drops them only after the epoch test says no reader can see them.
///
/// Sequence numbers: the initial snapshot is number 1 (kInitialSequence) and every publish()
/// takes the previous number + 1, whatever it publishes (an edit segment, undo, redo, a
/// correction, a load, or a snapshot published before). Number and snapshot are one immutable
/// record behind one atomic pointer, so a guard's sequence() always names its adf(). 0 is never
/// a sequence number (GuardedAccessor uses it for "not bound").
///
/// Reclamation bound: a snapshot retired by publish() is freed by the first publish() or
/// reclaim() that starts after every guard acquired before that publish() returned has been
/// released. Guards acquired later never delay it, however many there are (each publish advances
/// the epoch, so readers need not signal anything). No publish is needed: the writer's idle loop
/// calls reclaim() every T (the edit thread: 10 ms), so a retired snapshot is freed at most T
/// after the last guard that could see it is released.
#pragma once

#include "adf/adf.h"
#include "adf/epoch.h"

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <memory>
#include <stdexcept>

namespace kizamu::adf {

/// Owned by the application (one per sculpture). Not copyable.
class SnapshotStore {
public:
    /// The sequence number of the snapshot given to the constructor.
    static constexpr uint64_t kInitialSequence = 1;

    /// @param initial     first published snapshot (not null), sequence kInitialSequence
    /// @param maxReaders  reader threads that may be registered at once
    /// @throw std::invalid_argument when `initial` is null
    explicit SnapshotStore(AdfPtr initial, std::size_t maxReaders = 16);
    /// All readers must be gone.
    ~SnapshotStore();
    SnapshotStore(const SnapshotStore&) = delete;
    SnapshotStore& operator=(const SnapshotStore&) = delete;

    // ---- writer (one thread) ----

    /// Makes `next` the current snapshot under the next sequence number and returns that number;
    /// the previous snapshot is retired and freed later (see the bound above). `next` may be a
    /// snapshot published before (undo, redo): it gets a new number.
    /// @throw std::invalid_argument for a null `next`; std::bad_alloc (nothing published then)
    /// Complexity: O(maxReaders + snapshots freed). Memory: one record and one retire-list entry.
    uint64_t publish(AdfPtr next);
    /// The current snapshot, as an owning pointer (writer side only).
    const AdfPtr& current() const { return mCurrentRecord->snapshot; }
    /// The current snapshot's sequence number (writer side only).
    uint64_t currentSequence() const { return mCurrentRecord->sequence; }
    /// Frees every retired snapshot no reader can still see; returns how many remain. Cheap
    /// enough to call on a timer from the writer's idle loop: O(1) when nothing is retired,
    /// else O(maxReaders + snapshots freed); allocates nothing.
    std::size_t reclaim();
    /// Retired snapshots not yet freed (writer side only).
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
            /// The number adf() was published under (read with it, in one atomic load).
            uint64_t sequence() const { return mSequence; }
            /// The Reader that acquired this guard.
            const Reader& reader() const { return *mReader; }
            ~Guard() { mReader->mStore.mEpochs.exit(mReader->mSlot); }
            Guard(const Guard&) = delete;
            Guard& operator=(const Guard&) = delete;

        private:
            friend class Reader;
            Guard(const Reader* r, const Adf* a, uint64_t sequence)
                : mReader(r), mAdf(a), mSequence(sequence) {}
            const Reader* mReader;
            const Adf* mAdf;
            uint64_t mSequence;
        };

        /// Enters the epoch and loads the current record (snapshot and its number).
        [[nodiscard]] Guard acquire() const noexcept {
            mStore.mEpochs.enter(mSlot);
            const Published* p = mStore.mCurrent.load(std::memory_order_seq_cst);
            return Guard(this, p->snapshot.get(), p->sequence);
        }
        /// True while a guard of this reader is alive (debug checks; the owner thread only).
        bool isInside() const noexcept { return mStore.mEpochs.isInside(mSlot); }

    private:
        SnapshotStore& mStore;
        int mSlot;
    };

private:
    /// Immutable once published; readers reach it only through mCurrent inside a guard.
    struct Published {
        AdfPtr snapshot;
        uint64_t sequence;
    };
    struct Retired {
        std::unique_ptr<const Published> record;
        uint64_t epoch;
    };
    EpochDomain mEpochs;
    std::unique_ptr<const Published> mCurrentRecord;
    std::atomic<const Published*> mCurrent;
    std::deque<Retired> mRetired;
};

}  // namespace kizamu::adf
