// SPDX-License-Identifier: Apache-2.0
/// @file mesh_buffers.h
/// @brief A triangle mesh as flat arrays: what the mesher produces and exporters and the
/// renderer consume (the renderer never sees the octree).
///
/// Positions in metres, world frame. Triangles are counter-clockwise seen from outside the
/// material. Plain value type; one owner, no internal synchronisation.
#pragma once

#include "util/default_init_allocator.h"

#include <glm/gtc/type_precision.hpp>
#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace kizamu::mesh {

struct MeshBuffers {
    /// Sized first, then filled by parallel loops: no zero-fill (util/default_init_allocator.h).
    template <class T>
    using Buffer = std::vector<T, util::DefaultInitAllocator<T>>;
    Buffer<glm::vec3> positions;       ///< m
    Buffer<glm::vec3> normals;         ///< unit, one per vertex, or empty
    std::vector<glm::u8vec3> colours;  ///< sRGB, one per vertex, or empty
    Buffer<uint32_t> indices;          ///< 3 per triangle

    std::size_t vertexCount() const { return positions.size(); }
    std::size_t triangleCount() const { return indices.size() / 3; }
    /// Sizes agree and every index is in range.
    bool valid() const;
};

}  // namespace kizamu::mesh
