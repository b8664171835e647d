// SPDX-License-Identifier: Apache-2.0
/// @file surface_nets_update.cpp
/// @brief SurfaceMesher::update: sub-tile re-meshing after an edit.
///
/// Takes the mesher's state for the previous snapshot and the new snapshot; leaves the state of
/// the new one, whose mesh equals a build's bit for bit. update() calls its phases in order, one
/// function each (an UpdateContext carries the snapshots, the pool and the tiles):
///   0. compareRebuiltTiles, markChangedCells, followRebuiltTiles, listTilesToScan: the tiles the
///      snapshots do not share, the cells where they differ (ChangedCells), the tiles they touch.
///   1. rescanCrossings, queueCellsToRemesh: the crossings starting on a changed cell recomputed
///      (removed, added or kept in place), and the cells whose vertices that changes queued.
///   2. listTilesToRemesh, remeshCells: the queued cells' vertices, from scratch.
///   3. splitFacesNear, relaxNewVertices: split vertices near them; relaxation of the new
///      vertices and of the vertices that read them.
///   4. releaseRemovedCrossings, dropEmptiedTiles, addTotals.
/// Complexity: O(root entries + slots of the chunks the snapshots do not share) to find the
/// rebuilt tiles, O(nodes of the rebuilt tiles) to compare them, and otherwise work
/// proportional to the changed cells (see each phase).
/// Threading: update() runs on the mesher's owning thread; phases 0a, 1a and 2c run one tile per
/// pool task, heaviest first, and 3b blocks of vertices. A task writes only its tile's records
/// (and its cells' slots of crossings), so the result does not depend on the schedule; the rest
/// is serial.
///
/// Why it is exact. A crossing depends only on the leaves whose closed boxes contain its start
/// point p (its emitter and the leaves found around p) and on the emitter's corners; so a
/// crossing whose p lies on no changed cell is the same record in both snapshots, and only
/// crossings starting on a changed cell's closed box are recomputed (old ones there removed,
/// identical ones kept in place). A cell's vertices depend on its corners and on the crossings
/// around it, so only the cells around removed or added crossings, and changed cells, are
/// re-meshed from all their crossings (kept ones from the old vertices' lists); a position after
/// relaxation depends on the neighbours' projected vertices, so their neighbours are relaxed too.
/// Every float is computed by the same code in the same order as in a build (incidences sorted
/// by crossing key), so an update equals a build bit for bit.
#include "mesh/surface_nets.h"

#include "mesh/surface_nets_internal.h"
#include "adf/tile_diff.h"
#include "util/thread_pool.h"

#include <algorithm>
#include <bit>
#include <cassert>
#include <chrono>
#include <functional>
#include <stdexcept>

namespace kizamu::mesh {

using adf::Adf;
using adf::Tile;
using namespace detail;

namespace {

template <class T>
void sortUnique(std::vector<T>& v) {
    std::sort(v.begin(), v.end());
    v.erase(std::unique(v.begin(), v.end()), v.end());
}

inline bool inBox(glm::uvec3 p, glm::uvec3 lo, glm::uvec3 hi) {
    return p.x >= lo.x && p.y >= lo.y && p.z >= lo.z && p.x <= hi.x && p.y <= hi.y && p.z <= hi.z;
}

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

