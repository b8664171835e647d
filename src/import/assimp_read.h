// SPDX-License-Identifier: Apache-2.0
/// @file assimp_read.h
/// @brief One file read by assimp and flattened into one triangle mesh: the work of
/// `kizamu-import`; besides it only the import probe (tests/tools) runs assimp in its own
/// process (docs/decisions/0028-assimp-in-a-child-process.md).
///
/// The scene is flattened: every mesh with its node transforms applied
/// (aiProcess_PreTransformVertices), polygons triangulated (aiProcess_Triangulate), points and
/// lines dropped (aiProcess_SortByPType), normals, texture coordinates, colours and materials
/// removed (aiProcess_RemoveComponent) before vertices are joined
/// (aiProcess_JoinIdenticalVertices), so vertices are joined by position; positions equal
/// across meshes are joined too.
///
/// Units: metres. aiProcess_GlobalScale, with assimp's global factor left at 1, applies only
/// the unit a file declares: FBX's UnitScaleFactor (centimetres per unit) scales by
/// UnitScaleFactor / 100, with a warning when that is not 1; COLLADA's `<unit meter>` is
/// applied by assimp's reader in any case; glTF is metres by its specification; formats without
/// a unit are read as metres. Axes are as the file has them (glTF Y-up, 3DS Z-up): no rotation.
#pragma once

#include "mesh/mesh_buffers.h"

#include <string>
#include <vector>

namespace kizamu::import {

/// Reads `path` with assimp into `out` (positions and indices; at least one triangle).
/// @param as        read the file as if its extension were this ("glb"); files it refers to
///                  are still looked for beside `path`. Empty: its own extension.
/// @param warnings  appended, one line each (without the path).
/// @return empty on success, else the one-line problem ("assimp cannot read it: ...", "the file
///         holds no triangles", ...). Assimp may crash or hang: run this in a child process.
/// Complexity: assimp's, then O(vertices + triangles) expected (a hash join).
std::string readWithAssimp(const std::string& path, const std::string& as, mesh::MeshBuffers& out,
                           std::vector<std::string>& warnings);

}  // namespace kizamu::import
