// SPDX-License-Identifier: Apache-2.0
/// @file mesh_intersections.h
/// @brief An exact check that a triangle mesh is embedded: no coincident vertices, no degenerate
/// or duplicate triangles, and no two triangles meeting anywhere but along what they share.
///
/// A test oracle for the mesher that shares no code with it (src/mesh/surface_nets*,
/// src/mesh/triangle_bvh.*): its own bounding-volume hierarchy over triangle boxes finds the
/// candidate pairs, and CGAL's exact predicates (Exact_predicates_inexact_constructions_kernel:
/// interval filters with an exact fallback) decide each one on the float32 coordinates, which
/// convert to double exactly. No tolerance anywhere: a vertex that lies exactly on another
/// triangle's plane is decided as exactly as one a metre away.
///
/// Vertices are welded by position first (bit-equal floats, -0 taken as +0), so "shared" means
/// "at the same position", whatever the indices say; coincident vertices are reported on their
/// own. Per pair of welded triangles:
///  - no shared vertex: the closed triangles must be disjoint;
///  - one shared vertex: they meet only there (each triangle's opposite edge misses the other
///    closed triangle, both ways; for two non-degenerate triangles this is equivalent);
///  - a shared edge: not coplanar with the third vertices on the same side of the edge (a fold);
///  - three shared vertices: a duplicate triangle, either orientation.
/// Triangles with collinear (or non-finite) vertices are degenerate and take no part in the pairs.
///
/// Part of kizamu_testing (tests/support/); CGAL is confined to mesh_intersections.cpp. Any
/// thread; allocates.
#pragma once

#include "mesh/mesh_buffers.h"
#include "tests/util/mesh_check.h"

#include <gtest/gtest.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace kizamu::test {

/// What a violation is; each has its own count in MeshIntersections.
enum class MeshDefect {
    CoincidentVertices,  ///< two or more vertices at one position (a group)
    DegenerateTriangle,  ///< zero area: collinear or repeated vertices, or a non-finite one
    DuplicateTriangle,   ///< two triangles on the same three positions
    FoldedEdge,          ///< two triangles on one edge, coplanar and on the same side of it
    MeetAtSharedVertex,  ///< two triangles sharing one vertex that also meet elsewhere
    Intersecting,        ///< two triangles sharing no vertex that meet (touching included)
};

/// MeshDefect values run 0 .. kMeshDefectKinds - 1.
inline constexpr std::size_t kMeshDefectKinds = 6;

/// One example of a defect: two vertex indices (CoincidentVertices), two triangle indices (the
/// pairs), or one triangle index and `second` = kNone (DegenerateTriangle). Indices of the mesh
/// as given, not the welded one.
struct MeshDefectExample {
    static constexpr uint32_t kNone = ~0u;
    MeshDefect kind;
    uint32_t first;
    uint32_t second;
};

/// The outcome of findMeshIntersections: counts per defect, and the first few examples of each.
struct MeshIntersections {
    static constexpr std::size_t kExamplesPerKind = 3;
    std::size_t coincidentVertexGroups = 0;
    std::size_t degenerateTriangles = 0;
    std::size_t duplicateTriangles = 0;     ///< pairs
    std::size_t foldedEdges = 0;            ///< pairs
    std::size_t meetingAtSharedVertex = 0;  ///< pairs
    std::size_t intersecting = 0;           ///< pairs
    std::size_t candidatePairs = 0;         ///< pairs whose boxes touch (for cost figures)
    std::vector<MeshDefectExample> examples;

    std::size_t count(MeshDefect kind) const;
    std::size_t violations() const;
    bool clean() const { return violations() == 0; }
    /// "2 coincident vertex groups, 1 folded edge pair (e.g. triangles 10 and 11: (x, y, z) ...)".
    std::string describe(const mesh::MeshBuffers& mesh) const;
};

/// Checks `mesh` for every defect in MeshDefect, exactly on its float coordinates.
/// Requires every index in range (mesh.valid() or at least the indices).
/// Complexity: O(n log n) in triangles n for the hierarchy, plus O(1) per candidate pair (about
///             7 per triangle on the mesher's output); some 15 ms per 10k triangles
/// Threading:  reads `mesh` only; single-threaded (callers run meshes in parallel)
/// Memory:     O(n) scratch
MeshIntersections findMeshIntersections(const mesh::MeshBuffers& mesh);

/// `mesh` with its vertices merged where positions are bit-equal (-0 taken as +0): positions in
/// order of first use by vertex index, indices remapped, normals and colours of the first of each
/// group kept.
mesh::MeshBuffers weldByPosition(const mesh::MeshBuffers& mesh);

/// findMeshIntersections finds nothing; otherwise the counts and examples.
inline ::testing::AssertionResult noSelfIntersections(const mesh::MeshBuffers& mesh) {
    const MeshIntersections r = findMeshIntersections(mesh);
    if (r.clean()) return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << r.describe(mesh);
}

/// The mesh welded by position is closed, oriented and manifold (closedOrientedManifold): what
/// holds up the embedding claim when vertices coincide.
inline ::testing::AssertionResult weldsToClosedManifold(const mesh::MeshBuffers& mesh) {
    const ::testing::AssertionResult r = closedOrientedManifold(weldByPosition(mesh));
    if (r) return r;
    return ::testing::AssertionFailure() << "welded by position: " << r.message();
}

}  // namespace kizamu::test
