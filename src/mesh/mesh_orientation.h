// SPDX-License-Identifier: Apache-2.0
/// @file mesh_orientation.h
/// @brief Orients each closed part of a mesh by its nesting depth: outward at even depth, into
/// its cavity at odd depth, so the winding-number sign does not depend on how a part was faced.
///
/// The step between a read mesh and its distance source: `makeMeshSource` calls it. Parts are
/// the triangles connected across shared edges, with vertices welded by exact position (the STL
/// reader welds; OBJ, PLY and OFF keep the file's vertices, which may repeat a position, e.g. at
/// texture seams). A part is closed when each of
/// its edges is used by exactly two of its triangles, in opposite directions, and no edge has
/// equal ends; only closed parts are touched. An open or inconsistently oriented part is left as
/// it is: the winding number already copes with holes, and there is no volume to orient by.
/// A closed part's depth is the number of other closed parts that contain it: each of its
/// vertices is inside that part (|winding number| > 3/4) or on it, none outside (< 1/4), and at
/// least one inside. Parts that cross each other contain neither, so overlapping solids stay a
/// union. Why this rule (and what it gives up): docs/decisions/0027-orientation-by-nesting.md.
/// Cold path; any one thread.
#pragma once

#include "mesh/mesh_buffers.h"

#include <cstddef>
#include <string>

namespace kizamu::mesh {

/// What orientClosedComponents found and changed.
struct OrientationReport {
    std::size_t components = 0;        ///< edge-connected parts
    std::size_t closed = 0;            ///< of which closed and consistently oriented
    std::size_t nested = 0;            ///< closed parts inside at least one other (depth >= 1)
    std::size_t flipped = 0;           ///< closed parts whose triangles were reversed
    std::size_t flippedTriangles = 0;  ///< their triangles

    /// Every part is closed: the winding number is an integer off the surface.
    bool allClosed() const { return components > 0 && closed == components; }
};

/// Reverses the triangles of each closed part of `mesh` whose signed volume disagrees with its
/// nesting depth: positive (outward) at even depth, negative (facing into a cavity) at odd. A
/// part with no volume (a two-sided sheet) is left as it is. Only `mesh.indices` changes (the
/// corner order of reversed triangles); nothing is reordered, so vertex attributes still match.
/// Complexity: O(V log V) to weld, O(T) for edges and parts at bounded vertex degree (union-find;
/// each edge's twins found in its first vertex's list). Then, only where one closed part's box
/// holds another's (found through a box tree over the C closed parts: O(C log C) to build, O(log C
/// + k) per part): an O(T_B log T_B) BVH once per holding part B, and O(log T_B) per vertex of the
/// held part A, stopping at the first vertex outside B; a nested A is probed in full, O(V_A log
/// T_B). A single closed part costs no BVH. Threading:  one thread; touches only `mesh`. Memory:
/// about 70 bytes per triangle of scratch, plus the BVHs of holding parts.
OrientationReport orientClosedComponents(MeshBuffers& mesh);

/// One line for an import's warnings, e.g. "reversed 1 of 2 closed parts (1 nested in another)
/// so that each faces out of its material: ...". Empty when nothing was flipped.
std::string describeOrientation(const OrientationReport& report);

}  // namespace kizamu::mesh
