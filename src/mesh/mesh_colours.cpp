// SPDX-License-Identifier: Apache-2.0
/// @file mesh_colours.cpp
/// @brief colourPoints.
#include "mesh/mesh_colours.h"

#include "util/thread_pool.h"

#include <algorithm>

namespace kizamu::mesh {

void colourPoints(const adf::ColourLayer& layer, std::span<const glm::vec3> positionsWorld,
                  std::vector<glm::u8vec3>& out, util::ThreadPool* pool) {
    out.resize(positionsWorld.size());
    // Chunks of consecutive points: mesh vertices come ordered by tile, so an accessor's slot
    // cache stays warm within a chunk.
    constexpr std::size_t kChunk = 4096;
    util::parallelFor(pool, (positionsWorld.size() + kChunk - 1) / kChunk, [&](std::size_t c) {
        adf::ColourAccessor acc(layer);
        const std::size_t end = std::min(positionsWorld.size(), (c + 1) * kChunk);
        for (std::size_t i = c * kChunk; i < end; ++i) out[i] = acc.colourAt(positionsWorld[i]);
    });
}

}  // namespace kizamu::mesh
