// SPDX-License-Identifier: Apache-2.0
/// @file mesh_import.h
/// @brief Reads triangle meshes from OBJ, STL (ASCII or binary), PLY (ASCII or binary, either
/// byte order) and OFF into MeshBuffers.
///
/// Polygons are fanned into triangles, STL's per-facet vertices are welded by exact position,
/// and vertex colours are kept where the file has them (OBJ `v x y z r g b`, PLY red/green/blue).
/// Normals are not read: the ADF recomputes them. Counts are checked against the bytes left
/// before anything is allocated, and indices must be whole and in range, so a damaged, empty,
/// enormous or hostile file gives a one-line FileError (with the line or element that is
/// wrong); the fuzz harness holds the readers to that. Cold path; any thread.
#pragma once

#include "mesh/mesh_buffers.h"
#include "mesh/mesh_export.h"

#include <string>
#include <string_view>

namespace kizamu::mesh {

/// Parses `bytes` as `format`; `name` prefixes error messages. @throw kizamu::FileError
MeshBuffers decodeMesh(std::string_view bytes, MeshFormat format, const std::string& name);

/// Reads `path` in the format its extension names. @throw kizamu::FileError
MeshBuffers importMesh(const std::string& path);

}  // namespace kizamu::mesh
