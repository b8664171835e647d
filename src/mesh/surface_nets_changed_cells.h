// SPDX-License-Identifier: Apache-2.0
/// @file surface_nets_changed_cells.h
/// @brief ChangedCells: where two snapshots differ, as an update's phases ask it (internal to
/// src/mesh/surface_nets*).
///
/// Holds the finest unit cubes inside the changed cells (the cells where an update's tile
/// comparison found the snapshots differ), per tile slot that holds any: a bitmap of the slot's
/// 2^(3 x shift) unit cubes, or a mark that the whole slot changed. The update's phases ask it
/// whether a unit cube, a lattice point (a crossing's start) or a cell's corners lie on a
/// changed cell: the test behind every "on a changed cell" in surface_nets_update.cpp and
/// surface_nets_remesh.cpp.
/// Complexity: mark() O(slots the cell touches + its rows); every query O(1) (a hash lookup
/// only when it moves to another slot than the last one, then a few words).
/// Threading: marked on one thread (phase 0b), then read by any number of tasks, each through
/// its own Query (which caches the last slot looked up, so is not shared).
/// Inlining: mark() is always inlined into its one caller (phase 0b's loop over the changed
/// cells): GCC inlines a large function called once only where no other file can call it.
#pragma once

#include "adf/adf.h"
#include "adf/lattice.h"
#include "adf/tile_diff.h"

