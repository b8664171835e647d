// SPDX-License-Identifier: Apache-2.0
/// @file surface_nets_internal.h
/// @brief The mesher's per-tile state and the per-cell steps shared by a full build
/// (surface_nets.cpp) and the sub-tile update (surface_nets_update.cpp).
///
/// References between tiles: a crossing holds a VertexRef (tile, index) for each leaf around it,
/// written only by the tile owning that leaf; a vertex lists its crossings by pointer, so
/// crossings live in a SlotPool and never move. Both sides are rewritten together whenever a
/// cell is re-meshed, which is what lets an update replace single crossings and cells.
/// Threading: as surface_nets.h (a slot is written by one task per phase, read after a barrier).
#pragma once

#include "adf/boundary_cells.h"
#include "adf/lattice.h"
#include "adf/tile_diff.h"
#include "util/flat_map.h"
#include "mesh/slot_pool.h"
#include "mesh/surface_nets.h"

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

using adf::packLattice;
using adf::unpackLattice;

/// A vertex's owner and index; filled in by the tile that owns the cell. Packed (12 bytes, no
/// padding): a crossing holds four.
struct __attribute__((packed, aligned(4))) VertexRef {
    SurfaceMesher::TileMesh* tile = nullptr;
    uint32_t index = 0;
};

/// Per axis and quadrant q of a leaf around an edge along it: the edge's start as a corner of
/// the leaf, packed in its sizes (the leaf's +a (+b) side where q lies on the edge's -a (-b)
/// side, q1 and q2 (q2 and q3); quadrants as Crossing's).
constexpr auto kStartCorner = [] {
    std::array<std::array<uint64_t, 4>, 3> t{};
    for (uint32_t k = 0; k < 3; ++k)
        for (uint32_t q = 0; q < 4; ++q) {
            glm::uvec3 c(0);
            c[(k + 1) % 3] = q == 1 || q == 2;
            c[(k + 2) % 3] = q == 2 || q == 3;
            t[k][q] = packLattice(c);
        }
    return t;
}();

/// One sign-changing minimal edge and the leaves around it. Quadrants q0..q3 turn
/// counter-clockwise about +axis: (+a,+b), (-a,+b), (-a,-b), (+a,-b) with a, b the next axes.
/// Two cache lines: a build writes and re-reads tens of thousands, and 64 bytes more cost 3 %
/// of a build (docs/PERFORMANCE.md, "Twenty-third session"). So what follows from other fields
/// is not stored: the start point (a corner of the emitting leaf) and the tiles holding the
/// ring cells (ownerKey, inTile). The first line holds what the incidences are
/// gathered from and what a cell reads, the second the vertex refs (all relaxation reads).
struct alignas(64) Crossing {
    uint32_t length = 0;
    uint8_t axis = 0;
    uint8_t startInside = 0;  ///< start corner negative: the surface faces +axis
    uint8_t emitter = 0;      ///< quadrant of the smallest leaf (it emitted this record)
    uint8_t alive = 0;        ///< a slot of the pool in use
    uint8_t ringLevel[4] = {};
    glm::vec3 point{0.0f};       ///< zero crossing, lattice units
    uint32_t slot = 0;           ///< its index in the emitting tile's pool
    uint64_t ringCell[4] = {};   ///< packed leaf origins
    VertexRef ringVertex[4];
    /// Extra vertex on the face between ring cells q and q+1, where that face carries two
    /// segments joining the same pair of vertices: its index in `splits` of the face's owner,
    /// the tile of the smaller of the two cell keys (faceCell), or kNoSplit. Nearly always
    /// none: an index, not a VertexRef, keeps the record small.
    uint32_t split[4] = {kNoSplit, kNoSplit, kNoSplit, kNoSplit};
    static constexpr uint32_t kNoSplit = UINT32_MAX;

    /// The start point, packed (packLattice): the emitting leaf's corner on the edge.
    uint64_t packedStart() const { return ringCell[emitter] + uint64_t(length) * kStartCorner[axis][emitter]; }
    glm::uvec3 start() const { return unpackLattice(packedStart()); }
    /// The ring cell whose tile owns the face between ring cells q and q + 1 (where split[q]
    /// lives): the smaller key.
    uint64_t faceCell(int q) const { return std::min(ringCell[q], ringCell[(q + 1) % 4]); }

