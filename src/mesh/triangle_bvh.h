// SPDX-License-Identifier: Apache-2.0
/// @file triangle_bvh.h
/// @brief Bounding-volume hierarchy over a triangle mesh: exact closest point and the fast
/// generalised winding number (Barill et al. 2018, first-order far field).
///
/// Used to turn imported meshes (real, imperfect ones: holes, duplicate faces, several parts)
/// into distance sources: distance is exact (closest point on any triangle), the sign comes from
/// the winding number, which stays meaningful where the surface has gaps.
/// Immutable after construction; any number of threads may query one.
#pragma once

#include "mesh/mesh_buffers.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <vector>

namespace kizamu::mesh {

class TriangleBvh {
public:
    /// Builds over the triangles of `mesh` (copied). Complexity: O(T log T).
    explicit TriangleBvh(const MeshBuffers& mesh);

    struct Closest {
        double distanceSquared = 0.0;  ///< m^2
        glm::dvec3 point{0.0};         ///< closest point on the mesh, m
        uint32_t triangle = 0;
    };
    /// Exact closest point on the mesh to `p` (m): the smallest computed distance over all
    /// triangles, lowest index on ties. Triangle indices are the BVH's own order (not the
    /// mesh's). `hint` (such an index, e.g. the answer for a nearby point) only bounds the
    /// search, so the answer is the same bits whatever it is, which keeps generation
    /// deterministic. Complexity: O(log T) typical.
    Closest closest(const glm::dvec3& p, uint32_t hint = kNoHint) const;
    static constexpr uint32_t kNoHint = ~0u;

    /// Generalised winding number at `p`: about 1 inside a closed, outward-oriented surface, 0
    /// outside, in between near holes. Nodes farther than `beta` times their radius use their
    /// dipole instead of their triangles. Complexity: O(log T) typical.
    double windingNumber(const glm::dvec3& p, double beta = 2.0) const;
    /// The same summed over every triangle exactly (for tests). Complexity: O(T).
    double windingNumberExact(const glm::dvec3& p) const;

    std::size_t triangleCount() const { return mTriangles.size(); }
    /// Bounds of all vertices, m.
    glm::dvec3 boundsMin() const { return mNodes.empty() ? glm::dvec3(0.0) : mNodes[0].lo; }
    glm::dvec3 boundsMax() const { return mNodes.empty() ? glm::dvec3(0.0) : mNodes[0].hi; }

private:
    struct Triangle {
        glm::dvec3 a, b, c;
    };
    struct Node {
        glm::dvec3 lo{0.0}, hi{0.0};  ///< box
        glm::dvec3 centre{0.0};       ///< area-weighted centroid
        glm::dvec3 areaNormal{0.0};   ///< sum of area-weighted normals (the dipole)
        double radius = 0.0;        ///< largest distance from centre to a vertex below
        uint32_t first = 0, count = 0;  ///< leaf: triangle range; inner: count == 0
        uint32_t left = 0, right = 0;
    };
    uint32_t build(uint32_t first, uint32_t count);

    std::vector<Triangle> mTriangles;
    std::vector<Node> mNodes;
    double mTolerance = 0.0;  ///< rounding bound of closest-point distances, m
};

}  // namespace kizamu::mesh
