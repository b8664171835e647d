// SPDX-License-Identifier: Apache-2.0
/// @file surface_nets_remesh.cpp
/// @brief SurfaceMesher::update's phases 2-4: the queued cells re-meshed, split vertices and
/// relaxation near them, removed records released, emptied tiles dropped, the totals.
///
/// Takes in: the queue of cells to re-mesh (RemeshQueue, phase 1c: each cell once, by tile, with
/// the crossings it gains), the changed cells, the scans' leaves and their removed records
/// (surface_nets_update.cpp). Produces: every queued cell's vertices from scratch (its kept
/// crossings from its old vertices, which go, and its added ones, sorted by crossing key as a
/// build sorts them, so the same floats), the split vertices of the tiles around them, the
/// relaxed positions of the new vertices and of every vertex that reads one, and the mesher's
/// totals; tiles left holding nothing are dropped.
/// Complexity: O(incidences of the queued cells) to re-mesh, O(multi-crossing faces of the
/// re-meshed tiles and their neighbours) for split vertices, O(relaxed vertices x their
/// incidences) to relax, O(removed crossings + visited tiles) for the rest.
/// Threading: update() calls each phase on the mesher's owning thread. Phase 2c runs one tile
/// per pool task (most cells first), writing only that tile's records and its cells' slots of
/// crossings; 3b runs blocks of vertices, each writing only its vertices' positions. The rest
/// is serial; the result does not depend on the schedule.
#include "mesh/surface_nets_update.h"

#include "util/thread_pool.h"

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <vector>

