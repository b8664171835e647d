// SPDX-License-Identifier: Apache-2.0
/// @file mesh_export.h
/// @brief Writes MeshBuffers as OBJ, binary STL, binary PLY or glTF 2.0 binary (.glb).
///
/// Formats other tools read: normals are written where the format has them (OBJ `vn`, PLY
/// nx/ny/nz, glTF NORMAL; STL carries per-facet normals from the triangle), colours where it
/// has them (OBJ `v x y z r g b`, PLY red/green/blue, glTF COLOR_0). Files are replaced
/// atomically. Cold path; any thread.
#pragma once

#include "mesh/mesh_buffers.h"

#include <string>

namespace kizamu::mesh {

/// Glb is written only; Off is read only.
enum class MeshFormat { Obj, Stl, Ply, Glb, Off };

/// Format from the file extension (case-insensitive). @throw kizamu::FileError if unknown.
MeshFormat meshFormatOf(const std::string& path);

/// Writes `mesh` to `path` in the format its extension names.
/// @throw kizamu::FileError on an invalid mesh, an unknown extension or an I/O failure.
/// Complexity: O(vertices + triangles). Memory: one buffer the size of the file.
void exportMesh(const MeshBuffers& mesh, const std::string& path);

}  // namespace kizamu::mesh
