// SPDX-License-Identifier: Apache-2.0
/// @file canonical_mesh.h
/// @brief Test helper: a mesh in a canonical form, so two meshes that hold the same vertices
/// and triangles in other orders compare equal.
#pragma once

#include "mesh/mesh_buffers.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <vector>

namespace kizamu::test {

/// Vertices as the bits of (position, normal), sorted; triangles as rows of those ranks
/// rotated to start at the smallest (orientation kept), sorted.
struct CanonicalMesh {
    std::vector<std::array<uint32_t, 6>> vertices;
    std::vector<std::array<uint32_t, 3>> triangles;
    bool operator==(const CanonicalMesh&) const = default;
};

inline CanonicalMesh canonicalOf(const mesh::MeshBuffers& m) {
    CanonicalMesh c;
    const std::size_t n = m.positions.size();
    std::vector<std::array<uint32_t, 6>> bits(n);
    for (std::size_t i = 0; i < n; ++i) {
        std::memcpy(&bits[i][0], &m.positions[i], 12);
        std::memcpy(&bits[i][3], &m.normals[i], 12);
    }
    std::vector<uint32_t> order(n);
    for (uint32_t i = 0; i < n; ++i) order[i] = i;
    std::sort(order.begin(), order.end(),
              [&](uint32_t a, uint32_t b) { return bits[a] < bits[b]; });
    std::vector<uint32_t> rank(n);
    for (uint32_t i = 0; i < n; ++i) rank[order[i]] = i;
    for (uint32_t i : order) c.vertices.push_back(bits[i]);
    for (std::size_t t = 0; t + 2 < m.indices.size(); t += 3) {
        std::array<uint32_t, 3> r{rank[m.indices[t]], rank[m.indices[t + 1]],
                                  rank[m.indices[t + 2]]};
        std::rotate(r.begin(), std::min_element(r.begin(), r.end()), r.end());
        c.triangles.push_back(r);
    }
    std::sort(c.triangles.begin(), c.triangles.end());
    return c;
}

}  // namespace kizamu::test
