// SPDX-License-Identifier: Apache-2.0
/// @file mesh_export_3mf.h
/// @brief The 3MF writer behind exportMesh (internal to kizamu_mesh: lib3mf stays in one file).
#pragma once

#include "mesh/mesh_buffers.h"
#include "mesh/mesh_export.h"

#include <glm/vec3.hpp>

#include <cstddef>
#include <span>
#include <string>
#include <vector>

namespace kizamu::mesh::detail {

/// The 3MF package (a zip: the model part, content types, relationships) of one mesh object
/// with one build item, its positions `pos` in `unit`, which the model declares.
/// @param path  names the file in error messages only
/// @throw kizamu::FileError with lib3mf's message when lib3mf fails.
/// Complexity: O(vertices + triangles). Memory: lib3mf's copy of the mesh, and the package.
void writeThreeMf(const MeshBuffers& m, std::span<const glm::vec3> pos, LengthUnit unit,
                  const std::string& path, std::vector<std::byte>& out);

/// The position a reader gets back from a 3MF for `p` as lib3mf writes it: each coordinate
/// multiplied by 10^6 in float, truncated toward zero and written with six decimals (what
/// lib3mf 1.8's mesh writer does; a test reads every coordinate of an export back to hold it
/// to that). Not the identity: untangling decides contacts on these.
glm::vec3 threeMfWritten(const glm::vec3& p);

}  // namespace kizamu::mesh::detail
