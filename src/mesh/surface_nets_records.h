// SPDX-License-Identifier: Apache-2.0
/// @file surface_nets_records.h
/// @brief The mesher's records: a crossing, a vertex and what links them (internal to
/// src/mesh/surface_nets*).
///
/// A crossing (one sign-changing minimal edge) names the four ring cells around it and, once
/// their tiles have meshed them, the vertex of each (VertexRef); a vertex lists its crossings
/// by pointer (VertexIncidence). Both sides are rewritten together whenever a cell is re-meshed,
/// which is what lets an update replace single crossings and cells. Crossings live in a
/// SlotPool and never move.
/// Layout: every size below is part of the design (docs/decisions/0011-mesher-record-layout.md)
/// and asserted: a build writes and re-reads hundreds of thousands of these records, so what
/// follows from other fields is not stored, and the fields each phase reads share cache lines.
/// Threading: a record is written by one task per phase and read by others after a barrier.
#pragma once

#include "adf/lattice.h"

#include <glm/vec3.hpp>

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace kizamu::mesh::detail {

using adf::packLattice;
using adf::unpackLattice;

struct TileMesh;

/// A vertex's owner and index; filled in by the tile that owns the cell. Packed (12 bytes, no
/// padding): a crossing holds four.
struct __attribute__((packed, aligned(4))) VertexRef {
    TileMesh* tile = nullptr;
    uint32_t index = 0;
};
static_assert(sizeof(VertexRef) == 12, "a crossing holds four vertex refs in its second cache line");

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

/// One sign-changing minimal edge and the leaves around it (its ring). Quadrants q0..q3 turn
/// counter-clockwise about +axis: (+a,+b), (-a,+b), (-a,-b), (+a,-b) with a, b the next axes.
/// Two cache lines (docs/decisions/0011-mesher-record-layout.md), so what follows from other
/// fields is not stored: the start point (a corner of the emitting leaf) and the tiles holding
/// the ring cells (ownerKey, inTile). The first line holds what the incidences are gathered
/// from and what a cell reads, the second the vertex refs (all relaxation reads).
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

/// Quadrants a cell occupies around a crossing, as a cyclic run first..last: what a cell's
/// vertices are made from (sorted by crossingKey, which fixes every float sum).
struct Incidence {
    uint64_t cell;
    uint64_t crossingKey;
    Crossing* x;
    uint8_t first, last;
};
static_assert(sizeof(Incidence) == 32);

/// An incidence as a vertex keeps it (its cell is the vertex's, its key the crossing's).
struct VertexIncidence {
    Crossing* x;
    uint8_t first, last;
};
static_assert(sizeof(VertexIncidence) == 16);

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
static_assert(sizeof(Vertex) == 64, "a vertex is one cache line");

/// What a vertex's neighbours read when they relax, kept apart from the vertex (TileMesh::
/// projected): the reads then come from a dense array, 16 bytes a vertex, not from the
/// 64-byte records.
struct Projected {
    glm::vec3 point{0.0f};  ///< after the first projection, lattice units
    /// The last update that marked it for relaxation; next to `point`, which a neighbour's
    /// relaxation reads in the same cache line when it checks the mark.
    uint32_t relaxStamp = 0;
};
static_assert(sizeof(Projected) == 16);

/// A vertex's final place, as its relaxation writes it and the assembly reads it
/// (TileMesh::placed).
struct Placed {
    glm::vec3 position{0.0f};  ///< lattice units
    glm::vec3 normal{0.0f};
};
static_assert(sizeof(Placed) == 24);

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

/// Triangles of a crossing's polygon without split vertices: a triangle where a larger leaf
/// fills two quadrants, else a quad's two.
inline uint32_t plainTriangles(const Crossing& x) {
    const uint64_t* c = x.ringCell;
    const uint32_t corners = (c[0] != c[3]) + (c[1] != c[0]) + (c[2] != c[1]) + (c[3] != c[2]);
    return corners == 3 ? 1u : 2u;
}

/// The run of quadrants that ring cell q fills (a larger leaf fills two when the edge lies in
/// its face), as Incidence::first/last. Inline: the incidence gathering calls it per crossing.
inline void incidenceRun(const Crossing& x, int q, uint8_t& first, uint8_t& last) {
    // The run of equal ring cells through q, walked both ways (a cyclic run of at most three:
    // no leaf holds an edge inside it); nearly always q alone, two comparisons.
    const uint64_t* c = x.ringCell;
    int f = q, l = q;
    for (int i = 0; i < 2 && c[(f + 3) % 4] == c[q]; ++i) f = (f + 3) % 4;
    for (int i = 0; i < 2 && c[(l + 1) % 4] == c[q]; ++i) l = (l + 1) % 4;
    first = uint8_t(f);
    last = uint8_t(l);
}

}  // namespace kizamu::mesh::detail
