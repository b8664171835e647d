// SPDX-License-Identifier: Apache-2.0
/// @file uv_sphere.h
/// @brief Test helper: a closed UV sphere (or ellipsoid), counter-clockwise from outside, with
/// the unit sphere's directions as normals.
#pragma once

#include "mesh/mesh_buffers.h"

#include <glm/vec3.hpp>

#include <cmath>
#include <cstdint>

namespace kizamu::test {

/// `rings` rings of latitude (poles included as single vertices) by `segments` of longitude,
/// scaled by `radii` and moved to `centre`.
inline mesh::MeshBuffers uvEllipsoid(const glm::vec3& centre, const glm::vec3& radii, int rings, int segments) {
    mesh::MeshBuffers m;
    auto add = [&](const glm::vec3& n) {
        m.positions.push_back(n * radii + centre);
        m.normals.push_back(n);
    };
    add({0, 0, 1});
    for (int r = 1; r < rings; ++r)
        for (int s = 0; s < segments; ++s) {
            const float th = float(M_PI) * float(r) / float(rings), ph = 2.0f * float(M_PI) * float(s) / float(segments);
            add({std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th)});
        }
    add({0, 0, -1});
    const auto ring = [&](int r, int s) { return uint32_t(1 + (r - 1) * segments + (s % segments)); };
    const auto bottom = uint32_t(m.positions.size() - 1);
    for (int s = 0; s < segments; ++s) {
        m.indices.insert(m.indices.end(), {0u, ring(1, s), ring(1, s + 1)});
        for (int r = 1; r + 1 < rings; ++r) {
            m.indices.insert(m.indices.end(), {ring(r, s), ring(r + 1, s), ring(r + 1, s + 1)});
            m.indices.insert(m.indices.end(), {ring(r, s), ring(r + 1, s + 1), ring(r, s + 1)});
        }
        m.indices.insert(m.indices.end(), {ring(rings - 1, s), bottom, ring(rings - 1, s + 1)});
    }
    return m;
}

}  // namespace kizamu::test