    /// Unique per minimal edge (one minimal edge starts at a point along an axis).
    uint64_t key() const { return packedStart() | (uint64_t(axis) << 60); }
    /// The same edge, surface direction, ring of leaves and point (the tiles holding the ring
    /// cells are the caller's to compare where snapshots differ).
    bool sameAs(const Crossing& o) const {
        return length == o.length && axis == o.axis && startInside == o.startInside && emitter == o.emitter &&
               std::equal(ringLevel, ringLevel + 4, o.ringLevel) && std::equal(ringCell, ringCell + 4, o.ringCell) &&
               point == o.point;
    }
};
static_assert(sizeof(Crossing) == 128 && offsetof(Crossing, ringVertex) == 64, "a crossing is two cache lines");

/// Quadrants a cell occupies around a crossing, as a cyclic run first..last.
struct Incidence {
    uint64_t cell;
    uint64_t crossingKey;
    Crossing* x;
    uint8_t first, last;
};

struct VertexIncidence {
    Crossing* x;
    uint8_t first, last;
};

/// A vertex as its cell makes it and its relaxation reads it: 64 bytes. What the
/// relaxation writes and neighbours read live apart (TileMesh::projected, placed).
struct Vertex {
    glm::uvec3 origin{0};  ///< the cell's
    uint32_t size = 0;
    float corners[8] = {};  ///< the cell's: projection reads the cell's own trilinear field
    uint32_t incBegin = 0, incEnd = 0;
    uint32_t nextInCell = UINT32_MAX;  ///< the cell's next vertex (several sheets), or none
    bool alive = true;                 ///< false: a released slot
};

/// What a vertex's neighbours read when they relax, kept apart from the vertex (TileMesh::
/// projected): the reads then come from a dense array, 16 bytes a vertex, not from the
/// 64-byte records.
struct Projected {
    glm::vec3 point{0.0f};  ///< after the first projection, lattice units
    /// The last update that marked it for relaxation; next to `point`, which a neighbour's
    /// relaxation reads in the same cache line when it checks the mark.
    uint32_t relaxStamp = 0;
};

/// A vertex's final place, as its relaxation writes it and the assembly reads it
/// (TileMesh::placed).
struct Placed {
    glm::vec3 position{0.0f};  ///< lattice units
    glm::vec3 normal{0.0f};
};

/// A face with four or more crossings, recorded by the cell with the smaller key: its segments
/// (crossing pairs) and the ring positions of the two cells in each crossing.
struct MultiFace {
    uint64_t cellA = 0, cellB = 0;
    struct End {
        Crossing* x;
        uint8_t qA, qB;  ///< ring positions of A and B next to each other
    };
    std::vector<std::pair<End, End>> segments;
};

/// A vertex splitting a doubled dual edge: placed half-way between its two ends.
struct SplitVertex {
    VertexRef a, b;
};

}  // namespace detail

struct SurfaceMesher::TileMesh {
    const adf::Tile* tile = nullptr;
    uint64_t key = 0;
    glm::uvec3 slotMin{0}, slotEnd{0};  ///< slots covered
    /// Packed (packLattice): set where a cell's offset from `key` leaves the tile's box (inTile).
    uint64_t outside = 0;
    unsigned home = 0;  ///< the pool thread that builds it and assembles its share (util::parallelForHomes)
    std::vector<BoundaryCell> leaves;   ///< during a build only, in walk order (walkOrder)
    SlotPool<detail::Crossing> crossings;  ///< emitted by this tile's leaves
    uint32_t liveCrossings = 0;
    /// During a build: crossings with a leaf owned by another tile, by that tile's key, so a
    /// neighbour gathering its cells' crossings reads only its own range.
    struct BorderRef {
        uint64_t owner;
        uint32_t index;
        bool operator<(const BorderRef& o) const { return owner != o.owner ? owner < o.owner : index < o.index; }
    };
    std::vector<BorderRef> border;
    std::vector<detail::Vertex> vertices;  ///< a build numbers them by cell in walk order, then cycle
    std::vector<detail::Projected> projected;  ///< per slot of `vertices`
    std::vector<detail::Placed> placed;        ///< per slot of `vertices`
    std::vector<uint32_t> freeVertices;    ///< released slots of `vertices`
    uint32_t liveVertices = 0;
    std::vector<detail::VertexIncidence> incidences;  ///< ranges of the vertices (some unused)
    std::size_t liveIncidences = 0;
    std::vector<detail::MultiFace> multiFaces;
    std::vector<detail::SplitVertex> splits;  ///< numbered after `vertices`
    /// Cell key -> its first vertex, for every cell with a vertex: an update reaches the
    /// vertices and crossings around a changed cell through it. A build leaves it to the first
    /// update that visits the tile (indexCells): a mesh built once and never updated (meshAdf,
    /// a benchmark) does not pay for it, 1.5 % of a build.
    FlatMap64 cellVertex;
    bool cellVertexPending = false;  ///< cellVertex is yet to be made from `vertices`
    /// Triangles of its live crossings' polygons, were none of them split (plainTriangles),
    /// kept by a build and updates as crossings come and go: the assembly counts only the few
    /// split ones instead of reading every crossing.
    uint32_t plainTriangles = 0;
    uint32_t offset = 0;  ///< first vertex in the assembled mesh
    /// Slots below this are numbered by slot (outNumber empty): the assembly's fast path.
    uint32_t denseEnd = 0;
    /// Vertex slot (then split) -> number within the tile's share of the mesh; empty where no
    /// slot is released (the number is the slot).
    std::vector<uint32_t> outNumber;
    uint32_t share = 0;  ///< the tile's position in the assembly's order

