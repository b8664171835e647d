// SPDX-License-Identifier: Apache-2.0
/// @file mesh_source.h
/// @brief A triangle mesh as a signed DistanceSource: exact unsigned distance through a BVH,
/// sign from the fast generalised winding number (inside where it exceeds 1/2).
///
/// This is how imported meshes become ADFs (`generate` with this source). The winding number
/// makes the sign robust for real meshes with holes, duplicate faces or several parts; orienting
/// the closed parts first makes it independent of which way they face. For a
/// closed, consistently oriented mesh the winding number is an integer off the surface and
/// changes only across it, so inside one batch (one cell's points) a point whose distance ball
/// overlaps a signed neighbour's (d_i + d_j > |p_i - p_j|: no surface between them) takes that
/// neighbour's sign without a winding-number query. Thread-safe.
#pragma once

#include "adf/distance_source.h"
#include "adf/domain.h"
#include "mesh/triangle_bvh.h"

#include <memory>
#include <string>
#include <vector>

namespace kizamu::mesh {

/// The signed distance of `mesh` (negative inside), with its closed parts oriented by nesting
/// depth first (mesh_orientation.h; on a copy, `mesh` is not changed): a closed part is solid
/// whichever way it faces, a closed part inside it a cavity, one inside that solid again.
/// @param warnings  where one line saying what was reversed is appended, if anything was; may be
///                  null.
/// @throw std::invalid_argument if it has no triangles.
/// Complexity: O(T log T) to build, O(log T) per distance.
adf::SourcePtr makeMeshSource(const MeshBuffers& mesh, std::vector<std::string>* warnings = nullptr);

/// A cubic domain around `mesh` at `maxLevel`, with a margin of `marginCells` finest cells plus
/// 2 % of the size, so the accurate band stays off the domain's faces (at very low levels, where
/// the margin would exceed a quarter of the domain, the margin is capped there).
adf::Domain domainAround(const MeshBuffers& mesh, int maxLevel, double marginCells);

}  // namespace kizamu::mesh
