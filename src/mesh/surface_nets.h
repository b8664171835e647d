// SPDX-License-Identifier: Apache-2.0
/// @file surface_nets.h
/// @brief Adaptive SurfaceNets (Kizamu 7.2) with one vertex per sheet, meshed per tile and
/// incrementally.
///
/// Topology. The sign of every lattice point that is a leaf corner is known. A *minimal edge* is
/// a segment between consecutive lattice points on a line where leaves meet; it is exactly an
/// edge of the smallest leaf around it. Every minimal edge whose ends differ in sign (a
/// *crossing*) gets one polygon joining the 3 or 4 leaves around it (Ju et al.'s octree dual
/// contouring), oriented by the edge. A leaf gets one vertex per *cycle*: the crossings on its
/// boundary linked through the leaf-to-leaf faces they lie on, where a face with four or more
/// crossings pairs them so that inside runs are cut off (the same rule from both sides). That
/// is the dual of a closed surface made of one disk per cycle, so the result is closed,
/// consistently oriented, edge- and vertex-manifold whenever the surface stays inside the domain:
/// no cracks between cells of different size (Kizamu figure 9B included: a leaf with no sign
/// change at its own corners still gets a vertex when crossings lie on its faces), and one
/// vertex per sheet where a finest cell holds several. Quads are split along the diagonal
/// through the smallest leaf, which no other polygon can share.
///
/// Geometry. A vertex starts at the mean of its cycle's edge crossings, is projected onto the
/// surface along the gradient, moved half-way along the tangent plane toward its neighbours'
/// mean and projected again, never leaving its cell (Kizamu's relaxation).
///
/// Work. State is kept per stored tile: a tile's *crossings* (emitted by its boundary leaves),
/// the *vertices* of its cells, their positions. An update compares each tile the new snapshot
/// does not share with the previous one against its old version, cell by cell (tile_diff.h),
/// recomputes only the crossings starting on a changed cell, the vertices of the cells around
/// changed crossings (and of changed cells), and relaxes those vertices and their neighbours;
/// the result equals a mesh built from scratch (tests/unit/mesh/surface_nets_test.cpp).
/// Complexity: O(boundary leaves) for a build; an update costs O(slots) to find the rebuilt
/// tiles, O(nodes of the rebuilt tiles) to compare them, and otherwise work proportional to
/// the changed cells (old crossings are reached through a per-tile cell index, never a scan;
/// a build leaves a tile's index to the first update that visits the tile).
/// Threading: tiles in parallel on the pool; one SurfaceMesher is owned by one thread. The
/// pool must outlive the mesher: its destructor, like build(), frees the tiles in a loop on the
/// pool (each on the thread that built it).
/// Memory: 128 bytes per crossing (a removed one's record is reused by a later update), 64 + 16
/// + 24 per vertex (plus its incidences) and 16-21 per cell index entry (a flat hash at most
/// 3/4 full). A build also keeps, per pool thread, scratch the size of the largest tile's
/// boundary leaves and incidences, reused by the next tile and the next build, and a table of a
/// tile's cells by place (1 MiB, surface_nets_tile.h's PlaceTable); an update keeps the
/// boundary leaves its scan found near the changed cells, per tile scanned, until the next
/// update (its cells phase takes their corners).
/// Files: the phases are in surface_nets_crossings.cpp, surface_nets_cycles.cpp,
/// surface_nets_vertices.cpp, surface_nets_assembly.cpp and surface_nets_update.cpp; the build
/// and its scheduling in surface_nets.cpp; the internal state in namespace detail
/// (surface_nets_records.h, surface_nets_tile.h, surface_nets_internal.h); the per-tile deltas
/// a consumer mirrors the mesh from (takeDelta, fullDelta) in mesh_delta.h and .cpp.
#pragma once

#include "adf/adf.h"
#include "mesh/mesh_buffers.h"
#include "mesh/mesh_delta.h"

#include <cstddef>
#include <cstdint>
#include <memory>
#include <unordered_map>
#include <vector>

namespace kizamu::util {
class ThreadPool;
}

