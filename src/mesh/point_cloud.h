// SPDX-License-Identifier: Apache-2.0
/// @file point_cloud.h
/// @brief Surface points with normals for point rendering (Kizamu 6.1).
///
/// Points are shared out among the boundary cells in proportion to each cell's estimated
/// surface area (the cell's face area over the L1 norm of the unit gradient: the mean area of
/// a plane crossing the cell), placed uniformly at random in the cell and projected onto the
/// surface in one step along the trilinear gradient; the normal is the gradient there. Only the
/// cell's own corners are read (no lookups); a painted snapshot's points get their colours
/// from its colour layer (mesh_colours.h). Deterministic for a given seed and thread count
/// independent. Complexity: O(boundary cells + points). Threading: parallel on the pool.
/// Memory: the output, the boundary cells and one double per boundary cell.
#pragma once

#include "adf/adf.h"
#include "util/default_init_allocator.h"

#include <glm/gtc/type_precision.hpp>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace kizamu::util {
class ThreadPool;
}

namespace kizamu::mesh {

struct PointCloud {
    /// Filled by a parallel loop: no zero-fill first (util/default_init_allocator.h).
    using Points = std::vector<glm::vec3, util::DefaultInitAllocator<glm::vec3>>;
    Points positions;  ///< m, world
    Points normals;    ///< unit
    std::vector<glm::u8vec3> colours;  ///< sRGB from the snapshot's paint, or empty when unpainted
};

/// `count` points on the surface of `adf`.
PointCloud surfacePointCloud(const adf::Adf& adf, std::size_t count, uint64_t seed = 1,
                             util::ThreadPool* pool = nullptr);

}  // namespace kizamu::mesh