namespace kizamu::mesh::detail {

// --- Phase 2: the queued cells re-meshed --------------------------------------------------------

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

namespace {

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
void newCorners(const Adf& newAdf, const ScannedLeaves* scanned, uint64_t cell, float corners[8]) {
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
                std::size_t end, TileMesh& tm, const ScannedLeaves* scanned, uint32_t relaxMark,
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

}  // namespace

/// Phase 2c: re-meshes the queued cells: all their vertices, from scratch (cycles and first
/// projection, computed as a build does: incidences sorted by crossing key).
/// In: the queue, the tiles owning its cells, the scans' leaves (`scanned`, one per tile of
/// `toScan`). Out: per tile, the vertices made (marked with `relaxMark`); counters in `st`, the
/// vertex total's move in `deltas`. Complexity: O(incidences of the queued cells).
/// Threading: parallel over tiles, most cells first, as the scan.
std::vector<std::vector<VertexRef>> remeshCells(const UpdateContext& ctx, const ChangedCells& changed,
                                                const RemeshQueue& queue, const RemeshTiles& toRemesh,
                                                const ScanList& toScan, const std::vector<ScannedLeaves*>& scanned,
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
        const ScannedLeaves* leaves = scanIndex ? scanned[*scanIndex] : nullptr;
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

/// Phase 2d: the tiles whose shares the re-meshing changed: every re-meshed tile (its vertex
/// slots), and the tile of every crossing around a re-meshed cell (meshCell rewrote its vertex
/// refs; a crossing lives in the tile of its emitter's cell). A removed crossing's tile is its
/// scan's. Complexity: O(incidences of the new vertices), nearly all in the vertex's own tile.
/// Serial.
void listRemeshedShares(const UpdateContext& ctx, const RemeshTiles& toRemesh,
                        const std::vector<std::vector<VertexRef>>& made, std::vector<uint64_t>& changedTiles) {
    for (const TileMesh* tm : toRemesh.tiles) changedTiles.push_back(tm->key);
    for (const std::vector<VertexRef>& list : made)
        for (const VertexRef& r : list) {
            const TileMesh& tm = *r.tile;
            const Vertex& v = tm.vertices[r.index];
            uint64_t lastOther = UINT64_MAX;  // (a vertex's crossings mostly share a tile)
            for (uint32_t j = v.incBegin; j < v.incEnd; ++j) {
                const Crossing& x = *tm.incidences[j].x;
                const uint64_t emitterCell = x.ringCell[x.emitter];
                if (inTile(emitterCell, tm.key, tm.outside)) continue;
                const uint64_t owner = ownerKey(ctx.newAdf, emitterCell);
                if (owner != lastOther) changedTiles.push_back(lastOther = owner);
            }
        }
}

// --- Phase 3: split vertices and relaxation -----------------------------------------------------

/// Phase 3a: recomputes the split vertices (rare) of the re-meshed tiles and their neighbours:
/// a multi-crossing face lies between two adjacent cells, so its owner is the tile of a
/// re-meshed cell or a neighbour of it. A tile whose split list changed, and the tile of each
/// crossing whose split index changed, go to `changedTiles` (the crossings of re-meshed cells
/// are there already). Complexity: O(multi-crossing faces of those tiles). Serial.
void splitFacesNear(const UpdateContext& ctx, const RemeshTiles& toRemesh, TotalDeltas& deltas,
                    std::vector<uint64_t>& changedTiles) {
    std::vector<uint64_t> nearKeys;
    for (const TileMesh* tm : toRemesh.tiles) neighbourKeys(ctx.newAdf, tm->slotMin, tm->slotEnd, nearKeys);
    sortUnique(nearKeys);
    std::vector<SplitVertex> splitsBefore;
    std::vector<std::array<uint32_t, 4>> indicesBefore;  // per segment end: its crossing's split[]
    auto sameRef = [](const VertexRef& a, const VertexRef& b) { return a.tile == b.tile && a.index == b.index; };
    for (uint64_t k : nearKeys) {
        auto it = ctx.tiles.find(k);
        if (it == ctx.tiles.end() || (it->second->multiFaces.empty() && it->second->splits.empty())) continue;
        TileMesh& tm = *it->second;
        splitsBefore.assign(tm.splits.begin(), tm.splits.end());
        indicesBefore.clear();
        for (const MultiFace& mf : tm.multiFaces)
            for (const auto& [e, l] : mf.segments) {
                indicesBefore.push_back(std::to_array(e.x->split));
                indicesBefore.push_back(std::to_array(l.x->split));
            }
        deltas.splitEdges -= int64_t(tm.splits.size());
        splitFaces(tm);
        deltas.splitEdges += int64_t(tm.splits.size());
        bool same = splitsBefore.size() == tm.splits.size();
        for (std::size_t i = 0; same && i < splitsBefore.size(); ++i)
            same = sameRef(splitsBefore[i].a, tm.splits[i].a) && sameRef(splitsBefore[i].b, tm.splits[i].b);
        if (!same) changedTiles.push_back(tm.key);
        std::size_t at = 0;
        for (const MultiFace& mf : tm.multiFaces)
            for (const auto& [e, l] : mf.segments)
                for (const Crossing* x : {e.x, l.x})
                    if (std::to_array(x->split) != indicesBefore[at++])
                        changedTiles.push_back(ownerKey(ctx.newAdf, x->ringCell[x->emitter]));
    }
}

namespace {

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

}  // namespace

/// Phase 3b: relaxes the new vertices (`made`, per re-meshed tile), then every vertex that reads
/// one of them (a position after relaxation depends on the neighbours' projected vertices),
/// each once. Relaxing the new vertices reports the unmarked vertices that read them (found on
/// the way, not listed beforehand on one thread from every ring cell of every new vertex's
/// crossings); those are marked in report order and relaxed after.
/// Returns how many were relaxed. Complexity: O(relaxed vertices x their incidences).
/// Threading: parallel over blocks of vertices; the marking between the two passes is serial.
std::size_t relaxNewVertices(const UpdateContext& ctx, const std::vector<std::vector<VertexRef>>& made,
                             uint32_t relaxMark, std::vector<uint64_t>& changedTiles) {
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
            if (changedTiles.empty() || changedTiles.back() != r.tile->key) changedTiles.push_back(r.tile->key);
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
                      const RemeshTiles& toRemesh, TotalDeltas& deltas, std::vector<uint64_t>& changedTiles) {
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
        changedTiles.push_back(k);
    }
}

/// Phase 4c: the whole mesh's totals in `st`: those `before` the update moved by `deltas`.
void addTotals(const SurfaceNetsStats& before, const TotalDeltas& deltas, SurfaceNetsStats& st) {
    st.crossings = std::size_t(int64_t(before.crossings) + deltas.crossings);
    st.vertices = std::size_t(int64_t(before.vertices) + deltas.vertices);
    st.splitEdges = std::size_t(int64_t(before.splitEdges) + deltas.splitEdges);
    st.crossingSlots = std::size_t(int64_t(before.crossingSlots) + deltas.crossingSlots);
}

}  // namespace kizamu::mesh::detail
