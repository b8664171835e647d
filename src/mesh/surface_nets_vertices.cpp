// SPDX-License-Identifier: Apache-2.0
/// @file surface_nets_vertices.cpp
/// @brief Crossings -> each cell's incidences -> vertices (a build's vertex phase), then split
/// faces and relaxation (the build and the update alike).
///
/// Takes in: every tile's crossings (a build: its own and the runs of its neighbours' border
/// lists that name it) and its boundary leaves. Produces: per cell of the tile, its incidences
/// sorted by crossing key, meshed by meshCell (surface_nets_cycles.cpp) into projected
/// vertices; then per tile the split vertices of its multi-crossing faces and every vertex's
/// relaxed position and normal.
/// Complexity: O(incidences) per tile for the gathering (a counting sort by cell, insertion
/// sorts of each cell's handful), O(vertices x incidences each) for relaxation.
/// Threading: one task per tile, on its home thread. The vertex phase writes the tile's vertices
/// and its cells' quadrants of any tile's crossings; relaxation reads neighbours' `projected`
/// (written by the previous phase) and writes the tile's `placed`.
#include "mesh/surface_nets_internal.h"

#include "mesh/surface_nets_cell.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <numeric>
#include <stdexcept>

namespace kizamu::mesh::detail {

using adf::Adf;

namespace {

/// Position of a cell of a tile whose side spans 2^bits lattice units, at `local` (its origin
/// less the tile's), in the boundary-cell walk's order: depth first, children by their x, y, z
/// bits (interleaved bits, z highest). A build keeps cells in that order, as the walk gives the
/// leaves: no sort, and neighbouring leaves come close together (the leaf locator's caches).
uint64_t walkOrder(glm::uvec3 local, int bits) {
    uint64_t k = 0;
    for (int b = bits - 1; b >= 0; --b)
        k = (k << 3) | (((local.z >> b) & 1u) << 2) | (((local.y >> b) & 1u) << 1) | ((local.x >> b) & 1u);
    return k;
}

/// Incidences of the cells of `self` during a build: crossings in its own pool and its
/// neighbours' border lists that have a leaf owned by it, into s.byCell grouped by cell in walk
/// order (cell i's run is [s.cellRunBegin[i], s.cellRunBegin[i + 1]), its key s.cellAtRank[i]),
/// each cell's sorted by crossing key. A counting sort: cells are numbered (PlaceTable, else
/// s.cellNumber), the tile's boundary leaves in their order and other cells as met, then merged
/// in; each cell's handful of incidences is sorted by insertion. A boundary leaf may get an
/// empty run (its crossings all leave the domain).
void gatherIncidences(int maxLevel, TileBuild& self, const std::vector<TileBuild*>& neighbours, BuildScratch& s) {
    const TileMesh& tm = *self.mesh;
    // The crossings read: the tile's own, and the runs of its neighbours' border lists naming it.
    s.sources.clear();
    std::size_t bound = 0;  // incidences at most (4 a crossing)
    for (TileBuild* found : neighbours) {
        TileBuild& src = *found;
        if (src.mesh->key == tm.key) {
            s.sources.push_back({&src, 0, UINT32_MAX});
            bound += 4 * std::size_t(src.mesh->crossings.size());
        } else {
            const auto b = std::lower_bound(src.border.begin(), src.border.end(), BorderCrossing{tm.key, 0});
            auto e = b;
            while (e != src.border.end() && e->owner == tm.key) ++e;
            s.sources.push_back({&src, uint32_t(b - src.border.begin()), uint32_t(e - src.border.begin())});
            bound += 4 * std::size_t(e - b);
        }
    }
    // Written through raw pointers into buffers that only grow (no push_back checks in the
    // loop).
    if (s.gathered.size() < bound) {
        s.gathered.resize(bound);
        s.gatheredCell.resize(bound);
        s.otherCells.resize(bound);
    }
    Incidence* gathered = s.gathered.data();
    uint32_t* gatheredCell = s.gatheredCell.data();
    std::pair<uint64_t, uint32_t>* otherCells = s.otherCells.data();
    // Nearly every cell is a boundary leaf of the tile: those are numbered first, in their
    // (walk) order, so only the few others need sorting in.
    const std::vector<BoundaryCell>& leaves = self.leaves;
    const uint32_t nLeaves = uint32_t(leaves.size());
    uint32_t nGathered = 0, nCells = nLeaves, nOther = 0;
    // In locals: the writes through `addIncidence` could alias tm's fields.
    const uint64_t tileKey = tm.key, outside = tm.outside;
    // Numbers through the place table; a larger (coarse) tile through a hash map.
    uint32_t* const byPlace = PlaceTable::fits(*tm.tile, maxLevel) ? PlaceTable::entries() : nullptr;
    auto place = [&](uint64_t cell) { return PlaceTable::place(cell, tileKey); };
    if (!byPlace) s.cellNumber.resetFor(nLeaves + nLeaves / 8 + 8);
    s.cellAtRank.resize(nLeaves);
    // The leaves' places, then the other cells' (numbered after them). From the leaves
    // themselves: s.cellAtRank is merged with the other cells before the table is cleared.
    const auto cellKey = [&](std::size_t i) {
        return i < nLeaves ? packLattice(leaves[i].origin) : otherCells[i - nLeaves].first;
    };
    PlaceTable::ClearOnExit<decltype(cellKey)> clear{byPlace, tileKey, 0, cellKey};
    for (uint32_t i = 0; i < nLeaves; ++i) {
        s.cellAtRank[i] = packLattice(leaves[i].origin);
        if (byPlace) byPlace[place(s.cellAtRank[i])] = i;
        else s.cellNumber.assign(s.cellAtRank[i], i);
        clear.cells = i + 1;
    }
    auto addIncidence = [&](Crossing& x, uint64_t key, int q, uint8_t first, uint8_t last) {
        uint32_t number;
        if (byPlace) {
            uint32_t& slot = byPlace[place(x.ringCell[q])];
            if (slot == PlaceTable::kNone) {
                slot = nCells;
                clear.cells = nCells + 1;  // (otherCells' entry is written below)
            }
            number = slot;
        } else {
            number = s.cellNumber.findOrAssign(x.ringCell[q], nCells);
        }
        if (number == nCells) otherCells[nOther++] = {x.ringCell[q], nCells++};
        gathered[nGathered] = {x.ringCell[q], key, &x, first, last};
        gatheredCell[nGathered++] = number;
    };
    auto ownedCell = [&](uint64_t cell) { return inTile(cell, tileKey, outside); };
    // Always inlined: called out of line, it kept nothing in registers.
    auto takeCrossing = [&](Crossing& x) __attribute__((always_inline)) {
        const uint64_t key = x.key();
        // A leaf fills a run of adjacent quadrants: nearly always one each (four leaves).
        const uint64_t* c = x.ringCell;
        if (c[0] != c[1] && c[1] != c[2] && c[2] != c[3] && c[3] != c[0]) {
            for (int q = 0; q < 4; ++q)
                if (ownedCell(c[q])) addIncidence(x, key, q, uint8_t(q), uint8_t(q));
            return;
        }
        uint8_t done = 0;
        for (int q = 0; q < 4; ++q) {
            if (!ownedCell(c[q]) || ((done >> q) & 1)) continue;
            uint8_t first, last;
            incidenceRun(x, q, first, last);
            for (uint8_t r = first;; r = uint8_t((r + 1) % 4)) {
                done |= uint8_t(1u << r);
                if (r == last) break;
            }
            addIncidence(x, key, q, first, last);
        }
    };
    for (const BuildScratch::CrossingSource& from : s.sources) {
        TileBuild& src = *from.tile;
        SlotPool<Crossing>& pool = src.mesh->crossings;
        if (from.end == UINT32_MAX) {
            for (uint32_t j = 0; j < pool.size(); ++j) takeCrossing(pool[j]);
        } else {
            for (uint32_t b = from.begin; b < from.end; ++b) takeCrossing(pool[src.border[b].index]);
        }
    }
    const std::size_t cells = nCells;
    s.walkRank.resize(cells);
    if (nOther == 0) {
        std::iota(s.walkRank.begin(), s.walkRank.end(), 0u);
    } else {  // merge the others into the leaves' (walk) order
        const glm::uvec3 o = tm.tile->latticeOrigin();
        const int bits = maxLevel - tm.tile->level();
        auto order = [&](uint64_t key) { return walkOrder(unpackLattice(key) - o, bits); };
        std::vector<std::pair<uint64_t, uint32_t>> others(nOther);  // (walk order, index in otherCells)
        for (uint32_t j = 0; j < nOther; ++j) others[j] = {order(otherCells[j].first), j};
        std::sort(others.begin(), others.end());
        std::vector<uint64_t> leafKeys(s.cellAtRank.begin(), s.cellAtRank.end());
        s.cellAtRank.resize(cells);
        uint32_t leaf = 0, other = 0;
        for (uint32_t r = 0; r < cells; ++r) {
            if (other == nOther || (leaf < nLeaves && order(leafKeys[leaf]) < others[other].first)) {
                s.walkRank[leaf] = r;
                s.cellAtRank[r] = leafKeys[leaf++];
            } else {
                const auto& [key, number] = otherCells[others[other++].second];
                s.walkRank[number] = r;
                s.cellAtRank[r] = key;
            }
        }
    }
    s.byCell.resize(nGathered);
    groupByRank(nGathered, s.walkRank, s.cellRunBegin, [&](std::size_t j) { return gatheredCell[j]; },
                [&](std::size_t j, uint32_t at) { s.byCell[at] = gathered[j]; });
    for (std::size_t i = 0; i < cells; ++i) {
        Incidence* run = s.byCell.data() + s.cellRunBegin[i];
        const uint32_t n = s.cellRunBegin[i + 1] - s.cellRunBegin[i];
        for (uint32_t j = 1; j < n; ++j) {
            if (run[j - 1].crossingKey < run[j].crossingKey) continue;  // in place (keys are distinct)
            const Incidence v = run[j];
            uint32_t k = j;
            for (; k > 0 && v.crossingKey < run[k - 1].crossingKey; --k) run[k] = run[k - 1];
            run[k] = v;
        }
    }
}

/// Slot of the face between ring positions qA and qB (adjacent) in a crossing's split array.
inline int faceSlot(uint8_t qA, uint8_t qB) { return (qA + 1) % 4 == qB ? qA : qB; }

}  // namespace

BuildScratch& buildScratch() {
    thread_local BuildScratch s;
    return s;
}

void computeVertices(const Adf& adf, TileBuild& tile, const std::vector<TileBuild*>& neighbours,
                     SurfaceNetsStats& st) {
    BuildScratch& scratch = buildScratch();
    gatherIncidences(adf.domain().maxLevel, tile, neighbours, scratch);
    TileMesh& tm = *tile.mesh;
    const std::vector<BoundaryCell>& leaves = tile.leaves;
    const std::vector<Incidence>& inc = scratch.byCell;
    const std::vector<uint32_t>& cellRunBegin = scratch.cellRunBegin;
    const std::size_t cells = cellRunBegin.size() - 1;
    tm.vertices.clear();
    tm.projected.clear();
    tm.placed.clear();
    tm.freeVertices.clear();
    tm.liveVertices = 0;
    tm.incidences.clear();
    tm.multiFaces.clear();
    tm.vertices.reserve(cells + cells / 8);  // a few cells hold several sheets
    tm.projected.reserve(cells + cells / 8);
    tm.placed.reserve(cells + cells / 8);
    tm.incidences.reserve(inc.size());       // each incidence goes to one vertex
    CellScratch& cycles = scratch.cycles;
    cycles.freshCrossings = true;  // a build made every crossing this phase reads
    std::size_t leafAt = 0;  // the cells in walk order take the tile's leaves in turn
    for (std::size_t i = 0; i < cells; ++i) {
        const uint32_t i0 = cellRunBegin[i], i1 = cellRunBegin[i + 1];
        const uint64_t cell = scratch.cellAtRank[i];
        const BoundaryCell* leaf =
            leafAt < leaves.size() && packLattice(leaves[leafAt].origin) == cell ? &leaves[leafAt++] : nullptr;
        if (i0 == i1) continue;  // a boundary leaf whose crossings all leave the domain: no vertex
        // The cell's corners: a boundary leaf of this tile, or (figure 9B) looked up.
        float corners[8];
        if (leaf) {
            std::copy(leaf->corners, leaf->corners + 8, corners);
        } else {
            const adf::LeafRef r = adf.findLeaf(unpackLattice(cell));
            std::copy(r.corners, r.corners + 8, corners);
            if (!isBoundary(corners)) ++st.signlessCells;
        }
        meshCell(adf, tm, &inc[i0], i1 - i0, corners, cycles, st);
    }
    tm.liveIncidences = tm.incidences.size();
    tm.cellVertex.clear();
    tm.cellVertex.pending = true;
}

/// Where two segments of one face join the same two vertices, the dual mesh would use one edge
/// twice; every such segment but the first gets a vertex of its own, which the two polygons at
/// its ends include (they are then fanned around their centre). Needs the cycles of both cells.
void splitFaces(TileMesh& tm) {
    tm.splits.clear();
    for (const MultiFace& mf : tm.multiFaces) {
        std::vector<std::pair<uint64_t, uint64_t>> seen;
        for (const auto& [e, l] : mf.segments) {
            const VertexRef a = e.x->ringVertex[e.qA], b = e.x->ringVertex[e.qB];
            const std::pair<uint64_t, uint64_t> id{uint64_t(reinterpret_cast<uintptr_t>(a.tile)) ^ (uint64_t(a.index) << 1),
                                                   uint64_t(reinterpret_cast<uintptr_t>(b.tile)) ^ (uint64_t(b.index) << 1)};
            uint32_t split = Crossing::kNoSplit;
            if (std::find(seen.begin(), seen.end(), id) != seen.end()) {
                split = uint32_t(tm.splits.size());
                tm.splits.push_back({a, b});
            } else {
                seen.push_back(id);
            }
            e.x->split[faceSlot(e.qA, e.qB)] = split;
            l.x->split[faceSlot(l.qA, l.qB)] = split;
        }
    }
}

void relaxVertex(TileMesh& tm, uint32_t vi, UnmarkedNeighbours unmarked) {
    Vertex& v = tm.vertices[vi];
    auto projectedAt = [&](const VertexRef& r) -> const glm::vec3& {
        if (!r.tile) throw std::logic_error("surface nets: a neighbouring vertex was not computed");
        const Projected& w = r.tile->projected[r.index];
        if (unmarked.out && w.relaxStamp != unmarked.mark) unmarked.out->push_back(r);
        return w.point;
    };
    // The ring cells on both sides of each crossing's run (most neighbours come twice).
    glm::vec3 sum(0.0f);
    for (uint32_t i = v.incBegin; i < v.incEnd; ++i) {
        const VertexIncidence& c = tm.incidences[i];
        sum += projectedAt(c.x->ringVertex[(c.first + 3) % 4]);
        sum += projectedAt(c.x->ringVertex[(c.last + 1) % 4]);
    }
    const uint32_t count = 2 * (v.incEnd - v.incBegin);
    const glm::vec3 p = tm.projected[vi].point;
    const adf::Sample s = cellSample<true>(v, p);
    glm::vec3 moved = p;
    glm::vec3 gradient = s.gradient;  // the normal: gradient where the last projection started
    const float g = glm::length(s.gradient);
    if (count > 0 && g > 1e-12f && isBoundary(v.corners)) {  // (a signless cell's vertex stays: see meshCell)
        const glm::vec3 n = s.gradient / g;
        const glm::vec3 d = sum / float(count) - p;
        moved = projectOnce<true>(v, clampToCell(p + 0.5f * (d - glm::dot(n, d) * n), v), &gradient);
    }
    Placed& out = tm.placed[vi];
    out.position = moved;
    const float ge = glm::length(gradient);
    if (ge > 1e-12f && std::isfinite(ge)) {
        out.normal = gradient / ge;
    } else {
        // The crossed edges' directions (whole numbers: the sum's order does not matter).
        glm::vec3 crossed(0.0f);
        for (uint32_t i = v.incBegin; i < v.incEnd; ++i) {
            const Crossing& x = *tm.incidences[i].x;
            glm::vec3 dir(0.0f);
            dir[x.axis] = x.startInside ? 1.0f : -1.0f;
            crossed += dir;
        }
        const float cn = glm::length(crossed);
        out.normal = cn > 0.0f ? crossed / cn : glm::vec3(0.0f, 0.0f, 1.0f);
    }
}

}  // namespace kizamu::mesh::detail