    void mark(const LatticeBox& b) {
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

/// A crossing's key and where its record is (a slot of its tile's pool, or an index).
using KeyedIndex = std::pair<uint64_t, uint32_t>;

/// An update's per-task buffers, kept per pool thread across updates: the snapshots an editing
/// session keeps for undo take the heap's top, where buffers made afresh would come from, so
/// each update would fault their pages in again. Not reentrant: a task must not start another
/// update (none does).
struct UpdateScratch {
    std::vector<BoundaryCell> oldLeaves;  ///< the old tile's leaves near the changed cells
    std::vector<uint64_t> oldCells;       ///< the old tile's cells that may have emitted there
    std::vector<KeyedIndex> oldCrossings;  ///< (key, slot) of those crossings
    std::vector<Crossing> fresh;           ///< the crossings recomputed there
    std::vector<KeyedIndex> freshByKey;    ///< (key, index in `fresh`), sorted
    std::vector<Incidence> incidences;  ///< a re-meshed cell's, sorted by crossing key
    CellScratch cell;
};
UpdateScratch& updateScratch() {
    thread_local UpdateScratch s;
    return s;
}

using TileMap = std::unordered_map<uint64_t, std::unique_ptr<TileMesh>>;

/// What every phase of an update reads: the two snapshots and their lattice geometry, the pool,
/// and the mesher's tiles (`ensureTile` makes the state of a tile of the new snapshot that has
/// none yet; null if the key is no tile's). Lives in update()'s frame; phases take it by reference.
struct UpdateContext {
    UpdateContext(const Adf& before, const Adf& after, util::ThreadPool* threads, TileMap& tileMap,
                  std::function<TileMesh*(uint64_t)> ensure)
        : oldAdf(before), newAdf(after), pool(threads), tiles(tileMap), ensureTile(std::move(ensure)),
          maxLevel(after.domain().maxLevel), slotShift(uint32_t(maxLevel - after.domain().tileLevel())),
          slots(after.domain().slotsPerAxis()) {}

    /// The tile of snapshot `s` whose packed origin is `key`; null if no tile of `s` starts there.
    const Tile* tileOfKey(const Adf& s, uint64_t key) const {
        const Tile* t = s.tileAtSlot(unpackLattice(key) >> slotShift);
        return packLattice(t->latticeOrigin()) == key ? t : nullptr;
    }
    /// The side of tile `t`, in lattice units.
    uint32_t extentOf(const Tile& t) const { return 1u << uint32_t(maxLevel - t.level()); }

    const Adf& oldAdf;
    const Adf& newAdf;
    util::ThreadPool* pool;
    TileMap& tiles;
    std::function<TileMesh*(uint64_t)> ensureTile;
    int maxLevel;
    uint32_t slotShift;  ///< slot coordinates = lattice coordinates >> slotShift
    uint32_t slots;      ///< slots per axis
};

/// How the whole mesh's totals move (the tiles an update does not visit hold what they held).
struct TotalDeltas {
    int64_t crossings = 0, vertices = 0, splitEdges = 0, crossingSlots = 0;
};

// --- Phase 0: where the snapshots differ --------------------------------------------------------

/// The keys of the tiles the new snapshot does not share with the old one (of both snapshots,
/// sorted), and per key the cells where the old and the new tile differ.
struct RebuiltTiles {
    std::vector<uint64_t> keys;
    std::vector<std::vector<LatticeBox>> changedBoxes;
    /// Per key, where both tiles exist at one level: the old tile's node word at each box.
    std::vector<std::vector<uint32_t>> oldWords;
};

/// Phase 0a: finds the slots whose tiles differ, then compares each such tile cell by cell (a
/// tile that is new, gone or at another level differs as a whole).
/// In: both snapshots. Out: RebuiltTiles.
/// Complexity: O(root entries + slots of the chunks not shared) to find the slots (Adf::
/// forEachSlotDiffering), O(nodes) per tile compared.
/// Threading: parallel over the tiles, the largest rebuilt tile first (nearly always the edit's
/// crater): usually the caller takes it, as it takes the crater in every later phase and in the
/// edit that rebuilt it.
RebuiltTiles compareRebuiltTiles(const UpdateContext& ctx) {
    const Adf& oldAdf = ctx.oldAdf;
    const Adf& newAdf = ctx.newAdf;
    RebuiltTiles rebuilt;
    std::vector<uint64_t>& keys = rebuilt.keys;
    // The old tile of every TileMesh is the old snapshot's, so the keys of both are listed.
    newAdf.forEachSlotDiffering(oldAdf, [&](glm::uvec3 slot) {
        keys.push_back(packLattice(oldAdf.tileAtSlot(slot)->latticeOrigin()));
        keys.push_back(packLattice(newAdf.tileAtSlot(slot)->latticeOrigin()));
    });
    sortUnique(keys);
    rebuilt.changedBoxes.resize(keys.size());
    rebuilt.oldWords.resize(keys.size());
    auto nodes = [&](std::size_t i) {
        const Tile* t = ctx.tileOfKey(newAdf, keys[i]);
        return t ? t->nodeCount() : 0u;
    };
    util::parallelForHeaviestFirst(ctx.pool, keys.size(), nodes, [&](std::size_t i) {
        const Tile* was = ctx.tileOfKey(oldAdf, keys[i]);
        const Tile* now = ctx.tileOfKey(newAdf, keys[i]);
        std::vector<LatticeBox>& boxes = rebuilt.changedBoxes[i];
        if (was && now && was->level() == now->level()) {
            appendChangedCells(*was, *now, ctx.maxLevel, boxes, &rebuilt.oldWords[i]);
        } else {
            if (was) boxes.push_back({was->latticeOrigin(), ctx.extentOf(*was)});
            if (now) boxes.push_back({now->latticeOrigin(), ctx.extentOf(*now)});
        }
    });
    return rebuilt;
}

/// A tile whose closed box touches a changed cell: the bounding box of those cells.
struct Touched {
    glm::uvec3 lo{UINT32_MAX}, hi{0};
    uint32_t cells = 0;  ///< changed cells touching it: how much it has to scan
};
using TouchedTiles = std::unordered_map<uint64_t, Touched>;

/// Phase 0b: marks every changed cell in `changed` and finds, by key, the tiles of the new
/// snapshot whose closed box touches one (counted in st.changedCells).
/// Complexity: O(slots each changed cell touches), nearly always one or two. Serial.
TouchedTiles markChangedCells(const UpdateContext& ctx, const RebuiltTiles& rebuilt, ChangedCells& changed,
                              SurfaceNetsStats& st) {
    const uint32_t shift = ctx.slotShift;
    TouchedTiles touched;
    for (const std::vector<LatticeBox>& boxes : rebuilt.changedBoxes)
        for (const LatticeBox& b : boxes) {
            ++st.changedCells;
            changed.mark(b);
            const glm::uvec3 hi = b.lo + b.size;
            glm::uvec3 s0 = b.lo >> shift, s1 = glm::min(hi >> shift, glm::uvec3(ctx.slots - 1));
            for (int k = 0; k < 3; ++k)
                if (s0[k] > 0 && (b.lo[k] & ((1u << shift) - 1)) == 0) --s0[k];
            for (uint32_t z = s0.z; z <= s1.z; ++z)
                for (uint32_t y = s0.y; y <= s1.y; ++y)
                    for (uint32_t x = s0.x; x <= s1.x; ++x) {
                        Touched& t = touched[packLattice(ctx.newAdf.tileAtSlot({x, y, z})->latticeOrigin())];
                        t.lo = glm::min(t.lo, b.lo);
                        t.hi = glm::max(t.hi, hi);
                        ++t.cells;
                    }
        }
    return touched;
}

/// Phase 0c: points the state of each rebuilt tile at its new tile. A tile that is gone is
/// touched everywhere, so its scan removes every crossing it holds and re-meshing their cells
/// every vertex. Complexity: O(rebuilt tiles). Serial.
void followRebuiltTiles(const UpdateContext& ctx, const RebuiltTiles& rebuilt, TouchedTiles& touched) {
    for (uint64_t k : rebuilt.keys) {
        auto it = ctx.tiles.find(k);
        if (it == ctx.tiles.end()) continue;
        const Tile* now = ctx.tileOfKey(ctx.newAdf, k);
        if (!now) {
            Touched& t = touched[k];  // (its changed-cell count kept: it orders the scan)
            t.lo = glm::uvec3(0);
            t.hi = glm::uvec3(UINT32_MAX);
        } else if (now != it->second->tile) {
            setTile(ctx.newAdf, *now, *it->second);
        }
    }
}

/// The tiles whose crossings at changed cells are recomputed, by key, with what touches each.
struct ScanList {
    std::vector<TileMesh*> tiles;
    std::vector<Touched> boxes;
};

/// Phase 0d: the touched tiles that hold crossings or may emit some, by key (a touched tile of
/// the new snapshot gets its state here). Complexity: O(t log t), t touched tiles. Serial.
ScanList listTilesToScan(const UpdateContext& ctx, const TouchedTiles& touched) {
    std::vector<uint64_t> keys;
    for (const auto& [k, t] : touched) keys.push_back(k);
    std::sort(keys.begin(), keys.end());
    ScanList toScan;
    for (uint64_t k : keys) {
        auto it = ctx.tiles.find(k);
        TileMesh* tm = it != ctx.tiles.end() ? it->second.get() : nullptr;
        if (!tm) {
            const Tile* t = ctx.tileOfKey(ctx.newAdf, k);
            if (!t || !mayEmit(*t)) continue;  // emits nothing
            tm = ctx.ensureTile(k);
        }
        toScan.tiles.push_back(tm);
        toScan.boxes.push_back(touched.at(k));
    }
    return toScan;
}

// --- Phase 1: the crossings at changed cells, and the cells to re-mesh --------------------------

/// A scanned tile's leaf set, kept by the mesher across updates (SurfaceMesher::ScannedLeaves):
/// the boundary leaves its scan found near the changed cells, and their index by cell key.
struct ScannedLeavesRef {
    std::vector<BoundaryCell>& leaves;
    FlatMap64& byCell;
};

/// What rescanning one tile did to its crossings at changed cells.
struct TileRescan {
    std::vector<Crossing*> removed, added, kept;
    std::vector<uint32_t> released;  ///< the removed records' slots: read until the update ends
    SurfaceNetsStats st;
};

/// Where one tile's scan looks: the bounding box of the changed cells touching it, as a box and
/// as the one-box region the boundary-leaf walks take, and the changed cells themselves.
struct ScanRegion {
    Touched box;
    std::vector<LatticeBox> region;
    const ChangedCells::Query& changedAt;
    /// Only a leaf with a corner on a changed cell can emit (or have emitted) a crossing that
    /// starts on one: the walks test it before decoding a leaf (many in the box fail).
    LeafFilter cornerOnChanged;
};

/// Appends the keys of the leaves of `t` inside the cell at `origin` of `size`, where `t` holds
/// the node word `word` (appendChangedCells' beforeWords: a leaf's word for a brick's child).
/// Complexity: O(cells inside).
void appendLeafCellsIn(const Tile& t, uint32_t word, glm::uvec3 origin, uint32_t size, std::vector<uint64_t>& out) {
    if (adf::node::isLeaf(word)) {
        out.push_back(packLattice(origin));
        return;
    }
    const uint32_t half = size >> 1;
    for (uint32_t c = 0; c < 8; ++c) {
        const glm::uvec3 o = origin + glm::uvec3(c & 1, (c >> 1) & 1, c >> 2) * half;
        if (adf::node::isBrick(word))
            out.push_back(packLattice(o));
        else
            appendLeafCellsIn(t, t.node(word + c), o, half, out);
    }
}

/// Phase 1a, one tile: the old crossings that start on a changed cell in the scan's box, as
/// (key, slot) in `buffers.oldCrossings` (unsorted, a crossing may come twice). Each was emitted
/// by a boundary leaf of the old tile touching the region and is listed by that leaf's vertices,
/// found through the cell index (no scan of the tile's crossings). Where the tile was rebuilt
/// at its level, such a leaf is either in the new tile too (in `newLeaves`, which the new walk
/// found) or inside one of the cells the tile comparison found changed, so the old tile is not
/// walked again. Complexity: O(incidences of the leaves' vertices). Reads `tm`, and crossings of
/// other tiles only in fields no task writes in this phase.
void listOldCrossings(const UpdateContext& ctx, const RebuiltTiles& rebuilt, const TileMesh& tm, const Tile& was,
                      const Tile* now, bool current, const std::vector<BoundaryCell>& newLeaves,
                      const ScanRegion& scan, UpdateScratch& buffers) {
    const std::vector<uint64_t>& rebuiltKeys = rebuilt.keys;
    std::vector<KeyedIndex>& oldCrossings = buffers.oldCrossings;  // (key, slot)
    std::vector<uint64_t>& oldCells = buffers.oldCells;
    std::size_t compared = rebuiltKeys.size();  // the tile comparison's entry for it
    if (current && &was != now && was.level() == now->level()) {
        const auto at = std::lower_bound(rebuiltKeys.begin(), rebuiltKeys.end(), tm.key);
        compared = std::size_t(at - rebuiltKeys.begin());
        if (compared == rebuiltKeys.size() || rebuiltKeys[compared] != tm.key)
            throw std::logic_error("surface nets: a rebuilt tile was not compared");
    }
    if (&was == now || compared < rebuiltKeys.size()) {
        for (const BoundaryCell& e : newLeaves) oldCells.push_back(packLattice(e.origin));
        if (compared < rebuiltKeys.size())
            for (std::size_t k = 0; k < rebuilt.changedBoxes[compared].size(); ++k) {
                const LatticeBox& b = rebuilt.changedBoxes[compared][k];
                appendLeafCellsIn(was, rebuilt.oldWords[compared][k], b.lo, b.size, oldCells);
            }
    } else {
        std::vector<BoundaryCell>& wasLeaves = buffers.oldLeaves;
        wasLeaves.clear();
        appendBoundaryCellsTouching(was, ctx.maxLevel, scan.region, wasLeaves, scan.cornerOnChanged);
        for (const BoundaryCell& e : wasLeaves) oldCells.push_back(packLattice(e.origin));
    }
    for (const uint64_t cell : oldCells) {
        const uint32_t* firstVertex = tm.cellVertex.find(cell);
        if (!firstVertex) continue;
        for (uint32_t vi = *firstVertex; vi != UINT32_MAX; vi = tm.vertices[vi].nextInCell) {
            const Vertex& v = tm.vertices[vi];
            for (uint32_t j = v.incBegin; j < v.incEnd; ++j) {
                // Another tile's crossing: only fields no task writes in this phase.
                const Crossing& x = *tm.incidences[j].x;
                // Emitted by this cell (a cell of this tile: its vertex is the tile's).
                if (x.ringCell[x.emitter] != cell) continue;
                const glm::uvec3 start = x.start();
                if (inBox(start, scan.box.lo, scan.box.hi) && scan.changedAt.pointChanged(start))
                    oldCrossings.emplace_back(x.key(), x.slot);
            }
        }
    }
}

/// Phase 1a, one tile: merges its old crossings at changed cells (`oldCrossings`, (key, slot),
/// sorted and unique) with the fresh ones by key. An old one without a fresh one is removed, a
/// fresh one without an old one added, and a pair is kept in place if it is the same record
/// with each ring cell in a tile of the same key (else replaced). Records never move:
/// `freshByKey` is scratch for the fresh ones' order. Complexity: O(f log f + o). Writes only
/// `tm`'s records.
void mergeCrossings(const UpdateContext& ctx, TileMesh& tm, const std::vector<KeyedIndex>& oldCrossings,
                    const std::vector<Crossing>& fresh, std::vector<KeyedIndex>& freshByKey, TileRescan& out) {
    freshByKey.resize(fresh.size());
    for (uint32_t j = 0; j < fresh.size(); ++j) freshByKey[j] = {fresh[j].key(), j};
    std::sort(freshByKey.begin(), freshByKey.end());
    auto remove = [&](uint32_t j) {
        Crossing& x = tm.crossings[j];
        x.alive = 0;
        --tm.liveCrossings;
        tm.plainTriangles -= plainTriangles(x);
        out.removed.push_back(&x);
        out.released.push_back(j);
    };
    auto add = [&](const Crossing& x) {
        // A slot an earlier update released (its record is read by nobody since), else a new
        // one; never one released in this update: removed records are read until its end.
        const uint32_t j = tm.crossings.allocate();
        tm.crossings[j] = x;
        tm.crossings[j].slot = j;
        ++tm.liveCrossings;
        tm.plainTriangles += plainTriangles(x);
        out.added.push_back(&tm.crossings[j]);
    };
    std::size_t o = 0, f = 0;  // next in `oldCrossings`, in `freshByKey`
    while (o < oldCrossings.size() || f < freshByKey.size()) {
        if (f == freshByKey.size() || (o < oldCrossings.size() && oldCrossings[o].first < freshByKey[f].first)) {
            remove(oldCrossings[o++].second);
        } else if (o == oldCrossings.size() || freshByKey[f].first < oldCrossings[o].first) {
            add(fresh[freshByKey[f++].second]);
        } else {
            Crossing& x = tm.crossings[oldCrossings[o].second];
            const Crossing& y = fresh[freshByKey[f].second];
            // The same record, and each ring cell in a tile of the same key: the vertex refs
            // it keeps name the tiles that hold those cells now. (Generated coarse tiles are
            // single leaves, so equal cells and levels imply it; a loaded file's need not be.)
            bool same = x.sameAs(y);
            for (int q = 0; q < 4 && same; ++q)
                same = ownerKey(ctx.oldAdf, x.ringCell[q]) == ownerKey(ctx.newAdf, x.ringCell[q]);
            if (same) {
                out.kept.push_back(&x);
            } else {
                remove(oldCrossings[o].second);
                add(y);
            }
            ++o;
            ++f;
        }
    }
}

/// Phase 1a, one tile: recomputes its crossings that start on a changed cell. The new tile's
/// boundary leaves near the changed cells go to `scanned` (with their index by cell, for the
/// cells phase), the crossings they emit there are computed afresh and merged with the old ones.
/// A tile that is gone only loses its old crossings. Complexity: O(leaves in the box + their
/// crossings). Writes only `tm`, `scanned` and `out`; uses this thread's UpdateScratch.
void rescanTile(const UpdateContext& ctx, const RebuiltTiles& rebuilt, const ChangedCells& changed, TileMesh& tm,
                const Touched& box, const ScannedLeavesRef& scanned, TileRescan& out) {
    indexCells(tm);
    const ChangedCells::Query changedAt(changed);
    const glm::uvec3 hi = glm::min(box.hi, glm::uvec3(ctx.newAdf.domain().latticeSize()));
    const ScanRegion scan{box,
                          {{box.lo, std::max({hi.x - box.lo.x, hi.y - box.lo.y, hi.z - box.lo.z})}},
                          changedAt,
                          {[](const void* q, glm::uvec3 lo, uint32_t size) {
                               return static_cast<const ChangedCells::Query*>(q)->cornerChanged(lo, size);
                           },
                           &changedAt}};
    UpdateScratch& buffers = updateScratch();
    std::vector<KeyedIndex>& oldCrossings = buffers.oldCrossings;  // (key, slot)
    std::vector<BoundaryCell>& leaves = scanned.leaves;  // the new tile's (none if it is gone)
    oldCrossings.clear();
    leaves.clear();
    buffers.oldCells.clear();
    const Tile* now = ctx.tileOfKey(ctx.newAdf, tm.key);
    const bool current = now == tm.tile;  // else the tile is gone: only old crossings go
    const Tile* was = nullptr;
    if (tm.liveCrossings > 0) {
        was = ctx.tileOfKey(ctx.oldAdf, tm.key);
        if (!was) throw std::logic_error("surface nets: a tile's crossings outlived its tile");
    }
    if (current) appendBoundaryCellsTouching(*now, ctx.maxLevel, scan.region, leaves, scan.cornerOnChanged);
    if (was) listOldCrossings(ctx, rebuilt, tm, *was, now, current, leaves, scan, buffers);
    std::vector<Crossing>& fresh = buffers.fresh;
    fresh.clear();
    if (current) {
        out.st.boundaryLeaves = leaves.size();
        const StartFilter onChanged{[](const void* q, glm::uvec3 p) {
                                        return static_cast<const ChangedCells::Query*>(q)->pointChanged(p);
                                    },
                                    &changedAt};
        computeCrossings(ctx.newAdf, *now, leaves, fresh, out.st, onChanged);
    }
    scanned.byCell.clear();
    if (current) {
        scanned.byCell.reserve(leaves.size());
        for (uint32_t j = 0; j < leaves.size(); ++j) scanned.byCell.assign(packLattice(leaves[j].origin), j);
    }
    sortUnique(oldCrossings);  // a cell of both tiles may come twice
    mergeCrossings(ctx, tm, oldCrossings, fresh, buffers.freshByKey, out);
}

/// Phase 1a: recomputes the crossings that start on a changed cell, by the tiles that can emit
/// them (a crossing depends only on the leaves around its start point and on its emitter's
/// corners, so the others stay as they are).
/// In: the touched tiles and their boxes. Out: per tile, the crossings removed, added and kept;
/// the new tiles' leaves near the changed cells in `scanned` (one per tile to scan).
/// Complexity: O(leaves near the changed cells + their crossings).
/// Threading: parallel over tiles, busiest first (an edit's crater tile holds most of the work:
/// the other threads take the small ones and all finish together); results do not depend on it.
std::vector<TileRescan> rescanCrossings(const UpdateContext& ctx, const RebuiltTiles& rebuilt,
                                        const ChangedCells& changed, const ScanList& toScan,
                                        const std::vector<ScannedLeavesRef>& scanned) {
    std::vector<TileRescan> scans(toScan.tiles.size());
    auto changedCells = [&](std::size_t i) { return toScan.boxes[i].cells; };
    util::parallelForHeaviestFirst(ctx.pool, toScan.tiles.size(), changedCells, [&](std::size_t i) {
        rescanTile(ctx, rebuilt, changed, *toScan.tiles[i], toScan.boxes[i], scanned[i], scans[i]);
    });
    return scans;
}

/// The crossing records `tiles` hold, live or released. Only a scanned tile's pool can grow, and
/// only a dropped tile's records go: the whole mesh's record count moves by those, as the other
/// totals do (not a pass over every tile per update).
int64_t crossingSlotsOf(const std::vector<TileMesh*>& tiles) {
    int64_t slots = 0;
    for (const TileMesh* tm : tiles) slots += int64_t(tm->crossings.size());
    return slots;
}

/// A cell to re-mesh (each once), numbered as it was queued; re-meshed by tile, then cell.
struct CellTask {
    uint64_t owner, cell;
    uint32_t number;
    bool operator<(const CellTask& o) const { return owner != o.owner ? owner < o.owner : cell < o.cell; }
};

/// The cells to re-mesh, each once, sorted by tile then cell, and the crossings each gains.
struct RemeshQueue {
    std::vector<CellTask> cells;
    /// Cell i's added crossings are added[addedBegin[i]..addedBegin[i + 1]) (in scan order).
    std::vector<uint32_t> addedBegin;
    std::vector<Crossing*> added;
};

/// Phase 1b: adds the scans' counters to `st`, and their crossings added and removed to `deltas`.
/// Complexity: O(tiles scanned). Serial.
void addRescanCounts(const std::vector<TileRescan>& scans, SurfaceNetsStats& st, TotalDeltas& deltas) {
    for (const TileRescan& s : scans) {
        deltas.crossings += int64_t(s.added.size()) - int64_t(s.removed.size());
        st.boundaryLeaves += s.st.boundaryLeaves;
        st.openCrossings += s.st.openCrossings;
        st.crossingsComputed += s.st.crossingsComputed;
    }
}

/// Phase 1c: the cells whose vertices are recomputed: every ring cell of a removed or added
/// crossing (a cell's vertices depend on the crossings around it), and every changed cell a
/// kept crossing names (its corners changed). Removed crossings name their cells' owners in
/// the old snapshot, the others in the new one.
/// In: the scans. Out: RemeshQueue. Complexity: O(c log c) in the c cells queued, O(1) per
/// crossing's mention. Serial.
RemeshQueue queueCellsToRemesh(const UpdateContext& ctx, const ChangedCells& changed,
                               const std::vector<TileRescan>& scans) {
    RemeshQueue queue;
    std::vector<CellTask>& cells = queue.cells;
    const ChangedCells::Query changedAt(changed);
    // A cell is named by each of its crossings (about four): it is queued once (a cell key
    // names one cell of one tile) and its added crossings are grouped by its number, so the
    // sort sees only the distinct cells.
    FlatMap64 queued;  // cell -> number
    auto queueCell = [&](uint64_t owner, uint64_t cell) {
        const uint32_t number = queued.findOrAssign(cell, uint32_t(cells.size()));
        if (number == cells.size()) cells.push_back({owner, cell, number});
        return number;
    };
    std::vector<std::pair<uint32_t, Crossing*>> addedAt;  // (cell number, crossing)
    {
        // Room for them at once, so the map is not rehashed as it grows. A cell has about four
        // crossings and a crossing four cells, so the cells come to about as many as the
        // crossings named.
        std::size_t crossings = 0, addedMentions = 0;
        for (const TileRescan& s : scans) {
            crossings += s.removed.size() + s.added.size() + s.kept.size();
            addedMentions += 4 * s.added.size();
        }
        queued.reserve(crossings);
        cells.reserve(crossings);
        addedAt.reserve(addedMentions);
    }
    for (const TileRescan& s : scans) {
        for (Crossing* x : s.removed)
            for (int q = 0; q < 4; ++q) queueCell(ownerKey(ctx.oldAdf, x->ringCell[q]), x->ringCell[q]);
        for (Crossing* x : s.added)
            for (int q = 0; q < 4; ++q)
                if (std::find(x->ringCell, x->ringCell + q, x->ringCell[q]) == x->ringCell + q)
                    addedAt.emplace_back(queueCell(ownerKey(ctx.newAdf, x->ringCell[q]), x->ringCell[q]), x);
        for (Crossing* x : s.kept)
            for (int q = 0; q < 4; ++q)
                if (changedAt.unitChanged(unpackLattice(x->ringCell[q])))
                    queueCell(ownerKey(ctx.newAdf, x->ringCell[q]), x->ringCell[q]);
    }
    std::sort(cells.begin(), cells.end());
    // Added crossings by cell (a counting sort by each cell's rank in the sorted queue).
    std::vector<uint32_t> rank(cells.size());
    for (uint32_t i = 0; i < cells.size(); ++i) rank[cells[i].number] = i;
    queue.added.resize(addedAt.size());
    groupByRank(addedAt.size(), rank, queue.addedBegin, [&](std::size_t j) { return addedAt[j].first; },
                [&](std::size_t j, uint32_t at) { queue.added[at] = addedAt[j].second; });
    return queue;
}

// --- Phase 2: the queued cells re-meshed --------------------------------------------------------

/// The tiles holding cells to re-mesh, in queue order (by key), and each one's run of the queue.
struct RemeshTiles {
    std::vector<TileMesh*> tiles;
    /// Tile i's cells are queue.cells[cellBegin[i]..cellBegin[i + 1]).
    std::vector<std::size_t> cellBegin;
};

/// Phase 2a: the tiles owning the queued cells (a tile of the new snapshot gets its state here).
/// Complexity: O(queued cells). Serial.
RemeshTiles listTilesToRemesh(const UpdateContext& ctx, const RemeshQueue& queue) {
    const std::vector<CellTask>& cells = queue.cells;
    RemeshTiles toRemesh;
    for (std::size_t i = 0; i < cells.size(); ++i) {
        if (i > 0 && cells[i].owner == cells[i - 1].owner) continue;
        auto it = ctx.tiles.find(cells[i].owner);
        TileMesh* tm = it != ctx.tiles.end() ? it->second.get() : ctx.ensureTile(cells[i].owner);
        if (!tm) throw std::logic_error("surface nets: a crossing's cell has no tile");
        toRemesh.tiles.push_back(tm);
        toRemesh.cellBegin.push_back(i);
    }
    toRemesh.cellBegin.push_back(cells.size());
    return toRemesh;
}

/// Phase 2b: this update's mark, from the mesher's counter `stamp`: set on the vertices it makes,
/// then on those it relaxes because they read one, so each is relaxed once. When the counter
/// wraps, every tile's marks are cleared (O(vertices), once in 2^32 updates). Serial.
uint32_t nextRelaxMark(TileMap& tiles, uint32_t& stamp) {
    if (++stamp == 0) {  // wrapped: clear every mark
        for (const auto& [key, tm] : tiles)
            for (Projected& p : tm->projected) p.relaxStamp = 0;
        stamp = 1;
    }
    return stamp;
}

/// Phase 2c, one cell: releases its old vertices, appending the incidences of their crossings
/// that are still alive (the kept ones) to `incidences`. An unchanged cell (its origin is on no
/// changed cell: changed cells are whole octree cells) keeps its corners: copied to `corners`,
/// and then it returns true.
bool takeOldVertices(TileMesh& tm, uint64_t cell, const ChangedCells::Query& cellChanged,
                     std::vector<Incidence>& incidences, float corners[8]) {
    const uint32_t* firstVertex = tm.cellVertex.find(cell);
    if (!firstVertex) return false;
    bool haveCorners = false;
    if (!cellChanged.unitChanged(unpackLattice(cell))) {
        std::copy(tm.vertices[*firstVertex].corners, tm.vertices[*firstVertex].corners + 8, corners);
        haveCorners = true;
    }
    for (uint32_t vi = *firstVertex; vi != UINT32_MAX;) {
        const Vertex& v = tm.vertices[vi];
        for (uint32_t j = v.incBegin; j < v.incEnd; ++j) {
            const VertexIncidence& in = tm.incidences[j];
            if (in.x->alive) incidences.push_back({cell, in.x->key(), in.x, in.first, in.last});
        }
        tm.liveIncidences -= v.incEnd - v.incBegin;
        const uint32_t nextVi = v.nextInCell;
        tm.releaseVertex(vi);
        vi = nextVi;
    }
    tm.cellVertex.erase(cell);
    return haveCorners;
}

/// Phase 2c, one cell: appends the incidences of queued cell `t` (at key `cell`) with the
/// crossings it gains.
void appendAddedIncidences(const RemeshQueue& queue, std::size_t t, uint64_t cell,
                           std::vector<Incidence>& incidences) {
    for (uint32_t k = queue.addedBegin[t]; k < queue.addedBegin[t + 1]; ++k) {
        Crossing* x = queue.added[k];
        const int q = int(std::find(x->ringCell, x->ringCell + 4, cell) - x->ringCell);
        uint8_t first, last;
        incidenceRun(*x, q, first, last);
        incidences.push_back({cell, x->key(), x, first, last});
    }
}

/// Phase 2c, one cell: its corners in the new snapshot. A re-meshed cell near a changed one is
/// nearly always a leaf its tile's scan found (`scanned`, null if the tile was not scanned);
/// else the leaf is looked up.
void newCorners(const Adf& newAdf, const ScannedLeavesRef* scanned, uint64_t cell, float corners[8]) {
    if (const uint32_t* j = scanned ? scanned->byCell.find(cell) : nullptr) {
        std::copy(scanned->leaves[*j].corners, scanned->leaves[*j].corners + 8, corners);
    } else {  // a cell without a sign change, or in a tile not scanned
        const adf::LeafRef leaf = newAdf.findLeaf(unpackLattice(cell));
        std::copy(leaf.corners, leaf.corners + 8, corners);
    }
}

/// Rebuilds `tm`'s incidence list when most of it belongs to re-meshed vertices.
void compactIncidences(TileMesh& tm) {
    if (tm.incidences.size() < 2 * tm.liveIncidences + 1024) return;
    std::vector<VertexIncidence> kept;
    kept.reserve(tm.liveIncidences);
    for (Vertex& v : tm.vertices) {
        if (!v.alive) continue;
        const uint32_t begin = uint32_t(kept.size());
        kept.insert(kept.end(), tm.incidences.begin() + v.incBegin, tm.incidences.begin() + v.incEnd);
        v.incBegin = begin;
        v.incEnd = uint32_t(kept.size());
    }
    tm.incidences.swap(kept);
}

/// Phase 2c, one tile: re-meshes its queued cells queue.cells[begin..end) in order, each from
/// all its crossings (the kept ones from its old vertices, which go, and the added ones); the
/// cells' multi-crossing faces are found again. The vertices made carry `relaxMark` and are
/// appended to `made`, the tile's counters to `stats`. Complexity: O(incidences of the cells).
/// Writes only `tm` (and its crossings' slots of these cells); uses this thread's UpdateScratch.
void remeshTile(const UpdateContext& ctx, const ChangedCells& changed, const RemeshQueue& queue, std::size_t begin,
                std::size_t end, TileMesh& tm, const ScannedLeavesRef* scanned, uint32_t relaxMark,
                SurfaceNetsStats& stats, std::vector<VertexRef>& made) {
    const std::vector<CellTask>& cells = queue.cells;
    indexCells(tm);  // (a safeguard: a tile with cells to re-mesh touches a changed cell, so its scan indexed it)
    // The re-meshed cells' multi-crossing faces are found again by meshCell.
    const auto cellFirst = cells.begin() + std::ptrdiff_t(begin), cellEnd = cells.begin() + std::ptrdiff_t(end);
    std::erase_if(tm.multiFaces, [&](const MultiFace& mf) {
        const auto at = std::lower_bound(cellFirst, cellEnd, mf.cellA,
                                         [](const CellTask& t, uint64_t c) { return t.cell < c; });
        return at != cellEnd && at->cell == mf.cellA;
    });
    UpdateScratch& buffers = updateScratch();
    CellScratch& cellScratch = buffers.cell;
    cellScratch.freshCrossings = false;
    std::vector<Incidence>& incidences = buffers.incidences;
    const ChangedCells::Query cellChanged(changed);
    for (std::size_t t = begin; t < end; ++t) {
        const uint64_t cell = cells[t].cell;
        ++stats.cellsMeshed;
        incidences.clear();
        float corners[8];
        const bool haveCorners = takeOldVertices(tm, cell, cellChanged, incidences, corners);
        appendAddedIncidences(queue, t, cell, incidences);
        std::sort(incidences.begin(), incidences.end(),
                  [](const Incidence& l, const Incidence& r) { return l.crossingKey < r.crossingKey; });
        if (incidences.empty()) continue;
        if (!haveCorners) newCorners(ctx.newAdf, scanned, cell, corners);
        bool anyIn = false, anyOut = false;
        for (float v : corners) (v < 0.0f ? anyIn : anyOut) = true;
        if (!(anyIn && anyOut)) ++stats.signlessCells;
        const std::size_t incBefore = tm.incidences.size();
        const uint32_t first =
            meshCell(ctx.newAdf, tm, incidences.data(), uint32_t(incidences.size()), corners, cellScratch, stats);
        tm.liveIncidences += tm.incidences.size() - incBefore;
        tm.cellVertex.assign(cell, first);
        for (uint32_t vi = first; vi != UINT32_MAX; vi = tm.vertices[vi].nextInCell) {
            tm.projected[vi].relaxStamp = relaxMark;
            made.push_back({&tm, vi});
        }
    }
    compactIncidences(tm);
}

/// Phase 2c: re-meshes the queued cells: all their vertices, from scratch (cycles and first
/// projection, computed as a build does: incidences sorted by crossing key).
/// In: the queue, the tiles owning its cells, the scans' leaves (`scanned`, one per tile of
/// `toScan`). Out: per tile, the vertices made (marked with `relaxMark`); counters in `st`, the
/// vertex total's move in `deltas`. Complexity: O(incidences of the queued cells).
/// Threading: parallel over tiles, most cells first, as the scan.
std::vector<std::vector<VertexRef>> remeshCells(const UpdateContext& ctx, const ChangedCells& changed,
                                                const RemeshQueue& queue, const RemeshTiles& toRemesh,
                                                const ScanList& toScan, const std::vector<ScannedLeavesRef>& scanned,
                                                uint32_t relaxMark, SurfaceNetsStats& st, TotalDeltas& deltas) {
    const std::vector<TileMesh*>& tiles = toRemesh.tiles;
    const std::vector<std::size_t>& cellBegin = toRemesh.cellBegin;
    for (const TileMesh* tm : tiles) deltas.vertices -= tm->liveVertices;
    std::vector<SurfaceNetsStats> tileStats(tiles.size());
    std::vector<std::vector<VertexRef>> made(tiles.size());
    FlatMap64 scanOf;  // tile key -> its index in toScan
    for (uint32_t i = 0; i < toScan.tiles.size(); ++i) scanOf.assign(toScan.tiles[i]->key, i);
    auto cellsToMesh = [&](std::size_t ti) { return cellBegin[ti + 1] - cellBegin[ti]; };
    util::parallelForHeaviestFirst(ctx.pool, tiles.size(), cellsToMesh, [&](std::size_t ti) {
        TileMesh& tm = *tiles[ti];
        const uint32_t* scanIndex = scanOf.find(tm.key);
        const ScannedLeavesRef* leaves = scanIndex ? &scanned[*scanIndex] : nullptr;
        remeshTile(ctx, changed, queue, cellBegin[ti], cellBegin[ti + 1], tm, leaves, relaxMark, tileStats[ti],
                   made[ti]);
    });
    for (const TileMesh* tm : tiles) deltas.vertices += tm->liveVertices;
    st.tilesMeshed = tiles.size();
    for (const SurfaceNetsStats& s : tileStats) {
        st.cellsMeshed += s.cellsMeshed;
        addVertexCounters(st, s);
    }
    return made;
}

// --- Phase 3: split vertices and relaxation -----------------------------------------------------

/// Phase 3a: recomputes the split vertices (rare) of the re-meshed tiles and their neighbours:
/// a multi-crossing face lies between two adjacent cells, so its owner is the tile of a
/// re-meshed cell or a neighbour of it. Complexity: O(multi-crossing faces of those tiles).
/// Serial.
void splitFacesNear(const UpdateContext& ctx, const RemeshTiles& toRemesh, TotalDeltas& deltas) {
    std::vector<uint64_t> nearKeys;
    for (const TileMesh* tm : toRemesh.tiles) neighbourKeys(ctx.newAdf, tm->slotMin, tm->slotEnd, nearKeys);
    sortUnique(nearKeys);
    for (uint64_t k : nearKeys) {
        auto it = ctx.tiles.find(k);
        if (it == ctx.tiles.end() || (it->second->multiFaces.empty() && it->second->splits.empty())) continue;
        deltas.splitEdges -= int64_t(it->second->splits.size());
        splitFaces(*it->second);
        deltas.splitEdges += int64_t(it->second->splits.size());
    }
}

/// Relaxes `list` in blocks of vertices (each vertex is independent: it reads its neighbours'
/// `projected` and writes its own position, so blocks, not one pool hand-off each). With
/// `unmarked`, block b reports in (*unmarked)[b] the neighbours it read that do not carry
/// `relaxMark`. Threading: parallel over blocks.
void relaxBlocks(util::ThreadPool* pool, const std::vector<VertexRef>& list, uint32_t relaxMark,
                 std::vector<std::vector<VertexRef>>* unmarked) {
    constexpr std::size_t kRelaxBlock = 512;
    const std::size_t blocks = (list.size() + kRelaxBlock - 1) / kRelaxBlock;
    if (unmarked) unmarked->resize(blocks);
    util::parallelFor(pool, blocks, [&](std::size_t b) {
        const std::size_t first = b * kRelaxBlock, end = std::min(list.size(), first + kRelaxBlock);
        relaxInOrder(end - first, [&](std::size_t k) { return list[first + k]; },
                     unmarked ? UnmarkedNeighbours{&(*unmarked)[b], relaxMark} : UnmarkedNeighbours{});
    });
}

/// Phase 3b: relaxes the new vertices (`made`, per re-meshed tile), then every vertex that reads
/// one of them (a position after relaxation depends on the neighbours' projected vertices),
/// each once. Relaxing the new vertices reports the unmarked vertices that read them (found on
/// the way, not listed beforehand on one thread from every ring cell of every new vertex's
/// crossings); those are marked in report order and relaxed after.
/// Returns how many were relaxed. Complexity: O(relaxed vertices x their incidences).
/// Threading: parallel over blocks of vertices; the marking between the two passes is serial.
std::size_t relaxNewVertices(const UpdateContext& ctx, const std::vector<std::vector<VertexRef>>& made,
                             uint32_t relaxMark) {
    std::vector<VertexRef> newVertices;
    for (const std::vector<VertexRef>& list : made) newVertices.insert(newVertices.end(), list.begin(), list.end());
    std::vector<std::vector<VertexRef>> readers;
    relaxBlocks(ctx.pool, newVertices, relaxMark, &readers);
    std::vector<VertexRef> readersToRelax;
    for (const std::vector<VertexRef>& list : readers)
        for (const VertexRef& r : list) {
            Projected& reader = r.tile->projected[r.index];
            if (reader.relaxStamp == relaxMark) continue;
            reader.relaxStamp = relaxMark;
            readersToRelax.push_back(r);
        }
    relaxBlocks(ctx.pool, readersToRelax, relaxMark, nullptr);
    return newVertices.size() + readersToRelax.size();
}

// --- Phase 4: released records, dropped tiles, totals -------------------------------------------

/// Phase 4a: releases the removed crossing records, which the next update may reuse (not this
/// one: they were read until now). Complexity: O(removed crossings). Serial.
void releaseRemovedCrossings(const ScanList& toScan, const std::vector<TileRescan>& scans, TotalDeltas& deltas) {
    for (std::size_t i = 0; i < toScan.tiles.size(); ++i) {
        for (uint32_t j : scans[i].released) toScan.tiles[i]->crossings.release(j);
        deltas.crossingSlots += int64_t(toScan.tiles[i]->crossings.size());
    }
}

/// Phase 4b: drops the state of the tiles that are gone (which must be empty by now) and of the
/// tiles left empty (only a visited tile can become empty). Complexity: O(visited tiles). Serial.
void dropEmptiedTiles(const UpdateContext& ctx, const RebuiltTiles& rebuilt, const ScanList& toScan,
                      const RemeshTiles& toRemesh, TotalDeltas& deltas) {
    std::vector<uint64_t> emptied;
    for (uint64_t k : rebuilt.keys) {
        auto it = ctx.tiles.find(k);
        if (it == ctx.tiles.end() || ctx.tileOfKey(ctx.newAdf, k)) continue;
        if (it->second->liveCrossings || it->second->liveVertices)
            throw std::logic_error("surface nets: a tile that is gone still holds mesh");
        emptied.push_back(k);
    }
    for (const std::vector<TileMesh*>* list : {&toScan.tiles, &toRemesh.tiles})
        for (const TileMesh* tm : *list)
            if (tm->liveCrossings == 0 && tm->liveVertices == 0) emptied.push_back(tm->key);
    sortUnique(emptied);
    for (uint64_t k : emptied) {
        auto it = ctx.tiles.find(k);
        deltas.splitEdges -= int64_t(it->second->splits.size());
        deltas.crossingSlots -= int64_t(it->second->crossings.size());
        ctx.tiles.erase(it);
    }
}

/// Phase 4c: the whole mesh's totals in `st`: those `before` the update moved by `deltas`.
void addTotals(const SurfaceNetsStats& before, const TotalDeltas& deltas, SurfaceNetsStats& st) {
    st.crossings = std::size_t(int64_t(before.crossings) + deltas.crossings);
    st.vertices = std::size_t(int64_t(before.vertices) + deltas.vertices);
    st.splitEdges = std::size_t(int64_t(before.splitEdges) + deltas.splitEdges);
    st.crossingSlots = std::size_t(int64_t(before.crossingSlots) + deltas.crossingSlots);
}

}  // namespace

void SurfaceMesher::update(adf::AdfPtr next) {
    if (!next) throw std::invalid_argument("surface nets: no snapshot");
    if (!mAdf || !(next->domain() == mAdf->domain())) {
        build(std::move(next));
        return;
    }
    const auto tStart = std::chrono::steady_clock::now();
    const adf::AdfPtr before = std::move(mAdf);  // its tiles stay alive until the update is done
    mAdf = std::move(next);
    const UpdateContext ctx(*before, *mAdf, mPool, mTiles, [this](uint64_t key) { return ensureTile(key); });
    SurfaceNetsStats st;
    TotalDeltas deltas;

    // 0. Where the snapshots differ: the changed cells, and the tiles they touch.
    const RebuiltTiles rebuilt = compareRebuiltTiles(ctx);
    ChangedCells changed(ctx.newAdf);
    TouchedTiles touched = markChangedCells(ctx, rebuilt, changed, st);
    followRebuiltTiles(ctx, rebuilt, touched);
    const ScanList toScan = listTilesToScan(ctx, touched);

    // 1. The crossings starting on a changed cell, recomputed; the cells around those that
    // changed, and the changed cells, queued.
    while (mScanned.size() < toScan.tiles.size()) mScanned.push_back(std::make_unique<ScannedLeaves>());
    std::vector<ScannedLeavesRef> scanned;
    scanned.reserve(toScan.tiles.size());
    for (std::size_t i = 0; i < toScan.tiles.size(); ++i)
        scanned.push_back({mScanned[i]->leaves, mScanned[i]->byCell});
    deltas.crossingSlots -= crossingSlotsOf(toScan.tiles);
    const std::vector<TileRescan> scans = rescanCrossings(ctx, rebuilt, changed, toScan, scanned);
    st.tilesScanned = toScan.tiles.size();
    addRescanCounts(scans, st, deltas);
    const RemeshQueue queue = queueCellsToRemesh(ctx, changed, scans);
    const auto tPhase1 = std::chrono::steady_clock::now();

    // 2. The queued cells: all their vertices, from scratch.
    const RemeshTiles toRemesh = listTilesToRemesh(ctx, queue);
    const uint32_t relaxMark = nextRelaxMark(mTiles, mRelaxStamp);
    const std::vector<std::vector<VertexRef>> made =
        remeshCells(ctx, changed, queue, toRemesh, toScan, scanned, relaxMark, st, deltas);
    const auto tPhase2 = std::chrono::steady_clock::now();

    // 3. Split vertices near the re-meshed cells; relaxation of the new vertices and their readers.
    splitFacesNear(ctx, toRemesh, deltas);
    st.verticesRelaxed = relaxNewVertices(ctx, made, relaxMark);

    // 4. Removed records released, empty tiles dropped, totals.
    // The scans' leaf sets stay for the next update's room, as many as this one scanned (one
    // large edit does not keep hundreds of them for every dab after it).
    mScanned.resize(toScan.tiles.size());
    releaseRemovedCrossings(toScan, scans, deltas);
    dropEmptiedTiles(ctx, rebuilt, toScan, toRemesh, deltas);
    const auto tPhase3 = std::chrono::steady_clock::now();
    auto ms = [](auto from, auto to) { return std::chrono::duration<double, std::milli>(to - from).count(); };
    st.crossingMs = ms(tStart, tPhase1);
    st.vertexMs = ms(tPhase1, tPhase2);
    st.relaxMs = ms(tPhase2, tPhase3);
    addTotals(mStats, deltas, st);
#ifndef NDEBUG
    SurfaceNetsStats recount;
    totals(recount);
    assert(recount.crossingSlots == st.crossingSlots && "surface nets: the record count drifted");
#endif
    mStats = st;
}

}  // namespace kizamu::mesh