    uint32_t allocateVertex() {
        // Copied from a blank record: a record zeroed in place compiled to `rep stos`, whose
        // start-up took 6 % of a build's cell phase.
        static const detail::Vertex kBlank{};
        ++liveVertices;
        if (freeVertices.empty()) {
            vertices.push_back(kBlank);
            projected.emplace_back();
            placed.emplace_back();
            return uint32_t(vertices.size() - 1);
        }
        const uint32_t i = freeVertices.back();
        freeVertices.pop_back();
        vertices[i] = kBlank;
        projected[i] = {};
        placed[i] = {};
        return i;
    }
    void releaseVertex(uint32_t i) {
        vertices[i].alive = false;
        freeVertices.push_back(i);
        --liveVertices;
    }
};

/// The boundary leaves an update's scan of one tile found near the changed cells, with their
/// decoded corners: the cells phase takes a re-meshed cell's corners from here (a search of
/// the snapshot per cell took 4 % of an update's instructions).
struct SurfaceMesher::ScannedLeaves {
    std::vector<BoundaryCell> leaves;
    FlatMap64 byCell;  ///< cell key -> its index in `leaves`
};

namespace detail {

using TileMesh = SurfaceMesher::TileMesh;

/// Whether the cell at packed origin `cell` lies in the tile at packed origin `tileKey` whose
/// TileMesh::outside is `outside`. Coordinates stay below 2^17 in 20-bit fields: a coordinate
/// below the tile's borrows from the next field and leaves bits above the tile's side in its
/// own, one at or beyond the tile's end sets such a bit, and either way a bit of `outside`.
inline bool inTile(uint64_t cell, uint64_t tileKey, uint64_t outside) { return ((cell - tileKey) & outside) == 0; }

/// TileMesh::outside of tile `t`: the bits outside its side, in every packed field.
inline uint64_t outsideOf(const adf::Tile& t, int maxLevel) {
    return ~packLattice(glm::uvec3((1u << uint32_t(maxLevel - t.level())) - 1));
}

/// Points `tm` at tile `t`: its key, slot box and `outside` follow.
void setTile(const adf::Adf& adf, const adf::Tile& t, TileMesh& tm);

/// Whether tile `t` can emit crossings: it holds a boundary leaf (a single leaf without a sign
/// change emits nothing; it can still own ring cells, figure 9B).
inline bool mayEmit(const adf::Tile& t) { return !(t.singleLeaf() && t.rootType() != adf::CellType::Boundary); }

/// fn(slot) for every slot in the closed box [lo, end] grown by one slot, clipped to the domain
/// (`slots` a side): the slots whose tiles touch a tile covering [lo, end).
template <class Fn>
void forSlotsAround(glm::uvec3 lo, glm::uvec3 end, uint32_t slots, Fn fn) {
    const glm::uvec3 a(lo.x ? lo.x - 1 : 0, lo.y ? lo.y - 1 : 0, lo.z ? lo.z - 1 : 0);
    const glm::uvec3 b(std::min(end.x + 1, slots), std::min(end.y + 1, slots), std::min(end.z + 1, slots));
    for (uint32_t z = a.z; z < b.z; ++z)
        for (uint32_t y = a.y; y < b.y; ++y)
            for (uint32_t x = a.x; x < b.x; ++x) fn(glm::uvec3(x, y, z));
}

/// The key of the tile holding the cell at packed origin `cell` in `adf`.
inline uint64_t ownerKey(const adf::Adf& adf, uint64_t cell) {
    const uint32_t shift = uint32_t(adf.domain().maxLevel - adf.domain().tileLevel());
    return packLattice(adf.tileAtSlot(unpackLattice(cell) >> shift)->latticeOrigin());
}

/// Which edge start points a computation wants (an update: those on changed cells).
struct StartFilter {
    bool (*keep)(const void* context, glm::uvec3 start) = nullptr;
    const void* context = nullptr;
};

/// Appends records to a tile's crossing pool, numbering their slots, with no vertices and no
/// split vertices (what a build writes computeCrossings into: no intermediate copy of the large
/// records). computeCrossings writes every other field, so the rest is not cleared first
/// (zeroing the whole record took 7 % of the crossing phase).
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

/// Triangles of a crossing's polygon without split vertices: a triangle where a larger leaf
/// fills two quadrants, else a quad's two.
inline uint32_t plainTriangles(const Crossing& x) {
    const uint64_t* c = x.ringCell;
    const uint32_t corners = (c[0] != c[3]) + (c[1] != c[0]) + (c[2] != c[1]) + (c[3] != c[2]);
    return corners == 3 ? 1u : 2u;
}

/// The run of quadrants that ring cell q fills (a larger leaf fills two when the edge lies in
/// its face), as Incidence::first/last.
void incidenceRun(const Crossing& x, int q, uint8_t& first, uint8_t& last);

/// Reusable buffers of meshCell.
struct CellScratch {
    struct FaceEntry {
        uint64_t neighbour;
        int q;  ///< ring position of the neighbour
        uint32_t local;
    };
    std::vector<FaceEntry> faces;
    std::vector<const Crossing*> faceXs;
    std::vector<std::pair<uint32_t, uint32_t>> pairs;
    std::vector<uint32_t> cycleOf, parent, made;
    /// The crossings hold no split vertices yet (a build: fresh records), so meshCell need not
    /// forget them (it would write a cache line of each crossing that is read nowhere else).
    bool freshCrossings = false;
};

/// Cycles and projected vertices of one cell owned by `tm`, from all its incidences `inc[0..n)`
/// sorted by crossing key (the order fixes every float sum, so a build and an update agree bit
/// for bit) and its 8 corners. Takes vertex slots from `tm` (released ones first), appends
/// their incidences and the cell's multi-crossing faces, writes the vertex refs into the
/// crossings' slots of this cell and forgets split vertices on faces toward larger keys.
/// Returns the first vertex (UINT32_MAX if n == 0); the others follow through nextInCell.
uint32_t meshCell(const adf::Adf& adf, TileMesh& tm, const Incidence* inc, uint32_t n, const float corners[8],
                  CellScratch& s, SurfaceNetsStats& st);

/// Distinct tile keys whose slots touch (closed) the slot box [lo, end), appended to `out`
/// (a coarse tile may appear more than once).
void neighbourKeys(const adf::Adf& adf, glm::uvec3 lo, glm::uvec3 end, std::vector<uint64_t>& out);

/// Makes `tm.cellVertex` if a build left it (cellVertexPending). A build allocates each cell's
/// vertices in consecutive slots, first to last, so a cell's first vertex has the lowest slot.
inline void indexCells(TileMesh& tm) {
    if (!tm.cellVertexPending) return;
    tm.cellVertexPending = false;
    tm.cellVertex.clear();
    tm.cellVertex.reserve(tm.vertices.size());
    for (uint32_t i = 0; i < tm.vertices.size(); ++i)
        if (tm.vertices[i].alive) tm.cellVertex.findOrAssign(packLattice(tm.vertices[i].origin), i);
}

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
/// vertices ahead: a build's relaxation phase took 16 % less on the AMD host (docs/PERFORMANCE.md,
/// "Eleventh session"). Asking for the neighbours one vertex ahead as well paid there and cost
/// 12 % on the Intel host ("Twenty-second session"), whose larger caches hold them anyway.
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

}  // namespace detail

}  // namespace kizamu::mesh
