// SPDX-License-Identifier: Apache-2.0
// The untangling pass: exact orientation signs where doubles round the wrong way, contacts and
// coincident vertices removed from meshes made to have them, clean meshes left alone, and the
// result independent of the numbering.
#include "mesh/mesh_untangle.h"

#include "adf/generate.h"
#include "mesh/exact_predicates.h"
#include "mesh/surface_nets.h"
#include "tests/util/mesh_check.h"
#include "util/thread_pool.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <tuple>

namespace kizamu::mesh {
namespace {

float nextUp(float x) { return std::nextafter(x, INFINITY); }

TEST(ExactPredicates, PointsOnALineOrPlaneGiveZeroAndOneUlpOffGivesTheSideOfALargeOffset) {
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<float> u(-100.0f, 100.0f);
    for (int i = 0; i < 2000; ++i) {
        // y = 2x and z = 2x hold exactly in floats: these points lie exactly on the line / plane.
        const float a = u(rng), b = u(rng), c = u(rng);
        const glm::dvec2 p(a, 2.0f * a), q(b, 2.0f * b), r(c, 2.0f * c);
        ASSERT_EQ(exact::orient2d(p, q, r), 0) << i;
        const glm::dvec2 rUp(c, nextUp(2.0f * c)), rFar(c, 2.0f * c + 1000.0f);
        if (a != b) {
            ASSERT_EQ(exact::orient2d(p, q, rUp), exact::orient2d(p, q, rFar)) << i;
        }

        const float y0 = u(rng), y1 = u(rng), y2 = u(rng), d = u(rng), dy = u(rng);
        const glm::dvec3 A(a, y0, 2.0f * a), B(b, y1, 2.0f * b), C(c, y2, 2.0f * c), D(d, dy, 2.0f * d);
        ASSERT_EQ(exact::orient3d(A, B, C, D), 0) << i;
        const int far = exact::orient3d(A, B, C, glm::dvec3(d, dy, 2.0f * d + 1000.0f));
        if (far != 0) {
            ASSERT_EQ(exact::orient3d(A, B, C, glm::dvec3(d, dy, nextUp(2.0f * d))), far) << i;
        }
    }
}

TEST(ExactPredicates, TinyAndHugeCoordinatesTogetherAreExact) {
    // Differences that doubles cannot hold: 1 + 2^-60 - 1 is 2^-60, not 0.
    const double tiny = std::ldexp(1.0, -60);
    EXPECT_EQ(exact::orient2d({0.0, 0.0}, {1.0, 0.0}, {1.0, tiny}), 1);
    EXPECT_EQ(exact::orient2d({0.0, 0.0}, {1.0, 0.0}, {1.0, -tiny}), -1);
    EXPECT_EQ(exact::orient3d({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1e30, 1e-30, -tiny}), 1);
    EXPECT_EQ(exact::orient3d({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1e30, 1e-30, 0.0}), 0);
}

/// The SurfaceNets mesh of a sphere (closed, manifold, free of contacts).
MeshBuffers sphereMesh(double radius = 0.3) {
    adf::Domain d;
    d.maxLevel = 6;
    d.tileSpanLevels = 3;
    return meshAdf(adf::generate(*adf::makeTranslated(adf::makeSphere(radius), glm::dvec3(0.5)), d, {}), nullptr);
}

/// Vertex `v`'s neighbours in `m`.
std::vector<uint32_t> neighbours(const MeshBuffers& m, uint32_t v) {
    std::vector<uint32_t> out;
    for (std::size_t t = 0; t < m.triangleCount(); ++t)
        for (int i = 0; i < 3; ++i)
            if (m.indices[3 * t + i] == v) {
                out.push_back(m.indices[3 * t + (i + 1) % 3]);
                out.push_back(m.indices[3 * t + (i + 2) % 3]);
            }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

TEST(Untangle, LeavesAMeshWithoutContactsAsItIs) {
    MeshBuffers m = sphereMesh();
    const MeshBuffers before = m;
    const UntangleReport r = untangle(m);
    EXPECT_EQ(r.contacts, 0u);
    EXPECT_EQ(r.coincidentVertices, 0u);
    EXPECT_EQ(r.verticesMoved, 0u);
    EXPECT_TRUE(std::equal(m.positions.begin(), m.positions.end(), before.positions.begin()));
}

TEST(Untangle, UnfoldsAVertexMirroredAcrossANeighbourAndKeepsTheTopology) {
    MeshBuffers m = sphereMesh();
    // Mirror a vertex across one of its neighbours: its fan folds over that neighbour's.
    const uint32_t v = 17;
    const std::vector<uint32_t> ring = neighbours(m, v);
    m.positions[v] = m.positions[ring[0]] + (m.positions[ring[0]] - m.positions[v]);
    const std::vector<uint32_t> indices(m.indices.begin(), m.indices.end());
    const UntangleReport r = untangle(m);
    EXPECT_GT(r.contacts, 0u);
    EXPECT_EQ(r.remaining, 0u);
    EXPECT_GT(r.verticesMoved, 0u);
    EXPECT_LT(r.verticesMoved, 60u) << "the repair stays local";
    EXPECT_TRUE(std::equal(indices.begin(), indices.end(), m.indices.begin()));
    EXPECT_TRUE(test::closedOrientedManifold(m));
    EXPECT_EQ(untangle(m).contacts, 0u) << "a second pass finds nothing";
}

TEST(Untangle, SeparatesVerticesAtOnePosition) {
    // Two spheres touching at one point: a vertex of each moved onto the same position.
    MeshBuffers a = sphereMesh(0.2), b = sphereMesh(0.2);
    const glm::vec3 shift(0.4f + 1e-3f, 0.0f, 0.0f);
    MeshBuffers m = a;
    const uint32_t offset = uint32_t(a.positions.size());
    for (glm::vec3 p : b.positions) m.positions.push_back(p + shift);
    for (glm::vec3 n : b.normals) m.normals.push_back(n);
    for (uint32_t i : b.indices) m.indices.push_back(i + offset);
    // The rightmost vertex of the first and the leftmost of the second meet half-way.
    uint32_t right = 0, left = offset;
    for (uint32_t i = 0; i < offset; ++i)
        if (m.positions[i].x > m.positions[right].x) right = i;
    for (uint32_t i = offset; i < m.positions.size(); ++i)
        if (m.positions[i].x < m.positions[left].x) left = i;
    const glm::vec3 meet = 0.5f * (m.positions[right] + m.positions[left]);
    m.positions[right] = m.positions[left] = meet;
    const UntangleReport r = untangle(m);
    EXPECT_EQ(r.coincidentVertices, 2u);
    EXPECT_EQ(r.remaining, 0u);
    EXPECT_NE(m.positions[right], m.positions[left]);
    EXPECT_TRUE(test::closedOrientedManifold(m));
}

TEST(Untangle, TheResultDependsNeitherOnTheNumberingNorOnThreads) {
    MeshBuffers m = sphereMesh();
    const std::vector<uint32_t> ring = neighbours(m, 40);
    m.positions[40] = m.positions[ring[0]] + 0.5f * (m.positions[ring[0]] - m.positions[40]);
    // The same mesh with vertices and triangles in another order.
    std::vector<uint32_t> perm(m.positions.size());
    std::iota(perm.begin(), perm.end(), 0u);
    std::shuffle(perm.begin(), perm.end(), std::mt19937(5));
    MeshBuffers p = m;
    for (uint32_t i = 0; i < perm.size(); ++i) p.positions[perm[i]] = m.positions[i];
    for (std::size_t i = 0; i < m.indices.size(); ++i) p.indices[i] = perm[m.indices[i]];
    std::vector<std::size_t> tris(m.triangleCount());
    std::iota(tris.begin(), tris.end(), std::size_t(0));
    std::shuffle(tris.begin(), tris.end(), std::mt19937(6));
    MeshBuffers q = p;
    for (std::size_t t = 0; t < tris.size(); ++t)
        for (int i = 0; i < 3; ++i) q.indices[3 * t + i] = p.indices[3 * tris[t] + (i + 1) % 3];
    MeshBuffers onPool = m;
    util::ThreadPool pool(2);
    const UntangleReport rm = untangle(m), rq = untangle(q), rp = untangle(onPool, &pool);
    EXPECT_GT(rm.contacts, 0u);
    EXPECT_EQ(rm.remaining, 0u);
    EXPECT_EQ(rm.contacts, rq.contacts);
    EXPECT_EQ(rm.verticesMoved, rq.verticesMoved);
    for (uint32_t i = 0; i < perm.size(); ++i) ASSERT_EQ(m.positions[i], q.positions[perm[i]]) << i;
    EXPECT_EQ(rp.contacts, rm.contacts);
    EXPECT_TRUE(std::equal(m.positions.begin(), m.positions.end(), onPool.positions.begin())) << "the same on a pool";
}

}  // namespace
}  // namespace kizamu::mesh
