// SPDX-License-Identifier: Apache-2.0
/// @file mesh_untangle.h
/// @brief Makes a closed mesh's written coordinates safe to weld: no two vertices at one
/// position, and no two triangles meeting anywhere but along the edges and vertices they share.
///
/// SurfaceNets' topology is closed and manifold, but its vertex positions are not free of
/// contact: relaxation can fold a triangle over its neighbour, a large leaf's triangle can
/// cross small ones at a level change, and two sheets of a thin part can put vertices at one
/// point. Slicers and STL readers weld vertices by position, so such a mesh stops being
/// manifold where it matters. `untangle` finds every contact on the float32 positions with
/// exact predicates (mesh/exact_predicates.h) and smooths the vertices around it toward their
/// neighbours' mean until none is left, widening the smoothed patch where a contact persists.
/// The moves are local (a few vertices, within their ring), the topology is kept. It runs where
/// meshes are written, not in the mesher (docs/decisions/0029-untangle-at-export.md).
/// Determinism: the result depends on the mesh's geometry and connectivity, not on the
/// numbering (neighbours are summed in the order of their positions), so two numberings of one
/// mesh untangle to the same positions.
/// Complexity: O(T log T) per round (a tree of triangle boxes), a few rounds.
/// Threading: the pair tests in parallel on a pool, the rest on the caller's thread; the mesh is
/// the caller's.
#pragma once

#include "mesh/mesh_buffers.h"

#include <glm/vec3.hpp>

#include <cstddef>

namespace kizamu::util {
class ThreadPool;
}

namespace kizamu::mesh {

struct UntangleReport {
    std::size_t coincidentVertices = 0;  ///< vertices that shared a position with another, at first
    std::size_t contacts = 0;            ///< triangle pairs in contact (and degenerate triangles), at first
    std::size_t verticesMoved = 0;       ///< distinct vertices moved, over all rounds
    double largestMove = 0.0;            ///< the farthest any vertex ended from where it was (mesh units)
    std::size_t rounds = 0;              ///< detection passes that found something
    std::size_t remaining = 0;           ///< coincident vertices plus contacts left (0 unless the rounds ran out)
};

/// How a writer turns a position into the one a reader gets back (a 3MF's six decimals); the
/// identity where it writes floats as they are.
using WrittenPosition = glm::vec3 (*)(const glm::vec3&);

/// Separates coincident vertices and removes contacts from `mesh` (positions only).
/// @param pool the pair tests run on it (nullptr: on the caller's thread); the result is the same
/// @param maxRounds detection-and-smoothing rounds before it gives up (`remaining` says what is left)
/// @param written where set, contacts and coincidences are decided on written(position), what
///        the file will hold, while the mesh keeps the positions to hand to the writer
UntangleReport untangle(MeshBuffers& mesh, util::ThreadPool* pool = nullptr, int maxRounds = 64,
                        WrittenPosition written = nullptr);

}  // namespace kizamu::mesh
