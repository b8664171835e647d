// SPDX-License-Identifier: Apache-2.0
/// @file tool_body.h
/// @brief The tool's own shape, drawn where a 3D hand holds it (a headset's controller): a unit
/// sphere, cube (half-size 1) or cylinder (radius 1, half-height 1, axis Z) as a mesh, which the
/// renderer scales by the tool's radius and draws as lines.
/// Pure; any thread.
#pragma once

#include "mesh/mesh_buffers.h"

#include <cstdint>

namespace kizamu::render {

enum class ToolBody : uint8_t { None, Sphere, Cube, Cylinder };

/// The unit body's triangles (empty for None). Complexity O(1) (a few hundred triangles).
mesh::MeshBuffers unitToolBody(ToolBody body);

}  // namespace kizamu::render
