// SPDX-License-Identifier: Apache-2.0
/// @file surface_nets_internal.h
/// @brief The mesher's phase steps, as a full build (surface_nets.cpp) and the sub-tile update
/// (surface_nets_update.cpp, surface_nets_remesh.cpp) call them (internal to src/mesh/surface_nets*).
///
/// The phases and their files: boundary leaves -> crossings (surface_nets_crossings.cpp), a
/// cell's crossings -> cycles -> vertices (surface_nets_cycles.cpp), incidence gathering,
/// split faces and relaxation (surface_nets_vertices.cpp), tiles -> MeshBuffers
/// (surface_nets_assembly.cpp). The records are in surface_nets_records.h, a tile's state in
/// surface_nets_tile.h.
/// Threading: as surface_nets.h (a slot is written by one task per phase, read after a barrier).
#pragma once

#include "adf/boundary_cells.h"
#include "adf/lattice.h"
#include "adf/tile_diff.h"
#include "mesh/slot_pool.h"
#include "mesh/surface_nets.h"
#include "mesh/surface_nets_cycles.h"
#include "mesh/surface_nets_records.h"
#include "mesh/surface_nets_tile.h"
#include "util/flat_map.h"

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace kizamu::mesh {

using adf::appendBoundaryCells;
using adf::appendBoundaryCellsTouching;
using adf::appendChangedCells;
using adf::BoundaryCell;
using adf::LatticeBox;
using adf::LeafFilter;
using util::FlatMap64;

namespace detail {

/// Sorts `v` and drops repeated elements. Always inlined: GCC keeps a header's template out of
/// line where a file's own would be inlined into its few callers.
template <class T>
[[gnu::always_inline]] inline void sortUnique(std::vector<T>& v) {
    std::sort(v.begin(), v.end());
    v.erase(std::unique(v.begin(), v.end()), v.end());
}

// ---- Crossings (surface_nets_crossings.cpp) ----

/// Which edge start points a computation wants (an update: those on changed cells).
struct StartFilter {
    bool (*keep)(const void* context, glm::uvec3 start) = nullptr;
    const void* context = nullptr;
};

/// Appends records to a tile's crossing pool, numbering their slots, with no vertices and no
/// split vertices (what a build writes computeCrossings into: no intermediate copy of the large
/// records). computeCrossings writes every other field, so the rest is not cleared first
/// (zeroing the whole record would write both cache lines twice).
struct PoolAppender {
    SlotPool<Crossing>& pool;
    Crossing& emplace_back() {
        const uint32_t j = pool.append();
        Crossing& x = pool[j];
        x.slot = j;
        std::fill(x.ringVertex, x.ringVertex + 4, VertexRef{});
        std::fill(x.split, x.split + 4, Crossing::kNoSplit);
        return x;
    }
};

/// The crossings emitted by `leaves` of `tile` (any order), appended to `out`
/// (a std::vector<Crossing> or a PoolAppender); with a filter, only those whose start point it
/// keeps (others are not looked at).
template <class Out>
void computeCrossings(const adf::Adf& adf, const adf::Tile& tile, const std::vector<BoundaryCell>& leaves, Out& out,
                      SurfaceNetsStats& st, StartFilter filter = {});

// ---- Vertices: split faces and relaxation (surface_nets_vertices.cpp) ----

/// Recomputes `tm`'s split vertices from its multi-crossing faces (reads both cells' vertices).
void splitFaces(TileMesh& tm);

/// Where relaxation reports the neighbours it reads that do not carry `mark` (an update
/// relaxes those too, after: they read a vertex that moved).
struct UnmarkedNeighbours {
    std::vector<VertexRef>* out = nullptr;
    uint32_t mark = 0;
};

/// Tangential relaxation toward the neighbours' mean, projection, normal of vertex `vi` of `tm`
/// (reads neighbours' `projected`, writes the vertex's `placed`). The neighbours it reads are
/// exactly the vertices that read it when they relax (the cells next to its run of ring cells
/// in each of its crossings), so `unmarked` gets every vertex that reads this one, unless marked
/// (once per read: most come twice).
void relaxVertex(TileMesh& tm, uint32_t vi, UnmarkedNeighbours unmarked = {});

/// Relaxes vertices at(0..n-1) in order (`at` gives each one's VertexRef). Relaxation chases
/// pointers (incidence, crossing, neighbour vertex), so the crossings are asked for a few
/// vertices ahead; the neighbours are not (a cache large enough holds them anyway, and asking
/// costs where it does) (docs/decisions/0011-mesher-record-layout.md).
template <class At>
void relaxInOrder(std::size_t n, At at, UnmarkedNeighbours unmarked = {}) {
    constexpr std::size_t kCrossingsAhead = 4;
    for (std::size_t k = 0; k < n; ++k) {
        if (k + kCrossingsAhead < n) {
            const VertexRef r = at(k + kCrossingsAhead);
            const Vertex& v = r.tile->vertices[r.index];
            for (uint32_t j = v.incBegin; j < v.incEnd; ++j) __builtin_prefetch(&r.tile->incidences[j].x->ringVertex);
        }
        const VertexRef r = at(k);
        relaxVertex(*r.tile, r.index, unmarked);
    }
}

// ---- Shared helpers ----

/// Counting sort into runs: item j (of n) belongs to group groupOf(j), groups numbered as first
/// met, and group g's run is the rank[g]-th. Calls place(j, position) with every run in rank
/// order and items in input order within a run, and leaves begin[r] (rank.size() + 1 entries)
/// where run r starts. Complexity: O(n + groups), no comparisons.
template <class GroupOf, class Place>
void groupByRank(std::size_t n, const std::vector<uint32_t>& rank, std::vector<uint32_t>& begin, GroupOf groupOf,
                 Place place) {
    const std::size_t runs = rank.size();
    begin.assign(runs + 1, 0);
    for (std::size_t j = 0; j < n; ++j) ++begin[rank[groupOf(j)] + 1];
    for (std::size_t r = 1; r <= runs; ++r) begin[r] += begin[r - 1];
    // Placing an item advances its run's start to the next run's; shifted back after.
    for (std::size_t j = 0; j < n; ++j) place(j, begin[rank[groupOf(j)]]++);
    for (std::size_t r = runs; r > 0; --r) begin[r] = begin[r - 1];
    begin[0] = 0;
}

/// Adds one tile's vertex-phase counters (the same in a build and an update) to `total`.
inline void addVertexCounters(SurfaceNetsStats& total, const SurfaceNetsStats& tile) {
    total.multiSheetCells += tile.multiSheetCells;
    total.multiCrossingFaces += tile.multiCrossingFaces;
    total.oddFaces += tile.oddFaces;
    total.signlessCells += tile.signlessCells;
    total.verticesComputed += tile.verticesComputed;
}

// ---- A build only ----

/// A crossing of a tile with a ring cell in another tile (`owner`, its key), by its slot
/// `index` in the tile's pool: the owner, gathering its cells' incidences, reads only its run
/// of the list (sorted by owner).
struct BorderCrossing {
    uint64_t owner;
    uint32_t index;
    bool operator<(const BorderCrossing& o) const { return owner != o.owner ? owner < o.owner : index < o.index; }
};

/// A tile's state that lives for one build only (owned by build(), freed by its relaxation
/// phase on the tile's home thread).
struct TileBuild {
    TileMesh* mesh = nullptr;
    std::vector<BoundaryCell> leaves;    ///< its boundary leaves, in walk order
    std::vector<BorderCrossing> border;  ///< its crossings with another tile's ring cell
};

/// `border` (tm's fresh crossings with a ring cell in another tile, by that tile's key) and
/// `tm.plainTriangles`; the list is made in `scratch` and copied once.
void listBorder(const adf::Adf& a, TileMesh& tm, std::vector<BorderCrossing>& border,
                std::vector<BorderCrossing>& scratch);

/// A build's per-thread buffers, reused across tiles and builds (pool workers live on): grown
/// from empty per tile they would cost thousands of allocations per small mesh. The incidence
/// gathering's arrays are written through raw pointers and only grow.
struct BuildScratch {
    std::vector<uint64_t> neighbourKeys;
    std::vector<TileBuild*> neighbours;         ///< the tiles around the one being meshed
    std::vector<BoundaryCell> walkedLeaves;     ///< a scan's walk, copied once into the tile's
    std::vector<BorderCrossing> borderList;     ///< a scan's border list, copied once
    /// A tile whose crossings are gathered: all (end == UINT32_MAX) or those its border list
    /// names in [begin, end).
    struct CrossingSource {
        TileBuild* tile;
        uint32_t begin, end;
    };
    std::vector<CrossingSource> sources;
    std::vector<Incidence> gathered;        ///< incidences in gathering order
    std::vector<uint32_t> gatheredCell;     ///< per gathered incidence: its cell's number
    /// (key, number) of each cell met that is no boundary leaf of the tile (numbered after them)
    std::vector<std::pair<uint64_t, uint32_t>> otherCells;
    std::vector<uint32_t> walkRank;         ///< cell number -> position in walk order
    std::vector<uint64_t> cellAtRank;       ///< position in walk order -> the cell's key
    std::vector<uint32_t> cellRunBegin;     ///< per cell in walk order: its first incidence, then the end
    std::vector<Incidence> byCell;          ///< the incidences grouped by cell in walk order
    FlatMap64 cellNumber;                   ///< cell key -> its number, for tiles too large for PlaceTable
    CellScratch cycles;
};
/// This thread's build scratch.
BuildScratch& buildScratch();

/// Cycles and projected vertices of every cell `tile` owns, during a build: its incidences
/// from its own crossings and the runs of its `neighbours`' border lists that name it.
void computeVertices(const adf::Adf& adf, TileBuild& tile, const std::vector<TileBuild*>& neighbours,
                     SurfaceNetsStats& st);

}  // namespace detail

}  // namespace kizamu::mesh
