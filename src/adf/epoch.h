// SPDX-License-Identifier: Apache-2.0
/// @file epoch.h
/// @brief Epoch-based reclamation: readers announce themselves, the writer frees what no
/// announced reader can still see.
///
/// Why epochs and not std::atomic<std::shared_ptr>: libstdc++ implements the latter with a
/// lock, and dropping the last reference on the reader would free memory on the haptic thread.
/// Here a reader's enter/exit is two atomic stores and a load: no lock, no allocation, no free.
/// All operations are sequentially consistent; the proof sketch is in snapshot_store.cpp.
#pragma once

#include <atomic>
#include <cassert>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>

namespace kizamu::adf {

/// Owned by a SnapshotStore. Reader slots are fixed at construction.
/// Threading: registerReader/unregisterReader from any thread (cold, a CAS scan); enter/exit only
/// by the slot's owner thread (hot, lock-free); advance/canReclaim by the single writer.
class EpochDomain {
public:
    static constexpr uint64_t kIdle = std::numeric_limits<uint64_t>::max();

    explicit EpochDomain(std::size_t maxReaders);

    /// A free slot index, or -1 when all `maxReaders` slots are taken. Cold path.
    int registerReader();
    void unregisterReader(int slot);

    /// Reader: announce the current epoch before loading shared pointers. Lock-free, O(1).
    /// One announcement per slot at a time (a nested enter would be ended by the inner exit).
    void enter(int slot) noexcept {
        assert(mSlots[slot].epoch.load(std::memory_order_relaxed) == kIdle &&
               "nested acquire on one reader");
        mSlots[slot].epoch.store(mEpoch.load(std::memory_order_seq_cst), std::memory_order_seq_cst);
    }
    /// Reader: done with everything loaded since enter(). Lock-free, O(1).
    void exit(int slot) noexcept { mSlots[slot].epoch.store(kIdle, std::memory_order_seq_cst); }

    /// Writer: after unpublishing something, returns the epoch to retire it under.
    uint64_t advance() noexcept { return mEpoch.fetch_add(1, std::memory_order_seq_cst); }
    /// Writer: true when no reader can still hold what was retired under `retiredEpoch`.
    /// Complexity: O(maxReaders).
    bool canReclaim(uint64_t retiredEpoch) const noexcept;
    /// Writer: the smallest epoch a reader announces, or kIdle when every slot is idle; what was
    /// retired under an epoch below it is unreachable (canReclaim for all of them in one scan).
    /// Complexity: O(maxReaders).
    uint64_t oldestAnnounced() const noexcept;

    /// True while `slot` is between enter() and exit() (debug checks and diagnostics).
    bool isInside(int slot) const noexcept {
        return mSlots[slot].epoch.load(std::memory_order_relaxed) != kIdle;
    }

    /// Readers currently inside enter/exit (for tests and diagnostics).
    std::size_t activeReaders() const noexcept;
    /// Registered reader slots.
    std::size_t registeredReaders() const noexcept;

private:
    struct alignas(64) Slot {
        std::atomic<uint64_t> epoch{kIdle};
        std::atomic<bool> used{false};
    };
    std::atomic<uint64_t> mEpoch{0};
    std::size_t mSlotCount;
    std::unique_ptr<Slot[]> mSlots;
};

}  // namespace kizamu::adf
