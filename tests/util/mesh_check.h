// SPDX-License-Identifier: Apache-2.0
/// @file mesh_check.h
/// @brief Test helpers that share no code with the mesher: a closed/oriented/manifold checker,
/// the Euler characteristic, and a canonical form for comparing meshes regardless of order.
#pragma once

#include "mesh/mesh_buffers.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <map>
#include <tuple>
#include <vector>

namespace kizamu::test {

/// Every directed edge appears exactly once and its reverse exactly once (closed, consistently
/// oriented, edge-manifold), no triangle repeats a vertex, and the triangles around each vertex
/// form a single fan (vertex-manifold). Every vertex is used.
inline ::testing::AssertionResult closedOrientedManifold(const mesh::MeshBuffers& m) {
    const std::size_t nv = m.positions.size(), nt = m.indices.size() / 3;
    if (m.indices.size() % 3 != 0) return ::testing::AssertionFailure() << "index count not a multiple of 3";
    std::vector<std::pair<uint64_t, uint32_t>> directed;  // (from << 32 | to, triangle)
    directed.reserve(3 * nt);
    for (std::size_t t = 0; t < nt; ++t) {
        const uint32_t* v = &m.indices[3 * t];
        for (int i = 0; i < 3; ++i)
            if (v[i] >= nv) return ::testing::AssertionFailure() << "index out of range";
        if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2])
            return ::testing::AssertionFailure() << "triangle " << t << " repeats a vertex";
        for (int i = 0; i < 3; ++i) directed.emplace_back((uint64_t(v[i]) << 32) | v[(i + 1) % 3], uint32_t(t));
    }
    std::sort(directed.begin(), directed.end());
    for (std::size_t i = 0; i + 1 < directed.size(); ++i)
        if (directed[i].first == directed[i + 1].first)
            return ::testing::AssertionFailure() << "directed edge " << (directed[i].first >> 32) << "->"
                                                 << (directed[i].first & 0xffffffffu)
                                                 << " used twice (non-manifold or flipped)";
    for (const auto& [e, t] : directed) {
        const uint64_t rev = ((e & 0xffffffffu) << 32) | (e >> 32);
        if (!std::binary_search(directed.begin(), directed.end(), std::make_pair(rev, 0u),
                                [](const auto& a, const auto& b) { return a.first < b.first; }))
            return ::testing::AssertionFailure() << "edge " << (e >> 32) << "->" << (e & 0xffffffffu)
                                                 << " has no opposite (open or inconsistently oriented)";
    }
    // One fan per vertex: the link edges (b -> c of each triangle (v, b, c)) form one cycle.
    std::vector<std::vector<std::pair<uint32_t, uint32_t>>> link(nv);
    for (std::size_t t = 0; t < nt; ++t) {
        const uint32_t* v = &m.indices[3 * t];
        for (int i = 0; i < 3; ++i) link[v[i]].emplace_back(v[(i + 1) % 3], v[(i + 2) % 3]);
    }
    for (std::size_t v = 0; v < nv; ++v) {
        auto& l = link[v];
        if (l.empty()) return ::testing::AssertionFailure() << "vertex " << v << " is unused";
        std::sort(l.begin(), l.end());
        for (std::size_t i = 0; i + 1 < l.size(); ++i)
            if (l[i].first == l[i + 1].first)
                return ::testing::AssertionFailure() << "vertex " << v << " has a branching link";
        uint32_t at = l[0].first;
        std::size_t steps = 0;
        do {
            auto it = std::lower_bound(l.begin(), l.end(), std::make_pair(at, 0u));
            if (it == l.end() || it->first != at)
                return ::testing::AssertionFailure() << "vertex " << v << " has an open link";
            at = it->second;
            ++steps;
        } while (at != l[0].first && steps <= l.size());
        if (steps != l.size())
            return ::testing::AssertionFailure() << "vertex " << v << " has " << l.size()
                                                 << " triangles in more than one fan (non-manifold vertex)";
    }
    return ::testing::AssertionSuccess();
}

/// V - E + F of a closed mesh (E counted as undirected edges).
inline long eulerCharacteristic(const mesh::MeshBuffers& m) {
    std::vector<uint64_t> edges;
    for (std::size_t t = 0; t < m.indices.size() / 3; ++t)
        for (int i = 0; i < 3; ++i) {
            const uint64_t a = m.indices[3 * t + i], b = m.indices[3 * t + (i + 1) % 3];
            edges.push_back(std::min(a, b) << 32 | std::max(a, b));
        }
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    return long(m.positions.size()) - long(edges.size()) + long(m.indices.size() / 3);
}

/// Connected components of the triangle graph (through shared vertices).
inline std::size_t componentCount(const mesh::MeshBuffers& m) {
    std::vector<uint32_t> parent(m.positions.size());
    for (uint32_t i = 0; i < parent.size(); ++i) parent[i] = i;
    auto find = [&](uint32_t i) {
        while (parent[i] != i) i = parent[i] = parent[parent[i]];
        return i;
    };
    for (std::size_t t = 0; t < m.indices.size() / 3; ++t)
        for (int i = 1; i < 3; ++i) parent[find(m.indices[3 * t + i])] = find(m.indices[3 * t]);
    std::size_t n = 0;
    for (uint32_t i = 0; i < parent.size(); ++i) n += find(i) == i;
    return n;
}

/// Triangles as sorted tuples of (position, normal, colour) rotated to start at the smallest
/// vertex: equal for two meshes that differ only in vertex and triangle order.
using CanonicalVertex = std::array<float, 9>;
using CanonicalMesh = std::vector<std::array<CanonicalVertex, 3>>;
inline CanonicalMesh canonical(const mesh::MeshBuffers& m) {
    CanonicalMesh out;
    for (std::size_t t = 0; t < m.indices.size() / 3; ++t) {
        std::array<CanonicalVertex, 3> tri;
        for (int i = 0; i < 3; ++i) {
            const uint32_t v = m.indices[3 * t + i];
            const glm::vec3 n = m.normals.empty() ? glm::vec3(0.0f) : m.normals[v];
            const glm::vec3 c = m.colours.empty() ? glm::vec3(-1.0f) : glm::vec3(m.colours[v]);
            tri[i] = {m.positions[v].x, m.positions[v].y, m.positions[v].z, n.x, n.y, n.z, c.x, c.y, c.z};
        }
        const int s = int(std::min_element(tri.begin(), tri.end()) - tri.begin());
        std::rotate(tri.begin(), tri.begin() + s, tri.end());
        out.push_back(tri);
    }
    std::sort(out.begin(), out.end());
    return out;
}

}  // namespace kizamu::test