namespace kizamu::mesh {

namespace detail {
struct TileMesh;       // a tile's share of the mesh (surface_nets_tile.h)
struct ScannedLeaves;  // an update's boundary leaves of one scanned tile (surface_nets_tile.h)
}  // namespace detail

/// Counters of the last build or update.
struct SurfaceNetsStats {
    std::size_t tilesScanned = 0;      ///< tiles whose crossings were (re)computed
    std::size_t tilesMeshed = 0;       ///< tiles whose vertices were (re)computed
    std::size_t boundaryLeaves = 0;    ///< leaves with a sign change, in the scanned tiles
    std::size_t crossings = 0;         ///< crossings in the whole mesh
    std::size_t vertices = 0;          ///< vertices in the whole mesh
    std::size_t multiSheetCells = 0;   ///< cells with more than one vertex, in the meshed tiles
    std::size_t multiCrossingFaces = 0;  ///< faces with 4 or more crossings, in the meshed tiles
    std::size_t signlessCells = 0;     ///< cells with a vertex but no sign change at their corners (figure 9B)
    std::size_t openCrossings = 0;     ///< crossings on the domain boundary (left open), scanned tiles
    std::size_t splitEdges = 0;        ///< doubled dual edges split by an extra vertex, whole mesh
    std::size_t crossingSlots = 0;     ///< crossing records held, live or released for reuse, whole mesh
    std::size_t oddFaces = 0;          ///< faces with an odd crossing count (never expected)
    std::size_t changedCells = 0;      ///< update: cells where a rebuilt tile differs from the old one
    std::size_t crossingsComputed = 0;  ///< crossings computed (an update recomputes those at changed cells)
    std::size_t cellsMeshed = 0;       ///< update: cells whose vertices were recomputed
    std::size_t verticesComputed = 0;  ///< vertices computed (cycles and first projection)
    std::size_t verticesRelaxed = 0;   ///< vertices relaxed (computed ones and those that read them)
    double crossingMs = 0.0;           ///< wall time: boundary leaves and crossings
    double vertexMs = 0.0;             ///< wall time: cycles, vertices, first projection
    double relaxMs = 0.0;              ///< wall time: split edges, relaxation, normals
};

/// Builds and keeps the SurfaceNets mesh of a sequence of snapshots.
class SurfaceMesher {
public:
    /// @param pool  worker threads, or null for serial meshing (same result either way)
    explicit SurfaceMesher(util::ThreadPool* pool = nullptr);
    ~SurfaceMesher();
    SurfaceMesher(const SurfaceMesher&) = delete;
    SurfaceMesher& operator=(const SurfaceMesher&) = delete;

    /// Meshes `adf` from scratch.
    void build(adf::AdfPtr adf);
    /// Re-meshes what differs between `adf` and the last snapshot (tiles are compared by
    /// identity: an edit shares untouched tiles) and splices it in. Same result as build(adf).
    void update(adf::AdfPtr adf);

    /// The current mesh: world positions (m), unit normals from the field gradient, triangles
    /// counter-clockwise seen from outside. Vertices are ordered by tile, then by cell (a build:
    /// the octree's depth-first order).
    /// Complexity: O(mesh). Memory: the buffers.
    MeshBuffers mesh() const;

    /// The tiles whose shares changed since the last takeDelta() or fullDelta() (mesh_delta.h):
    /// each in full, with the tiles that were dropped. Several updates between two takes give
    /// one delta (the union of their tiles); after a build, a full delta (reset).
    /// Complexity: O(changed tiles' vertices + crossings), parallel over tiles on the pool.
    /// Threading: the mesher's owning thread, between builds and updates (the delta is a value
    /// it may hand to another thread). Memory: the delta.
    MeshDelta takeDelta();
    /// Every tile's share (reset: a consumer's resync). Counts as a take: the next takeDelta()
    /// follows it. Complexity, threading, memory: as takeDelta(), over every tile.
    MeshDelta fullDelta();
    /// Counts builds and updates: the generation a delta taken now brings a mirror to.
    uint64_t generation() const { return mGeneration; }

    const SurfaceNetsStats& stats() const { return mStats; }
    const adf::AdfPtr& snapshot() const { return mAdf; }

private:
    detail::TileMesh* ensureTile(uint64_t key);  ///< null if `key` is no tile of the snapshot
    void dropEmptyTiles();
    /// Drops every tile, each freed on the thread that built it (its home): a free from
    /// another thread is mimalloc's slow path (docs/decisions/0012-mesher-homes-and-place-table.md).
    void clearTiles();
    void totals(SurfaceNetsStats& st) const;

    util::ThreadPool* mPool;
    adf::AdfPtr mAdf;
    std::unordered_map<uint64_t, std::unique_ptr<detail::TileMesh>> mTiles;
    uint32_t mRelaxStamp = 0;  ///< update counter marking vertices queued for relaxation
    SurfaceNetsStats mStats;
    /// An update's scanned tiles' leaves, one set per tile: as many as the last update scanned
    /// stay, for their vectors' room.
    std::vector<std::unique_ptr<detail::ScannedLeaves>> mScanned;
    /// Delta tracking: the keys of the tiles whose shares changed since the last take (with
    /// repeats; appended by update()'s serial steps), whether a build happened since, the
    /// generation counter and the generation of the last take.
    MeshDelta deltaOf(std::vector<uint64_t> keys, bool reset);
    std::vector<uint64_t> mChangedTiles;
    bool mResetPending = true;
    uint64_t mGeneration = 0, mTakenGeneration = 0;
};

/// Convenience: the SurfaceNets mesh of one snapshot.
MeshBuffers meshAdf(adf::AdfPtr adf, util::ThreadPool* pool = nullptr, SurfaceNetsStats* stats = nullptr);

}  // namespace kizamu::mesh
