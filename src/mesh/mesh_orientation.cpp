// SPDX-License-Identifier: Apache-2.0
/// @file mesh_orientation.cpp
/// @brief Parts by shared edges (union-find over triangles), closedness, signed volumes, and
/// nesting depth through a box tree of the closed parts and a BVH per containing part.
#include "mesh/mesh_orientation.h"

#include "mesh/box_tree.h"
#include "mesh/triangle_bvh.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <numeric>
#include <tuple>
#include <utility>
#include <vector>

namespace kizamu::mesh {

namespace {

constexpr double kInside = 0.75;   ///< |winding number| above: inside a closed part
constexpr double kOutside = 0.25;  ///< below: outside (between: on its surface)
/// Relative to the cube of a part's box size: below, a part has no volume to orient by.
constexpr double kNoVolume = 1e-9;

/// One id per vertex: the lowest index among the vertices at exactly its position (-0 == +0).
std::vector<uint32_t> weldByPosition(const MeshBuffers::Buffer<glm::vec3>& positions) {
    struct Key {
        uint32_t x, y, z, index;
    };
    auto bits = [](float f) { return f == 0.0f ? 0u : std::bit_cast<uint32_t>(f); };
    std::vector<Key> keys(positions.size());
    for (std::size_t i = 0; i < positions.size(); ++i)
        keys[i] = {bits(positions[i].x), bits(positions[i].y), bits(positions[i].z), uint32_t(i)};
    std::sort(keys.begin(), keys.end(), [](const Key& a, const Key& b) {
        return std::tie(a.x, a.y, a.z, a.index) < std::tie(b.x, b.y, b.z, b.index);
    });
    std::vector<uint32_t> id(positions.size());
    for (std::size_t i = 0; i < keys.size(); ++i) {
        const bool same = i > 0 && keys[i].x == keys[i - 1].x && keys[i].y == keys[i - 1].y &&
                          keys[i].z == keys[i - 1].z;
        id[keys[i].index] = same ? id[keys[i - 1].index] : keys[i].index;
    }
    return id;
}

/// Disjoint sets of triangles; path halving, the lower root wins.
class UnionFind {
public:
    explicit UnionFind(std::size_t n) : mParent(n) {
        std::iota(mParent.begin(), mParent.end(), 0u);
    }
    uint32_t find(uint32_t x) {
        while (mParent[x] != x) x = mParent[x] = mParent[mParent[x]];
        return x;
    }
    void unite(uint32_t a, uint32_t b) {
        a = find(a);
        b = find(b);
        if (a != b) mParent[std::max(a, b)] = std::min(a, b);
    }

private:
    std::vector<uint32_t> mParent;
};


/// The parts of a mesh: triangles by part, and what orientation needs of each.
struct Parts {
    std::vector<uint32_t> corner;   ///< per triangle corner: its vertex welded by position
    std::vector<uint8_t> touching;  ///< per welded vertex: used by more than one part
    std::vector<uint32_t> start;    ///< part p's triangles are triangles[start[p], start[p + 1])
    std::vector<uint32_t> triangles;
    std::vector<uint8_t> closed;  ///< closed and consistently oriented
    std::vector<double> volume;   ///< signed, m^3
    std::vector<Box3> box;
    std::size_t count() const { return start.size() - 1; }
};

Parts findParts(const MeshBuffers& mesh) {
    const auto triangleCount = uint32_t(mesh.triangleCount());
    Parts parts;
    std::vector<uint32_t>& corner = parts.corner;
    {
        const std::vector<uint32_t> weld = weldByPosition(mesh.positions);
        corner.resize(3 * std::size_t(triangleCount));
        for (std::size_t h = 0; h < corner.size(); ++h) corner[h] = weld[mesh.indices[h]];
    }
    auto target = [&](uint32_t h) { return corner[h - h % 3 + (h % 3 + 1) % 3]; };

    // Half-edges by their first vertex, so each edge finds its twins among a few.
    std::vector<uint32_t> first(mesh.positions.size() + 1, 0);
    for (uint32_t v : corner) ++first[v + 1];
    std::partial_sum(first.begin(), first.end(), first.begin());
    std::vector<uint32_t> outgoing(corner.size());
    {
        std::vector<uint32_t> cursor(first.begin(), first.end() - 1);
        for (uint32_t h = 0; h < corner.size(); ++h) outgoing[cursor[corner[h]]++] = h;
    }

    // Triangles sharing an edge (in either direction) are one part; an edge used other than
    // once each way, or with equal ends, makes its part not closed.
    UnionFind sets(triangleCount);
    std::vector<uint8_t> flawed(triangleCount, 0);
    for (uint32_t h = 0; h < corner.size(); ++h) {
        const uint32_t u = corner[h], v = target(h), t = h / 3;
        if (u == v) {
            flawed[t] = 1;
            continue;
        }
        int same = 0, reverse = 0;
        for (uint32_t i = first[u]; i < first[u + 1]; ++i)
            if (target(outgoing[i]) == v) {
                ++same;
                sets.unite(t, outgoing[i] / 3);
            }
        for (uint32_t i = first[v]; i < first[v + 1]; ++i)
            if (target(outgoing[i]) == u) {
                ++reverse;
                sets.unite(t, outgoing[i] / 3);
            }
        if (same != 1 || reverse != 1) flawed[t] = 1;
    }

    // Number the parts in order of their first triangle; gather their triangles and measures.
    std::vector<uint32_t> part(triangleCount);
    std::vector<uint32_t> rootPart(triangleCount, ~0u);
    parts.start.push_back(0);
    for (uint32_t t = 0; t < triangleCount; ++t) {
        uint32_t& p = rootPart[sets.find(t)];
        if (p == ~0u) {
            p = uint32_t(parts.start.size() - 1);
            parts.start.push_back(0);
        }
        part[t] = p;
        ++parts.start[p + 1];
    }
    const std::size_t n = parts.start.size() - 1;
    std::partial_sum(parts.start.begin(), parts.start.end(), parts.start.begin());
    parts.triangles.resize(triangleCount);
    parts.closed.assign(n, 1);
    parts.volume.assign(n, 0.0);
    parts.box.assign(n, Box3{});
    std::vector<uint32_t> cursor(parts.start.begin(), parts.start.end() - 1);
    std::vector<uint32_t> owner(mesh.positions.size(), ~0u);
    parts.touching.assign(mesh.positions.size(), 0);
    std::vector<glm::dvec3> origin(
        n);  // a corner of the part's first triangle: volumes relative to it keep precision
    for (uint32_t t = 0; t < triangleCount; ++t) {
        const uint32_t p = part[t];
        if (cursor[p] == parts.start[p])
            origin[p] = glm::dvec3(mesh.positions[mesh.indices[3 * std::size_t(t)]]);
        parts.triangles[cursor[p]++] = t;
        if (flawed[t]) parts.closed[p] = 0;
        for (std::size_t h = 3 * std::size_t(t); h < 3 * std::size_t(t) + 3; ++h) {
            if (owner[corner[h]] == ~0u) owner[corner[h]] = p;
            if (owner[corner[h]] != p) parts.touching[corner[h]] = 1;
        }
        const glm::dvec3 a =
            glm::dvec3(mesh.positions[mesh.indices[3 * std::size_t(t)]]) - origin[p];
        const glm::dvec3 b =
            glm::dvec3(mesh.positions[mesh.indices[3 * std::size_t(t) + 1]]) - origin[p];
        const glm::dvec3 c =
            glm::dvec3(mesh.positions[mesh.indices[3 * std::size_t(t) + 2]]) - origin[p];
        parts.volume[p] += glm::dot(a, glm::cross(b, c)) / 6.0;
        for (const glm::dvec3& q : {a, b, c}) parts.box[p].add(q + origin[p]);
    }
    return parts;
}

/// The triangles of part `p` as a mesh of their own (corners not shared), for its BVH.
MeshBuffers partMesh(const MeshBuffers& mesh, const Parts& parts, uint32_t p) {
    MeshBuffers m;
    m.positions.reserve(3 * std::size_t(parts.start[p + 1] - parts.start[p]));
    m.indices.reserve(m.positions.capacity());
    for (uint32_t i = parts.start[p]; i < parts.start[p + 1]; ++i)
        for (int k = 0; k < 3; ++k) {
            m.indices.push_back(uint32_t(m.positions.size()));
            m.positions.push_back(
                mesh.positions[mesh.indices[3 * std::size_t(parts.triangles[i]) + k]]);
        }
    return m;
}

/// How many other closed parts hold each closed part (0 for parts not closed).
std::vector<uint32_t> nestingDepths(const MeshBuffers& mesh, const Parts& parts,
                                    const std::vector<uint32_t>& closed) {
    std::vector<uint32_t> depth(parts.count(), 0);
    if (closed.size() < 2) return depth;
    const BoxTree tree(parts.box, closed);
    std::vector<std::unique_ptr<TriangleBvh>> bvh(parts.count());
    std::vector<uint32_t> probed(mesh.positions.size(),
                                 0);  // the last test that probed a welded vertex
    uint32_t test = 0;
    // `inner` is inside `outer`: none of its vertices outside, at least one inside (the others on
    // its surface). Parts that cross each other have vertices on both sides: neither holds. Every
    // vertex is probed, so only a crossing between vertices (through edges) goes unseen. A vertex
    // another part also uses is not probed: on that part, its winding number is undefined.
    auto inside = [&](uint32_t inner, uint32_t outer) {
        if (!bvh[outer]) bvh[outer] = std::make_unique<TriangleBvh>(partMesh(mesh, parts, outer));
        ++test;
        bool any = false;
        for (uint32_t i = parts.start[inner]; i < parts.start[inner + 1]; ++i) {
            const std::size_t t = parts.triangles[i];
            for (std::size_t h = 3 * t; h < 3 * t + 3; ++h) {
                const uint32_t v = parts.corner[h];
                if (parts.touching[v] || std::exchange(probed[v], test) == test) continue;
                const double w = std::abs(
                    bvh[outer]->windingNumber(glm::dvec3(mesh.positions[mesh.indices[h]])));
                if (w < kOutside) return false;
                any = any || w > kInside;
            }
        }
        return any;
    };
    for (uint32_t p : closed)
        tree.visit([&](const Box3& b) { return b.holds(parts.box[p]); }, [&](uint32_t q) {
            if (q != p && inside(p, q)) ++depth[p];
        });
    return depth;
}

}  // namespace

OrientationReport orientClosedComponents(MeshBuffers& mesh) {
    OrientationReport report;
    if (mesh.triangleCount() == 0) return report;
    const Parts parts = findParts(mesh);
    std::vector<uint32_t> closed;
    for (uint32_t p = 0; p < parts.count(); ++p)
        if (parts.closed[p]) closed.push_back(p);
    report.components = parts.count();
    report.closed = closed.size();
    const std::vector<uint32_t> depth = nestingDepths(mesh, parts, closed);
    for (uint32_t p : closed) {
        report.nested += depth[p] > 0;
        const glm::dvec3 e = parts.box[p].hi - parts.box[p].lo;
        const double size = std::max({e.x, e.y, e.z});
        const double v = parts.volume[p];
        if (!(std::abs(v) > kNoVolume * size * size * size))
            continue;  // no volume (or not a number)
        if ((v > 0.0) == (depth[p] % 2 == 0)) continue;
        for (uint32_t i = parts.start[p]; i < parts.start[p + 1]; ++i) {
            const std::size_t t = parts.triangles[i];
            std::swap(mesh.indices[3 * t + 1], mesh.indices[3 * t + 2]);
        }
        ++report.flipped;
        report.flippedTriangles += parts.start[p + 1] - parts.start[p];
    }
    return report;
}

std::string describeOrientation(const OrientationReport& r) {
    if (r.flipped == 0) return {};
    std::string s = "reversed " + std::to_string(r.flipped) + " of " + std::to_string(r.closed) +
                    " closed part" + (r.closed == 1 ? "" : "s") + " (" +
                    std::to_string(r.flippedTriangles) + " triangles";
    if (r.nested > 0) s += "; " + std::to_string(r.nested) + " nested in another";
    s += ") so that each faces out of its material: outward at even nesting depth, into a cavity "
         "at odd";
    return s;
}

}  // namespace kizamu::mesh
