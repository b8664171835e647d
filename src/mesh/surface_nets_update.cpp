// SPDX-License-Identifier: Apache-2.0
/// @file surface_nets_update.cpp
/// @brief SurfaceMesher::update: sub-tile re-meshing after an edit; its phases 0 and 1 (where
/// the snapshots differ, the crossings there, the cells to re-mesh).
///
/// Takes the mesher's state for the previous snapshot and the new snapshot; leaves the state of
/// the new one, whose mesh equals a build's bit for bit. update() calls its phases in order, one
/// function each (an UpdateContext carries the snapshots, the pool and the tiles; what the
/// phases pass on is in surface_nets_update.h):
///   0. compareRebuiltTiles, markChangedCells, followRebuiltTiles, listTilesToScan: the tiles the
///      snapshots do not share, the cells where they differ (ChangedCells,
///      surface_nets_changed_cells.h), the tiles they touch. Here.
///   1. rescanCrossings, queueCellsToRemesh: the crossings starting on a changed cell recomputed
///      (removed, added or kept in place), and the cells whose vertices that changes queued. Here.
///   2. listTilesToRemesh, remeshCells: the queued cells' vertices, from scratch.
///   3. splitFacesNear, relaxNewVertices: split vertices near them; relaxation of the new
///      vertices and of the vertices that read them.
///   4. releaseRemovedCrossings, dropEmptiedTiles, addTotals.
///   (2-4 in surface_nets_remesh.cpp.)
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
#include "mesh/surface_nets_update.h"
#include "adf/tile_diff.h"
#include "util/thread_pool.h"

#include <algorithm>
#include <cassert>
#include <chrono>
#include <stdexcept>

namespace kizamu::mesh {

using adf::Adf;
using adf::Tile;
using namespace detail;

namespace detail {

UpdateScratch& updateScratch() {
    thread_local UpdateScratch s;
    return s;
}

}  // namespace detail

namespace {

inline bool inBox(glm::uvec3 p, glm::uvec3 lo, glm::uvec3 hi) {
    return p.x >= lo.x && p.y >= lo.y && p.z >= lo.z && p.x <= hi.x && p.y <= hi.y && p.z <= hi.z;
}

// --- Phase 0: where the snapshots differ --------------------------------------------------------

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

/// The touched tiles, by key.
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
                const Touched& box, ScannedLeaves& scanned, TileRescan& out) {
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
                                        const std::vector<ScannedLeaves*>& scanned) {
    std::vector<TileRescan> scans(toScan.tiles.size());
    auto changedCells = [&](std::size_t i) { return toScan.boxes[i].cells; };
    util::parallelForHeaviestFirst(ctx.pool, toScan.tiles.size(), changedCells, [&](std::size_t i) {
        rescanTile(ctx, rebuilt, changed, *toScan.tiles[i], toScan.boxes[i], *scanned[i], scans[i]);
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
    std::vector<ScannedLeaves*> scanned;
    scanned.reserve(toScan.tiles.size());
    for (std::size_t i = 0; i < toScan.tiles.size(); ++i)
        scanned.push_back(mScanned[i].get());
    deltas.crossingSlots -= crossingSlotsOf(toScan.tiles);
    const std::vector<TileRescan> scans = rescanCrossings(ctx, rebuilt, changed, toScan, scanned);
    st.tilesScanned = toScan.tiles.size();
    addRescanCounts(scans, st, deltas);
    for (std::size_t i = 0; i < scans.size(); ++i)  // (their crossings, hence triangles, changed)
        if (!scans[i].added.empty() || !scans[i].removed.empty()) mChangedTiles.push_back(toScan.tiles[i]->key);
    const RemeshQueue queue = queueCellsToRemesh(ctx, changed, scans);
    const auto tPhase1 = std::chrono::steady_clock::now();

    // 2. The queued cells: all their vertices, from scratch.
    const RemeshTiles toRemesh = listTilesToRemesh(ctx, queue);
    const uint32_t relaxMark = nextRelaxMark(mTiles, mRelaxStamp);
    const std::vector<std::vector<VertexRef>> made =
        remeshCells(ctx, changed, queue, toRemesh, toScan, scanned, relaxMark, st, deltas);
    listRemeshedShares(ctx, toRemesh, made, mChangedTiles);
    const auto tPhase2 = std::chrono::steady_clock::now();

    // 3. Split vertices near the re-meshed cells; relaxation of the new vertices and their readers.
    splitFacesNear(ctx, toRemesh, deltas, mChangedTiles);
    st.verticesRelaxed = relaxNewVertices(ctx, made, relaxMark, mChangedTiles);

    // 4. Removed records released, empty tiles dropped, totals.
    // The scans' leaf sets stay for the next update's room, as many as this one scanned (one
    // large edit does not keep hundreds of them for every dab after it).
    mScanned.resize(toScan.tiles.size());
    releaseRemovedCrossings(toScan, scans, deltas);
    dropEmptiedTiles(ctx, rebuilt, toScan, toRemesh, deltas, mChangedTiles);
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
    ++mGeneration;
    // Updates nobody takes keep their tiles' keys: bounded by the tiles, not the updates.
    if (mChangedTiles.size() > 4096 + 2 * mTiles.size()) sortUnique(mChangedTiles);
}

}  // namespace kizamu::mesh
