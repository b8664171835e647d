// SPDX-License-Identifier: Apache-2.0
/// @file mesh_delta.h
/// @brief The mesh as per-tile shares addressed by (tile, slot), the changes of one or more
/// updates as a MeshDelta, and the consumer's copy of the mesh (MeshMirror).
///
/// Pipeline: the edit thread's SurfaceMesher records, per build and update, which tiles' shares
/// changed (SurfaceMesher::takeDelta, fullDelta in surface_nets.h); it hands the delta to the
/// render thread, which applies it to its MeshMirror and flattens that into MeshBuffers. The
/// render thread never reads the mesher: it may fall behind (the mesher keeps collecting the
/// changed tiles, so the next take holds them all) and may ask for a resync (a full delta).
///
/// Addressing. A vertex is (tile key, slot): the tile is the TileMesh owning the vertex's cell,
/// keyed by its packed lattice origin; the slot is the vertex's index in that tile's vertex
/// slots, which does not change while the vertex lives (a released slot is reused by a later
/// vertex, and every triangle naming the old one is rewritten, so its tile is in the same
/// delta). A split vertex (the extra vertex on a doubled dual edge) is (owner tile, kSplitSlot +
/// its index in that tile's split list). A fan centre (the centre of a polygon with a split
/// vertex on a side) has no address: a fan is given as its polygon. Split vertices and fan
/// centres are derived from other tiles' vertices (a split lies half-way between its two ends,
/// a centre at its polygon's mean), so the consumer computes them when it flattens: a vertex
/// that relaxation moves changes only its own tile's share.
/// Each tile's share holds its vertex slots (positions in lattice units, normals, live flags),
/// its split vertices (as their two ends' addresses), and the triangles and fans of the
/// crossings it emitted, whose corners may lie in up to four tiles.
/// Threading: a MeshDelta is a value handed between threads; a MeshMirror is owned by one
/// thread (the consumer).
#pragma once

#include "mesh/mesh_buffers.h"

#include <glm/vec3.hpp>

#include <array>
#include <cstddef>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace kizamu::mesh {

/// Where a vertex of the mesh lives: see the file comment.
struct VertexAddress {
    static constexpr uint32_t kSplitSlot = 0x80000000u;  ///< slots from here are split vertices
    uint64_t tile = 0;  ///< the owning tile's key (its packed lattice origin, adf::packLattice)
    uint32_t slot = 0;  ///< the vertex slot, or kSplitSlot + the split vertex's index
    bool isSplit() const { return slot >= kSplitSlot; }
    bool operator==(const VertexAddress&) const = default;
};

/// A polygon with a split vertex on a side, fanned around its centre (the mean of its corners'
/// world positions, in corner order; the normal the normalised sum of theirs, +z if zero):
/// triangles (centre, corner i, corner i + 1), reversed where `flip`.
struct MeshFan {
    std::array<VertexAddress, 8> corners{};
    uint8_t count = 0;
    bool flip = false;
};

/// One tile's share of the mesh, complete (a delta never sends part of a share).
struct MeshTileShare {
    uint64_t key = 0;
    std::vector<glm::vec3> positions;  ///< per vertex slot, lattice units (0 where not alive)
    std::vector<glm::vec3> normals;    ///< per vertex slot, unit (0 where not alive)
    std::vector<uint8_t> alive;        ///< per vertex slot: 1 live, 0 a free slot
    /// Split vertex i: half-way between its ends (lattice positions averaged, then to world);
    /// its normal the normalised sum of theirs (the first end's if zero).
    std::vector<std::array<VertexAddress, 2>> splits;
    std::vector<std::array<VertexAddress, 3>> triangles;  ///< counter-clockwise seen from outside
    std::vector<MeshFan> fans;
};

/// The shares that changed between two generations of a mesher's mesh. Applying it to a
/// mirror of generation `base` gives the mirror of `generation`.
struct MeshDelta {
    uint64_t base = 0;        ///< the generation it applies to (ignored where `reset`)
    uint64_t generation = 0;  ///< the mesher's generation it brings the mirror to
    bool reset = false;       ///< a full mesh: the mirror drops every tile first (a build, a resync)
    glm::dvec3 originWorld{0.0};  ///< world position (m) of lattice point 0
    double cellSize = 0.0;        ///< finest cell (m): world = originWorld + lattice * cellSize
    std::vector<MeshTileShare> tiles;  ///< every tile whose share changed, by key, in full
    std::vector<uint64_t> removed;     ///< tiles that no longer hold mesh, by key (may be unknown to the mirror)
    /// The newest tool sample whose effect this delta first shows: its time stamp (the producer's
    /// monotonic clock, ns; engine::ToolSample::timeNs), for sample-to-visible latency; 0: none.
    /// Coalescing keeps the newer of the two.
    int64_t newestSampleNs = 0;

    bool empty() const { return !reset && tiles.empty() && removed.empty(); }
};

/// Folds `newer` (which must follow `older`: newer.base == older.generation, or newer.reset)
/// into `older`, as if one take had produced both: what a mailbox does when its consumer has
/// not taken the last delta yet. Complexity: O(tiles of both, log). Threading: pure.
/// @throw std::invalid_argument if `newer` does not follow `older`
void coalesce(MeshDelta& older, MeshDelta&& newer);

/// The consumer's copy of the mesh: tile key -> share, kept by applying deltas.
/// Owned by one thread (the render thread); not thread-safe.
class MeshMirror {
public:
    /// Applies `delta` if it follows this mirror (delta.base == generation(), or delta.reset);
    /// returns false and changes nothing otherwise: the consumer missed a delta and should ask
    /// for a full one. Complexity: O(tiles in the delta). Memory: takes the shares over.
    bool apply(MeshDelta&& delta);

    /// The mesh: positions (world, m), normals, triangles, as SurfaceMesher::mesh() gives for the
    /// same generation up to vertex and triangle order (no colours). Vertices by tile key, then
    /// slot, then splits; fan centres last.
    /// Complexity: O(mesh). Memory: the buffers and a number per vertex slot.
    /// @throw std::logic_error if an address names a tile or slot the mirror lacks (a bug)
    MeshBuffers flatten() const;

    uint64_t generation() const { return mGeneration; }
    /// The newest MeshDelta::newestSampleNs applied (0: none yet).
    int64_t newestSampleNs() const { return mNewestSampleNs; }
    std::size_t tileCount() const { return mTiles.size(); }
    bool hasTile(uint64_t key) const { return mTiles.count(key) != 0; }
    const MeshTileShare* tile(uint64_t key) const;

private:
    std::unordered_map<uint64_t, MeshTileShare> mTiles;
    uint64_t mGeneration = 0;
    bool mSynced = false;  ///< a reset delta was applied
    int64_t mNewestSampleNs = 0;
    glm::dvec3 mOriginWorld{0.0};
    double mCellSize = 0.0;
};

}  // namespace kizamu::mesh
