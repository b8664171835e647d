// SPDX-License-Identifier: Apache-2.0
/// @file mesh_colours.h
/// @brief Vertex colours from a snapshot's paint (adf/colour_layer.h), for meshes and points.
///
/// Each colour is the layer's trilinear blend at the point's position, so it depends only on
/// the position and the layer: incremental and full meshes, LOD meshes (looked up in the fine
/// snapshot's layer) and point clouds all agree. Complexity: O(points) lookups, O(1) each while
/// points stay in one tile slot (ColourAccessor), O(log) otherwise. Threading: fixed chunks of
/// points in parallel on `pool`, one accessor per chunk; the result does not depend on threads.
/// Memory: resizes `out` to the point count.
#pragma once

#include "adf/colour_layer.h"

#include <glm/gtc/type_precision.hpp>
#include <glm/vec3.hpp>

#include <span>
#include <vector>

namespace kizamu::util {
class ThreadPool;
}

namespace kizamu::mesh {

/// out[i] = the colour (sRGB) of `layer` at positionsWorld[i] (m).
void colourPoints(const adf::ColourLayer& layer, std::span<const glm::vec3> positionsWorld,
                  std::vector<glm::u8vec3>& out, util::ThreadPool* pool = nullptr);

}  // namespace kizamu::mesh
