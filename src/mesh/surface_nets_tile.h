// SPDX-License-Identifier: Apache-2.0
/// @file surface_nets_tile.h
/// @brief A stored tile's share of the mesh (TileMesh), the tile geometry the mesher's phases
/// share, an update's scanned leaves (ScannedLeaves), the lazy cell index (indexCells) and the
/// per-thread table of a tile's cells by place (PlaceTable); internal to src/mesh/surface_nets*.
///
/// One TileMesh per tile of the snapshot that holds a crossing or a vertex, owned by
/// SurfaceMesher::mTiles. A tile's TileMesh holds its crossings (emitted by its leaves), the
/// vertices of its cells with their positions, and a lazy index of its cells (an update's way
/// in). Threading: a phase's task writes one tile's records and its own quadrants of other
/// tiles' crossings; other tiles' records are read after the phase's barrier.
#pragma once

#include "adf/adf.h"
#include "adf/boundary_cells.h"
#include "adf/lattice.h"
#include "mesh/slot_pool.h"
#include "mesh/surface_nets_records.h"
#include "util/flat_map.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace kizamu::mesh::detail {

using adf::BoundaryCell;
using util::FlatMap64;

/// A tile's share of the mesh, kept from one build or update to the next: owned by
/// SurfaceMesher::mTiles, freed on its home thread. What lives shorter is held elsewhere: a
/// build's boundary leaves and border list by the build (TileBuild), an update's scanned leaves
/// by SurfaceMesher::mScanned, the assembly's numbering by the mesh() call (so mesh() only reads
/// tiles), per-thread scratch by each thread.
struct TileMesh {
    // The tile (setTile).
    const adf::Tile* tile = nullptr;
    uint64_t key = 0;
    glm::uvec3 slotMin{0}, slotEnd{0};  ///< slots covered
    /// Packed (packLattice): set where a cell's offset from `key` leaves the tile's box (inTile).
    uint64_t outside = 0;
    /// Scheduling: the pool thread that builds it, assembles its share and frees it
    /// (util::parallelForHomes).
    unsigned home = 0;
    // The mesh.
    SlotPool<Crossing> crossings;  ///< emitted by this tile's leaves
    uint32_t liveCrossings = 0;
    std::vector<Vertex> vertices;  ///< a build numbers them by cell in walk order, then cycle
    std::vector<Projected> projected;  ///< per slot of `vertices`
    std::vector<Placed> placed;        ///< per slot of `vertices`
    std::vector<uint32_t> freeVertices;    ///< released slots of `vertices`
    uint32_t liveVertices = 0;
    std::vector<VertexIncidence> incidences;  ///< ranges of the vertices (some unused)
    std::size_t liveIncidences = 0;
    std::vector<MultiFace> multiFaces;
    std::vector<SplitVertex> splits;  ///< numbered after `vertices`
    /// The lazy cell index: cell key -> its first vertex, for every cell with a vertex. An
    /// update reaches the vertices and crossings around a changed cell through it. A build
    /// leaves it to the first update that visits the tile (indexCells): a mesh built once and
    /// never updated (meshAdf, a benchmark) does not pay for it
    /// (docs/decisions/0010-mesher-per-tile-state.md).
    struct LazyCellIndex : FlatMap64 {
        bool pending = false;  ///< yet to be made from `vertices`
    };
    LazyCellIndex cellVertex;
    /// Triangles of its live crossings' polygons, were none of them split (plainTriangles),
    /// kept by a build and updates as crossings come and go: the assembly counts only the few
    /// split ones instead of reading every crossing.
    uint32_t plainTriangles = 0;

    uint32_t allocateVertex() {
        // Copied from a blank record: a record zeroed in place compiles to `rep stos`, whose
        // start-up costs more than the copy of one cache line.
        static const Vertex kBlank{};
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
/// decoded corners: the cells phase takes a re-meshed cell's corners from here rather than
/// searching the snapshot per cell. Owned by SurfaceMesher::mScanned, one per tile scanned, kept
/// until the next update (for their vectors' room).
struct ScannedLeaves {
    std::vector<BoundaryCell> leaves;
    FlatMap64 byCell;  ///< cell key -> its index in `leaves`
};

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

/// Distinct tile keys whose slots touch (closed) the slot box [lo, end), appended to `out`
/// (a coarse tile may appear more than once).
void neighbourKeys(const adf::Adf& adf, glm::uvec3 lo, glm::uvec3 end, std::vector<uint64_t>& out);

/// Makes `tm.cellVertex` if a build left it (pending). A build allocates each cell's vertices in
/// consecutive slots, first to last, so a cell's first vertex has the lowest slot.
inline void indexCells(TileMesh& tm) {
    if (!tm.cellVertex.pending) return;
    tm.cellVertex.pending = false;
    tm.cellVertex.clear();
    tm.cellVertex.reserve(tm.vertices.size());
    for (uint32_t i = 0; i < tm.vertices.size(); ++i)
        if (tm.vertices[i].alive) tm.cellVertex.findOrAssign(packLattice(tm.vertices[i].origin), i);
}

/// A tile's cells by their place in it (the origin's offset, 6 bits an axis), for tiles at most
/// 64 lattice units a side (those at the tile level with the default 6-level tiles): what a
/// build numbers its cells through and looks its leaves up in without a hash map's probing
/// (docs/decisions/0012-mesher-homes-and-place-table.md). Larger tiles use a hash map and the
/// leaf locator.
/// Build scratch: one table per thread, 1 MiB, shared by the crossing and vertex phases (one
/// tile at a time); each user leaves every entry it set empty again (ClearOnExit).
class PlaceTable {
public:
    static constexpr int kBits = 6;
    static constexpr uint32_t kNone = UINT32_MAX;
    static bool fits(const adf::Tile& t, int maxLevel) { return maxLevel - t.level() <= kBits; }
    /// `cell` (packed) lies in the tile whose packed origin is `tileKey`.
    static uint32_t place(uint64_t cell, uint64_t tileKey) {
        const uint64_t d = cell - tileKey;  // a cell of the tile: no field borrows
        constexpr uint64_t m = (1u << kBits) - 1;
        return uint32_t((d & m) | (((d >> 20) & m) << kBits) | (((d >> 40) & m) << (2 * kBits)));
    }
    /// This thread's table (inline: one table per thread whichever file asks).
    static uint32_t* entries() {
        thread_local std::vector<uint32_t> table(std::size_t(1) << (3 * kBits), kNone);
        return table.data();
    }
    /// Empties the places of `cells` cells (key(i) for i < cells) when it goes, thrown past or not.
    template <class Key>
    struct ClearOnExit {
        uint32_t* table;
        uint64_t tileKey;
        std::size_t cells;
        Key key;
        ~ClearOnExit() {
            if (table)
                for (std::size_t i = 0; i < cells; ++i) table[place(key(i), tileKey)] = kNone;
        }
    };
};

}  // namespace kizamu::mesh::detail
