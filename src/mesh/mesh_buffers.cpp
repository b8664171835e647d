// SPDX-License-Identifier: Apache-2.0
/// @file mesh_buffers.cpp
/// @brief MeshBuffers validity check.
#include "mesh/mesh_buffers.h"

namespace kizamu::mesh {

bool MeshBuffers::valid() const {
    if (indices.size() % 3 != 0) return false;
    if (!normals.empty() && normals.size() != positions.size()) return false;
    if (!colours.empty() && colours.size() != positions.size()) return false;
    for (uint32_t i : indices)
        if (i >= positions.size()) return false;
    return true;
}

}  // namespace kizamu::mesh
