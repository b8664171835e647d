// SPDX-License-Identifier: Apache-2.0
/// @file slot_pool.h
/// @brief Index-addressed storage whose elements never move, with reuse of released slots.
///
/// The mesher's crossings are pointed at by other tiles' vertices; an incremental update
/// replaces a few of them and must not move the rest (a std::vector would on growth, a
/// std::deque allocates blocks of 512 bytes). Elements live in fixed chunks of 2^kChunkBits,
/// allocated without clearing. 64 per chunk: a level-10 tile emits about 75 crossings, and a
/// LOD or a sparse ADF has many tiles with a few, so larger chunks would give every such tile
/// pages of memory it never uses (docs/decisions/0010-mesher-per-tile-state.md).
/// Complexity: O(1) per operation. Threading: none; one owner (a TileMesh) at a time.
/// Memory: whole chunks, never returned before clear().
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

namespace kizamu::mesh {

template <class T, uint32_t kChunkBits = 6>
class SlotPool {
public:
    /// Slots ever handed out (live and released): valid indices are below this.
    uint32_t size() const { return mSize; }
    /// Slots currently released (and not yet handed out again).
    std::size_t releasedCount() const { return mFree.size(); }

    T& operator[](uint32_t i) { return mChunks[i >> kChunkBits][i & kMask]; }
    const T& operator[](uint32_t i) const { return mChunks[i >> kChunkBits][i & kMask]; }

    /// A new slot after every existing one (never a released one); holds whatever it held.
    uint32_t append() {
        if ((mSize >> kChunkBits) == mChunks.size()) mChunks.push_back(std::make_unique_for_overwrite<T[]>(kChunk));
        return mSize++;
    }
    /// A released slot if there is one, else a new one.
    uint32_t allocate() {
        if (mFree.empty()) return append();
        const uint32_t i = mFree.back();
        mFree.pop_back();
        return i;
    }
    /// The caller marks the element dead itself; the slot may be handed out again.
    void release(uint32_t i) { mFree.push_back(i); }

    void clear() {
        mChunks.clear();
        mFree.clear();
        mSize = 0;
    }

private:
    static constexpr uint32_t kChunk = 1u << kChunkBits, kMask = kChunk - 1;
    std::vector<std::unique_ptr<T[]>> mChunks;
    std::vector<uint32_t> mFree;
    uint32_t mSize = 0;
};

}  // namespace kizamu::mesh
