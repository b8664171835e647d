// SPDX-License-Identifier: Apache-2.0
/// @file surface_nets_update.h
/// @brief What the phases of SurfaceMesher::update share across its two files (internal to
/// src/mesh/surface_nets_update.cpp and surface_nets_remesh.cpp).
///
/// The context every phase reads (UpdateContext), the totals' moves (TotalDeltas), the structs
/// one phase produces and a later one takes in (RebuiltTiles, ScanList, TileRescan, RemeshQueue,
/// RemeshTiles, ...), an update's per-thread buffers, and the phases update() calls in
/// surface_nets_remesh.cpp (2-4). Phases 0 and 1 and update() itself are in
/// surface_nets_update.cpp, which describes the whole; the changed cells in
/// surface_nets_changed_cells.h.
/// Threading: as surface_nets_update.cpp (phases run in order on the mesher's owning thread;
/// some split into pool tasks that write only their own tile).
#pragma once

#include "mesh/surface_nets_changed_cells.h"
#include "mesh/surface_nets_internal.h"
#include "util/thread_pool.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <unordered_map>
#include <utility>
#include <vector>

namespace kizamu::mesh::detail {

using adf::Adf;
using adf::Tile;

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
/// This thread's UpdateScratch (surface_nets_update.cpp).
UpdateScratch& updateScratch();

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

/// A tile whose closed box touches a changed cell: the bounding box of those cells.
struct Touched {
    glm::uvec3 lo{UINT32_MAX}, hi{0};
    uint32_t cells = 0;  ///< changed cells touching it: how much it has to scan
};

/// The tiles whose crossings at changed cells are recomputed, by key, with what touches each.
struct ScanList {
    std::vector<TileMesh*> tiles;
    std::vector<Touched> boxes;
};

// --- Phase 1: the crossings at changed cells, and the cells to re-mesh --------------------------

/// What rescanning one tile did to its crossings at changed cells.
struct TileRescan {
    std::vector<Crossing*> removed, added, kept;
    std::vector<uint32_t> released;  ///< the removed records' slots: read until the update ends
    SurfaceNetsStats st;
};

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

// --- Phases 2-4 (surface_nets_remesh.cpp) -------------------------------------------------------

/// The tiles holding cells to re-mesh, in queue order (by key), and each one's run of the queue.
struct RemeshTiles {
    std::vector<TileMesh*> tiles;
    /// Tile i's cells are queue.cells[cellBegin[i]..cellBegin[i + 1]).
    std::vector<std::size_t> cellBegin;
};

/// Phase 2a: the tiles owning the queued cells (a tile of the new snapshot gets its state here).
RemeshTiles listTilesToRemesh(const UpdateContext& ctx, const RemeshQueue& queue);

/// Phase 2b: this update's relaxation mark, from the mesher's counter `stamp`.
uint32_t nextRelaxMark(TileMap& tiles, uint32_t& stamp);

/// Phase 2c: re-meshes the queued cells; returns per re-meshed tile the vertices made.
std::vector<std::vector<VertexRef>> remeshCells(const UpdateContext& ctx, const ChangedCells& changed,
                                                const RemeshQueue& queue, const RemeshTiles& toRemesh,
                                                const ScanList& toScan, const std::vector<ScannedLeaves*>& scanned,
                                                uint32_t relaxMark, SurfaceNetsStats& st, TotalDeltas& deltas);

/// Phase 2d: appends to `changedTiles` the keys of the tiles whose shares the re-meshing
/// changed: the re-meshed tiles and the tiles of the crossings whose vertex refs it rewrote.
void listRemeshedShares(const UpdateContext& ctx, const RemeshTiles& toRemesh,
                        const std::vector<std::vector<VertexRef>>& made, std::vector<uint64_t>& changedTiles);

/// Phase 3a: recomputes the split vertices of the re-meshed tiles and their neighbours; appends
/// to `changedTiles` the tiles whose split vertices, or whose crossings' split indices, changed.
void splitFacesNear(const UpdateContext& ctx, const RemeshTiles& toRemesh, TotalDeltas& deltas,
                    std::vector<uint64_t>& changedTiles);

/// Phase 3b: relaxes the new vertices, then every vertex that reads one; returns how many.
/// Appends to `changedTiles` the tiles of the readers it relaxed.
std::size_t relaxNewVertices(const UpdateContext& ctx, const std::vector<std::vector<VertexRef>>& made,
                             uint32_t relaxMark, std::vector<uint64_t>& changedTiles);

/// Phase 4a: releases the removed crossing records.
void releaseRemovedCrossings(const ScanList& toScan, const std::vector<TileRescan>& scans, TotalDeltas& deltas);

/// Phase 4b: drops the state of the tiles that are gone and of the tiles left empty; appends
/// their keys to `changedTiles`.
void dropEmptiedTiles(const UpdateContext& ctx, const RebuiltTiles& rebuilt, const ScanList& toScan,
                      const RemeshTiles& toRemesh, TotalDeltas& deltas, std::vector<uint64_t>& changedTiles);

/// Phase 4c: the whole mesh's totals in `st`: those `before` the update moved by `deltas`.
void addTotals(const SurfaceNetsStats& before, const TotalDeltas& deltas, SurfaceNetsStats& st);

}  // namespace kizamu::mesh::detail
