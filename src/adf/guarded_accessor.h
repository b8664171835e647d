// SPDX-License-Identifier: Apache-2.0
/// @file guarded_accessor.h
/// @brief The haptic thread's cached query, bound to SnapshotStore guards: its cache can never
/// point into a snapshot that has been freed.
///
/// Threads: one per reader thread, next to its SnapshotStore::Reader (the haptic thread keeps one
/// across ticks and acquires a guard per tick). Follows snapshot_store.h's epochs and
/// AdfAccessor's leaf cache (adf.h).
#pragma once

#include "adf/adf.h"
#include "adf/snapshot_store.h"

#include <cassert>
#include <cstdint>

namespace kizamu::adf {

/// An AdfAccessor that is only ever used through a live guard, on that guard's snapshot.
/// Every query takes the guard; when the guard's sequence number is not the one the cache was
/// filled under, the cache is dropped and rebound to the guard's snapshot first. So the cache is
/// used only while a guard holds its snapshot alive, and between guards (when that snapshot may
/// be freed) nothing reads it. Keyed by the sequence number, not the snapshot's address: a freed
/// snapshot's memory may hold a newer one, a sequence number never repeats.
/// Debug builds assert that the guard comes from this accessor's Reader and is still held.
/// Owned by the reader thread; not thread-safe; may outlive guards and snapshots, not its Reader.
class GuardedAccessor {
public:
    using Guard = SnapshotStore::Reader::Guard;

    /// Bound to `guard`'s snapshot. Complexity: O(1). Memory: none.
    explicit GuardedAccessor(const Guard& guard) noexcept
        : mAccessor(guard.adf()), mSequence(guard.sequence()), mReader(&guard.reader()) {}

    /// Same result as guard.adf().sample(pWorld) (world position, m).
    /// Complexity: AdfAccessor::sample's, plus O(1) to rebind when the snapshot changed.
    /// Threading: the Reader's thread, with `guard` held. Memory: none. Never blocks.
    Sample sample(const Guard& guard, const glm::vec3& pWorld) noexcept {
        bind(guard);
        return mAccessor.sample(pWorld);
    }

    /// Rebinds to `guard`'s snapshot, dropping the cache only when that is another snapshot
    /// than the one it was filled from (sample() does this itself). O(1), no atomics.
    void bind(const Guard& guard) noexcept {
        assert(&guard.reader() == mReader && "GuardedAccessor used with a guard of another Reader");
        assert(mReader->isInside() && "GuardedAccessor used with a released guard");
        if (guard.sequence() != mSequence) [[unlikely]] {
            mAccessor.reset(guard.adf());
            mSequence = guard.sequence();
        }
    }

    /// The cached accessor, bound to `guard`'s snapshot: for code that takes an AdfAccessor
    /// (haptics/proxy_renderer.h). Use it only while `guard` is held.
    AdfAccessor& bound(const Guard& guard) noexcept {
        bind(guard);
        return mAccessor;
    }

    /// Sequence number of the snapshot the cache belongs to.
    uint64_t sequence() const noexcept { return mSequence; }

private:
    AdfAccessor mAccessor;
    uint64_t mSequence;
    const SnapshotStore::Reader* mReader;
};

}  // namespace kizamu::adf
