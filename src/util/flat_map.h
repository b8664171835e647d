// SPDX-License-Identifier: Apache-2.0
/// @file flat_map.h
/// @brief A hash map from 64-bit keys (packed lattice points, adf/lattice.h) to small values in
/// one flat array (open addressing): the project's one hash map for hot lookups.
///
/// The mesher indexes every cell's first vertex, per tile, during a full build, so that an
/// update can find the vertices (and through them the crossings) around changed cells without
/// scanning the tile; generation caches the upper pass's samples and finds a tile's neighbours
/// by slot. std::unordered_map costs a node allocation per entry and 40 bytes per entry
/// (docs/decisions/0010-mesher-per-tile-state.md,
/// docs/decisions/0014-generation-flat-map-and-scratch.md).
/// Linear probing with multiplicative (Fibonacci) hashing; erase shifts the following run back,
/// so there are no tombstones and lookups stay short after many updates.
/// Complexity: O(1) expected per operation. Threading: none; one owner at a time.
/// Memory: 16 bytes per slot for values of up to 8 bytes, at most 3/4 of the slots used; grows
/// by doubling, never shrinks before clear().
#pragma once

#include <cassert>
#include <cstdint>
#include <type_traits>
#include <utility>
#include <vector>

namespace kizamu::util {

/// The map from 64-bit keys to values of type V (trivially copyable, small: a number or an
/// index). Owned by one user; not thread-safe.
template <class V>
class FlatMap {
    static_assert(std::is_trivially_copyable_v<V>, "FlatMap holds small plain values");

public:
    /// Reserved: no key may equal it.
    static constexpr uint64_t kEmpty = ~uint64_t(0);

    std::size_t size() const { return mSize; }
    bool empty() const { return mSize == 0; }

    /// The value of `key`, or null. The pointer is valid until the next insertion or erase.
    V* find(uint64_t key) {
        if (mSlots.empty()) return nullptr;
        for (std::size_t i = home(key);; i = (i + 1) & mMask) {
            if (mSlots[i].key == key) return &mSlots[i].value;
            if (mSlots[i].key == kEmpty) return nullptr;
        }
    }
    const V* find(uint64_t key) const { return const_cast<FlatMap*>(this)->find(key); }

    /// Sets the value of `key` (inserting it if absent).
    void assign(uint64_t key, V value) {
        assert(key != kEmpty && "FlatMap: the all-ones key is reserved");
        if (4 * (mSize + 1) > 3 * mSlots.size()) grow();
        for (std::size_t i = home(key);; i = (i + 1) & mMask) {
            if (mSlots[i].key == key) {
                mSlots[i].value = value;
                return;
            }
            if (mSlots[i].key == kEmpty) {
                mSlots[i] = {key, value};
                ++mSize;
                return;
            }
        }
    }

    /// The value of `key`, after inserting it with `value` if absent (one probe sequence).
    V findOrAssign(uint64_t key, V value) {
        assert(key != kEmpty && "FlatMap: the all-ones key is reserved");
        if (4 * (mSize + 1) > 3 * mSlots.size()) grow();
        for (std::size_t i = home(key);; i = (i + 1) & mMask) {
            if (mSlots[i].key == key) return mSlots[i].value;
            if (mSlots[i].key == kEmpty) {
                mSlots[i] = {key, value};
                ++mSize;
                return value;
            }
        }
    }

    /// The value of `key` and false, or, when absent, `key` inserted with `value` and true (one
    /// probe sequence). The pointer is valid until the next insertion or erase: a cache fills
    /// in the value after a miss without probing again.
    std::pair<V*, bool> tryInsert(uint64_t key, V value) {
        assert(key != kEmpty && "FlatMap: the all-ones key is reserved");
        if (4 * (mSize + 1) > 3 * mSlots.size()) grow();
        for (std::size_t i = home(key);; i = (i + 1) & mMask) {
            if (mSlots[i].key == key) return {&mSlots[i].value, false};
            if (mSlots[i].key == kEmpty) {
                mSlots[i] = {key, value};
                ++mSize;
                return {&mSlots[i].value, true};
            }
        }
    }

    /// Removes `key` if present.
    void erase(uint64_t key) {
        if (mSlots.empty()) return;
        std::size_t i = home(key);
        while (mSlots[i].key != key) {
            if (mSlots[i].key == kEmpty) return;
            i = (i + 1) & mMask;
        }
        // Backward shift: move later entries of the run into the hole when their home allows.
        for (std::size_t j = (i + 1) & mMask;; j = (j + 1) & mMask) {
            if (mSlots[j].key == kEmpty) break;
            const std::size_t h = home(mSlots[j].key);
            // Movable when the hole lies cyclically in [h, j).
            if (((j - h) & mMask) >= ((j - i) & mMask)) {
                mSlots[i] = mSlots[j];
                i = j;
            }
        }
        mSlots[i].key = kEmpty;
        --mSize;
    }

    /// Makes room for `n` entries without growing.
    void reserve(std::size_t n) {
        const std::size_t cap = capacityFor(n);
        if (cap > mSlots.size()) rehash(cap);
    }

    /// Empties the map and makes room for `n` entries, keeping its memory where that suffices
    /// (a scratch map reused per tile: no allocation, and its slots stay in cache).
    void resetFor(std::size_t n) { emptySlots(capacityFor(n)); }

    void clear() {
        mSlots.clear();
        mSize = 0;
        mMask = 0;
        mShift = 64;
    }

private:
    struct Slot {
        uint64_t key = kEmpty;
        V value{};
    };
    std::size_t home(uint64_t key) const { return std::size_t((key * 0x9E3779B97F4A7C15ull) >> mShift); }
    /// The smallest power of two from 16 holding `n` entries at most 3/4 full.
    static std::size_t capacityFor(std::size_t n) {
        std::size_t cap = 16;
        while (3 * cap < 4 * n) cap *= 2;
        return cap;
    }
    /// `cap` empty slots (a power of two) in the current vector.
    void emptySlots(std::size_t cap) {
        mSlots.assign(cap, Slot{});
        mMask = cap - 1;
        mShift = 64;
        for (std::size_t c = cap; c > 1; c >>= 1) --mShift;
        mSize = 0;
    }
    void grow() { rehash(mSlots.empty() ? 16 : 2 * mSlots.size()); }
    void rehash(std::size_t cap) {
        std::vector<Slot> old;
        old.swap(mSlots);
        emptySlots(cap);
        for (const Slot& s : old)
            if (s.key != kEmpty) assign(s.key, s.value);
    }

    std::vector<Slot> mSlots;
    std::size_t mSize = 0, mMask = 0;
    int mShift = 64;
};

/// 64-bit keys to 32-bit values (indices, numbers).
using FlatMap64 = FlatMap<uint32_t>;

}  // namespace kizamu::util