#include <glm/vec3.hpp>

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace kizamu::mesh::detail {

using adf::Adf;
using adf::LatticeBox;
using adf::packLattice;

/// The finest unit cubes inside changed cells, per tile slot: a bitmap (x fastest, so a row
/// of a 64-cell slot is one word), or the whole slot. Queries come in spatially coherent runs,
/// so each task queries through its own Query, which caches the last slot looked up.
class ChangedCells {
    struct Slot {
        bool whole = false;
        std::vector<uint64_t> bits;
    };

public:
    ChangedCells(const Adf& adf)
        : mShift(uint32_t(adf.domain().maxLevel - adf.domain().tileLevel())), mTop(adf.domain().latticeSize()) {}

    [[gnu::always_inline]] void mark(const LatticeBox& b) {
        const uint32_t slotSize = 1u << mShift;
        const glm::uvec3 s0 = b.lo >> mShift, s1 = (b.lo + (b.size - 1)) >> mShift;
        for (uint32_t z = s0.z; z <= s1.z; ++z)
            for (uint32_t y = s0.y; y <= s1.y; ++y)
                for (uint32_t x = s0.x; x <= s1.x; ++x) {
                    Slot& s = mSlots[slotKey({x, y, z})];
                    if (s.whole) continue;
                    if (b.size >= slotSize) {
                        s.whole = true;
                        s.bits = {};
                        continue;
                    }
                    if (s.bits.empty()) s.bits.assign((std::size_t(1) << (3 * mShift)) / 64 + 1, 0);
                    const glm::uvec3 o = b.lo - (glm::uvec3(x, y, z) << mShift);  // inside this slot
                    const std::size_t at = bit(o), row = std::size_t(1) << mShift, layer = row << mShift;
                    if (row % 64 == 0 && (at & 63) + b.size <= 64) {
                        // Rows are whole words and the cell's run fits in one: one mask for all.
                        const uint64_t mask = (b.size == 64 ? ~uint64_t(0) : (uint64_t(1) << b.size) - 1) << (at & 63);
                        uint64_t* w = s.bits.data() + (at >> 6);
                        for (uint32_t k = 0; k < b.size; ++k)
                            for (uint32_t j = 0; j < b.size; ++j) w[(k * layer + j * row) >> 6] |= mask;
                        continue;
                    }
                    for (uint32_t k = 0; k < b.size; ++k)
                        for (uint32_t j = 0; j < b.size; ++j) setRun(s.bits, at + k * layer + j * row, b.size);
                }
    }

    /// Reads the marks (after the last mark()); one per task: it caches the last slot.
    class Query {
    public:
        explicit Query(const ChangedCells& c) : mCells(c) {}

        /// The finest cube with minimum corner `u` lies in a changed cell.
        bool unitChanged(glm::uvec3 u) const {
            const Slot* s = slot(u >> mShift);
            if (!s) return false;
            if (s->whole) return true;
            const std::size_t at = bit(u & glm::uvec3((1u << mShift) - 1));
            return (s->bits[at >> 6] >> (at & 63)) & 1;
        }

        /// Lattice point `p` lies on the closed box of a changed cell.
        bool pointChanged(glm::uvec3 p) const {
            const uint32_t mask = (1u << mShift) - 1;
            const glm::uvec3 local = p & mask;
            if (local.x > 0 && local.y > 0 && local.z > 0 && p.x < mTop && p.y < mTop && p.z < mTop) {
                // The 8 unit cubes around p lie in one slot: two bits in each of 4 rows.
                const Slot* s = slot(p >> mShift);
                if (!s) return false;
                if (s->whole) return true;
                if (mShift <= 6)  // rows within words: x - 1 and x in each of the 4 rows' words
                    return ((row(s, local.y, local.z) | row(s, local.y - 1, local.z) | row(s, local.y, local.z - 1) |
                             row(s, local.y - 1, local.z - 1)) >>
                            (local.x - 1)) &
                           3u;
                for (uint32_t dz = 0; dz < 2; ++dz)
                    for (uint32_t dy = 0; dy < 2; ++dy) {
                        const std::size_t at = bit(local - glm::uvec3(1, dy, dz));
                        const uint64_t pair = (s->bits[at >> 6] >> (at & 63)) | ((at & 63) == 63 ? s->bits[(at >> 6) + 1] << 1 : 0);
                        if (pair & 3) return true;
                    }
                return false;
            }
            for (int c = 0; c < 8; ++c) {
                const glm::uvec3 d(c & 1, (c >> 1) & 1, c >> 2);
                if ((d.x > p.x) || (d.y > p.y) || (d.z > p.z)) continue;
                const glm::uvec3 u = p - d;
                if (u.x >= mTop || u.y >= mTop || u.z >= mTop) continue;
                if (unitChanged(u)) return true;
            }
            return false;
        }

        /// A corner of the cell [lo, lo + size]^3 lies on the closed box of a changed cell
        /// (pointChanged at any corner). The unit cubes around its corners are those at 4 x 4 x 4
        /// coordinates: grouped by slot (nearly always one), each slot is looked up once and,
        /// with rows of at most a word, read row by row with one mask, not 8 point queries.
        bool cornerChanged(glm::uvec3 lo, uint32_t size) const {
            if (mShift > 6) {
                for (int c = 0; c < 8; ++c)
                    if (pointChanged(lo + glm::uvec3(c & 1, (c >> 1) & 1, c >> 2) * size)) return true;
                return false;
            }
            // Every cube around the corners in lo's slot (nearly always): the rows at the 2-4 y
            // and z coordinates ORed, one mask.
            const uint32_t span = 1u << mShift;
            const glm::uvec3 in = lo & (span - 1);
            if (in.x > 0 && in.y > 0 && in.z > 0 && in.x + size < span && in.y + size < span && in.z + size < span) {
                const Slot* s = slot(lo >> mShift);
                if (!s) return false;
                if (s->whole) return true;
                const uint32_t y[4] = {in.y - 1, in.y, in.y + size - 1, in.y + size};
                const uint32_t z[4] = {in.z - 1, in.z, in.z + size - 1, in.z + size};
                uint64_t rows = 0;
                for (uint32_t zi : z)
                    for (uint32_t yi : y) rows |= row(s, yi, zi);
                return ((rows >> (in.x - 1)) & ((uint64_t(3) << size) | 3u)) != 0;
            }
            // Per axis, the cube coordinates in the domain by slot: its index and the bits within it.
            struct Axis {
                uint32_t slot[4];
                uint64_t bits[4];
                int n = 0;
            } axis[3];
            const uint32_t mask = span - 1;
            for (int k = 0; k < 3; ++k) {
                Axis& a = axis[k];
                const uint32_t local = lo[k] & mask;
                if (local > 0 && local + size < span) {  // nearly always: all four in lo's slot
                    a.n = 1;
                    a.slot[0] = lo[k] >> mShift;
                    a.bits[0] = (uint64_t(3) << (local - 1)) | (uint64_t(3) << (local + size - 1));
                    continue;
                }
                for (uint32_t c : {lo[k] - 1, lo[k], lo[k] + size - 1, lo[k] + size}) {  // increasing
                    if (c >= mTop) continue;  // outside (lo - 1 wraps)
                    if (a.n == 0 || a.slot[a.n - 1] != (c >> mShift)) {
                        a.slot[a.n] = c >> mShift;
                        a.bits[a.n++] = 0;
                    }
                    a.bits[a.n - 1] |= uint64_t(1) << (c & mask);
                }
            }
            for (int gz = 0; gz < axis[2].n; ++gz)
                for (int gy = 0; gy < axis[1].n; ++gy)
                    for (int gx = 0; gx < axis[0].n; ++gx) {
                        const Slot* s = slot({axis[0].slot[gx], axis[1].slot[gy], axis[2].slot[gz]});
                        if (!s) continue;
                        if (s->whole) return true;
                        for (uint64_t zs = axis[2].bits[gz]; zs; zs &= zs - 1)
                            for (uint64_t ys = axis[1].bits[gy]; ys; ys &= ys - 1) {
                                const std::size_t row = bit({0, uint32_t(std::countr_zero(ys)), uint32_t(std::countr_zero(zs))});
                                if ((s->bits[row >> 6] >> (row & 63)) & axis[0].bits[gx]) return true;  // a row lies in one word
                            }
                    }
            return false;
        }

    private:
        /// Row (y, z) of slot `s`'s bitmap, x at bit 0 (a row is at most a word: mShift <= 6).
        uint64_t row(const Slot* s, uint32_t y, uint32_t z) const {
            const std::size_t at = bit({0, y, z});
            return s->bits[at >> 6] >> (at & 63);
        }
        const Slot* slot(glm::uvec3 s) const {
            const uint64_t key = slotKey(s);
            if (key != mLastKey) {
                auto it = mCells.mSlots.find(key);
                mLastKey = key;
                mLast = it == mCells.mSlots.end() ? nullptr : &it->second;
            }
            return mLast;
        }
        std::size_t bit(glm::uvec3 local) const { return mCells.bit(local); }
        const ChangedCells& mCells;
        const uint32_t mShift = mCells.mShift, mTop = mCells.mTop;
        mutable uint64_t mLastKey = UINT64_MAX;
        mutable const Slot* mLast = nullptr;
    };

private:
    static uint64_t slotKey(glm::uvec3 s) { return packLattice(s); }
    std::size_t bit(glm::uvec3 local) const {
        return std::size_t(local.x) | (std::size_t(local.y) << mShift) | (std::size_t(local.z) << (2 * mShift));
    }
    /// Sets bits [at, at + n).
    static void setRun(std::vector<uint64_t>& bits, std::size_t at, uint32_t n) {
        if ((at & 63) + n < 64) {  // most cells are small: one word
            bits[at >> 6] |= ((uint64_t(1) << n) - 1) << (at & 63);
            return;
        }
        while (n > 0) {
            const uint32_t off = uint32_t(at & 63), take = std::min(n, 64u - off);
            bits[at >> 6] |= (take == 64 ? ~uint64_t(0) : ((uint64_t(1) << take) - 1)) << off;
            at += take;
            n -= take;
        }
    }
    uint32_t mShift, mTop;
    std::unordered_map<uint64_t, Slot> mSlots;
};

}  // namespace kizamu::mesh::detail
