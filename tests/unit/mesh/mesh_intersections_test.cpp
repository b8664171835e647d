// SPDX-License-Identifier: Apache-2.0
// The exact mesh checker (tests/support/mesh_intersections.h) on hand-made meshes: embedded
// closed meshes pass, and each kind of defect is found as that kind and no other.
#include "tests/support/mesh_intersections.h"

#include <gtest/gtest.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <initializer_list>

namespace kizamu {
namespace {

using mesh::MeshBuffers;
using test::findMeshIntersections;
using test::MeshDefect;
using test::MeshIntersections;

MeshBuffers meshOf(std::initializer_list<glm::vec3> positions,
                   std::initializer_list<uint32_t> indices) {
    MeshBuffers m;
    m.positions.assign(positions.begin(), positions.end());
    m.indices.assign(indices.begin(), indices.end());
    return m;
}

MeshBuffers tetrahedron() {
    return meshOf({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}},
                  {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3});
}

MeshBuffers cube(glm::vec3 lo, float size) {
    MeshBuffers m;
    for (int i = 0; i < 8; ++i)
        m.positions.push_back(lo + size * glm::vec3(i & 1, (i >> 1) & 1, (i >> 2) & 1));
    // Two counter-clockwise (seen from outside) triangles per face.
    for (uint32_t i : {0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4,
                       2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5})
        m.indices.push_back(i);
    return m;
}

MeshBuffers joined(const MeshBuffers& a, const MeshBuffers& b) {
    MeshBuffers m = a;
    const uint32_t n = uint32_t(a.positions.size());
    m.positions.insert(m.positions.end(), b.positions.begin(), b.positions.end());
    for (uint32_t i : b.indices) m.indices.push_back(n + i);
    return m;
}

/// Exactly one kind of defect, `count` times.
::testing::AssertionResult onlyDefect(const MeshBuffers& m, MeshDefect kind,
                                      std::size_t count = 1) {
    const MeshIntersections r = findMeshIntersections(m);
    if (r.count(kind) == count && r.violations() == count) return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure()
           << "expected " << count << " of kind " << int(kind) << ", got " << r.describe(m);
}

TEST(MeshIntersections, ClosedEmbeddedMeshesPass) {
    const MeshBuffers octahedron =
        meshOf({{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}},
               {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5});
    const MeshBuffers twoCubes = joined(cube({0, 0, 0}, 1.0f), cube({1.5f, 0.25f, -0.5f}, 0.5f));
    for (const MeshBuffers& m : {tetrahedron(), octahedron, cube({0, 0, 0}, 1.0f), twoCubes}) {
        EXPECT_TRUE(test::closedOrientedManifold(m));
        EXPECT_TRUE(test::noSelfIntersections(m));
        EXPECT_TRUE(test::weldsToClosedManifold(m));
        EXPECT_GT(findMeshIntersections(m).candidatePairs, 0u);
    }
}

TEST(MeshIntersections, OpenMeshesThatMeetOnlyAlongWhatTheyShareAreClean) {
    // A flat square in two triangles: coplanar across their edge, on opposite sides of it.
    EXPECT_TRUE(test::noSelfIntersections(
        meshOf({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, {0, 1, 2, 0, 2, 3})));
    // Two triangles in one plane on one vertex, back to back.
    EXPECT_TRUE(test::noSelfIntersections(
        meshOf({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {0, -1, 0}}, {0, 1, 2, 0, 3, 4})));
    // Two triangles on one vertex, the second bent out of the plane.
    EXPECT_TRUE(test::noSelfIntersections(
        meshOf({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {0, -1, 1}}, {0, 1, 2, 0, 3, 4})));
    // Boxes that touch but triangles that do not: candidates, no violation.
    const MeshBuffers m =
        meshOf({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {1, 1, 1}, {0.6f, 0.6f, 0}},
               {0, 1, 2, 3, 4, 5});
    const MeshIntersections r = findMeshIntersections(m);
    EXPECT_EQ(r.candidatePairs, 1u);
    EXPECT_TRUE(r.clean()) << r.describe(m);
}

TEST(MeshIntersections, CoincidentVerticesAreFoundAndWeldedAway) {
    // The tetrahedron with its apex twice: one triangle uses the copy.
    MeshBuffers m = tetrahedron();
    m.positions.push_back(m.positions[3]);
    m.indices[5] = 4;
    EXPECT_FALSE(test::closedOrientedManifold(m));
    EXPECT_TRUE(onlyDefect(m, MeshDefect::CoincidentVertices));
    const MeshIntersections r = findMeshIntersections(m);
    ASSERT_EQ(r.examples.size(), 1u);
    EXPECT_EQ(r.examples[0].first, 3u);
    EXPECT_EQ(r.examples[0].second, 4u);
    EXPECT_TRUE(test::weldsToClosedManifold(m));
    EXPECT_EQ(test::weldByPosition(m).positions.size(), 4u);
    EXPECT_EQ(test::weldByPosition(tetrahedron()).indices, tetrahedron().indices);
    // -0 and +0 are one position.
    MeshBuffers signedZero = tetrahedron();
    signedZero.positions.push_back({-0.0f, 0.0f, -0.0f});
    signedZero.indices[0] = 4;
    EXPECT_TRUE(onlyDefect(signedZero, MeshDefect::CoincidentVertices));
    // Welding can break manifoldness: two tetrahedra on one apex position.
    MeshBuffers pinched = joined(tetrahedron(), meshOf({{0, 0, 1}, {1, 1, 2}, {0, 1, 2}, {1, 0, 2}},
                                                       {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3}));
    EXPECT_TRUE(test::closedOrientedManifold(pinched));
    EXPECT_FALSE(test::weldsToClosedManifold(pinched));
}

TEST(MeshIntersections, FoldsAcrossASharedEdgeAreFound) {
    // Apex of the second triangle inside the first.
    EXPECT_TRUE(
        onlyDefect(meshOf({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.2f, 0.2f, 0}}, {0, 1, 2, 1, 0, 3}),
                   MeshDefect::FoldedEdge));
    // Apex beyond the first triangle, still on its side of the edge: they overlap in part.
    EXPECT_TRUE(onlyDefect(meshOf({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {2, 2, 0}}, {0, 1, 2, 1, 0, 3}),
                           MeshDefect::FoldedEdge));
    // A tetrahedron flattened: its apex moved into the base plane, inside the base.
    MeshBuffers flat = tetrahedron();
    flat.positions[3] = {0.25f, 0.25f, 0.0f};
    const MeshIntersections r = findMeshIntersections(flat);
    EXPECT_EQ(r.foldedEdges, 3u) << r.describe(flat);
}

TEST(MeshIntersections, AVertexOnAnotherTrianglesInteriorIsFound) {
    EXPECT_TRUE(onlyDefect(
        meshOf({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.25f, 0.25f, 0}, {0.25f, 0.25f, 1}, {1, 1, 1}},
               {0, 1, 2, 3, 4, 5}),
        MeshDefect::Intersecting));
    // On an edge of the other triangle.
    EXPECT_TRUE(onlyDefect(
        meshOf({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.5f, 0, 0}, {0.5f, -1, 1}, {0.5f, -1, -1}},
               {0, 1, 2, 3, 4, 5}),
        MeshDefect::Intersecting));
}

TEST(MeshIntersections, TrianglesOnOneVertexThatMeetElsewhereAreFound) {
    // Crossing: the second triangle's plane cuts through the first along a segment from the vertex.
    EXPECT_TRUE(onlyDefect(
        meshOf({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 1}, {1, 1, -1}}, {0, 1, 2, 0, 3, 4}),
        MeshDefect::MeetAtSharedVertex));
    // Coplanar, the second inside the first.
    EXPECT_TRUE(
        onlyDefect(meshOf({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.2f, 0.1f, 0}, {0.1f, 0.2f, 0}},
                          {0, 1, 2, 0, 3, 4}),
                   MeshDefect::MeetAtSharedVertex));
    // Coplanar, along a common ray from the vertex but on either side of it: they share a segment.
    EXPECT_TRUE(onlyDefect(
        meshOf({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {2, 0, 0}, {1, -1, 0}}, {0, 1, 2, 0, 4, 3}),
        MeshDefect::MeetAtSharedVertex));
}

TEST(MeshIntersections, PiercingTrianglesAreFound) {
    EXPECT_TRUE(onlyDefect(
        meshOf(
            {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.2f, 0.2f, -1}, {0.3f, 0.2f, 1}, {0.2f, 0.3f, 1}},
            {0, 1, 2, 3, 4, 5}),
        MeshDefect::Intersecting));
    // Two cubes that overlap: each has edges through the other's faces.
    const MeshBuffers m = joined(cube({0, 0, 0}, 1.0f), cube({0.5f, 0.25f, 0.25f}, 1.0f));
    const MeshIntersections r = findMeshIntersections(m);
    EXPECT_GT(r.intersecting, 0u);
    EXPECT_EQ(r.violations(), r.intersecting) << r.describe(m);
    EXPECT_TRUE(test::weldsToClosedManifold(m));  // the manifold check alone cannot see this
}

TEST(MeshIntersections, DegenerateTrianglesAreFoundAndLeftOutOfThePairs) {
    EXPECT_TRUE(onlyDefect(meshOf({{0, 0, 0}, {1, 1, 1}, {2, 2, 2}}, {0, 1, 2}),
                           MeshDefect::DegenerateTriangle));
    EXPECT_TRUE(
        onlyDefect(meshOf({{0, 0, 0}, {1, 0, 0}}, {0, 1, 1}), MeshDefect::DegenerateTriangle));
    // Two of its vertices at one position: a coincident group and a degenerate triangle.
    const MeshBuffers m = meshOf({{0, 0, 0}, {1, 0, 0}, {1, 0, 0}}, {0, 1, 2});
    const MeshIntersections r = findMeshIntersections(m);
    EXPECT_EQ(r.coincidentVertexGroups, 1u);
    EXPECT_EQ(r.degenerateTriangles, 1u);
    EXPECT_EQ(r.violations(), 2u);
    // Non-finite positions are degenerate, not an error.
    EXPECT_TRUE(onlyDefect(meshOf({{0, 0, 0}, {1, 0, 0}, {0, NAN, 0}}, {0, 1, 2}),
                           MeshDefect::DegenerateTriangle));
}

TEST(MeshIntersections, DuplicateTrianglesAreFoundInEitherOrientation) {
    MeshBuffers m = tetrahedron();
    for (uint32_t i : {0, 2, 1}) m.indices.push_back(i);
    EXPECT_TRUE(onlyDefect(m, MeshDefect::DuplicateTriangle));
    m = tetrahedron();
    for (uint32_t i : {0, 1, 2}) m.indices.push_back(i);
    EXPECT_TRUE(onlyDefect(m, MeshDefect::DuplicateTriangle));
    const MeshIntersections r = findMeshIntersections(m);
    ASSERT_EQ(r.examples.size(), 1u);
    EXPECT_EQ(r.examples[0].first, 0u);
    EXPECT_EQ(r.examples[0].second, 4u);
    EXPECT_NE(r.describe(m).find("triangle 4 [0 (0, 0, 0) 1 (1, 0, 0) 2 (0, 1, 0)]"),
              std::string::npos)
        << r.describe(m);
}

TEST(MeshIntersections, AVertexExactlyOnAnotherTrianglesPlaneIsDecidedExactly) {
    // Four float points on the plane x + 2y + 4z = 1 (each x, y a multiple of 2^-24, so z is a
    // float); the fourth inside the triangle of the first three. A double-precision determinant
    // puts it off the plane (checked below); the exact predicates see the contact.
    const glm::vec3 a(0x1.e75a00p-4f, 0x1.2f6ea8p-3f, 0x1.2b5d6cp-3f),
        b(0x1.16a538p-2f, 0x1.0b1b20p-5f, 0x1.534a00p-3f),
        c(0x1.7ad588p-3f, 0x1.d4f6b8p-3f, 0x1.6d9e84p-4f),
        p(0x1.894450p-3f, 0x1.17b960p-3f, 0x1.11d23cp-3f);
    for (const glm::vec3& v : {a, b, c, p})
        ASSERT_EQ(double(v.x) + 2.0 * double(v.y) + 4.0 * double(v.z), 1.0);
    const glm::dvec3 u = glm::dvec3(b) - glm::dvec3(a), v = glm::dvec3(c) - glm::dvec3(a),
                     w = glm::dvec3(p) - glm::dvec3(a);
    const double naive = (u.y * v.z - u.z * v.y) * w.x + (u.z * v.x - u.x * v.z) * w.y +
                         (u.x * v.y - u.y * v.x) * w.z;
    EXPECT_NE(naive, 0.0) << "the case should be one that double arithmetic gets wrong";

    // A second triangle resting on the first at p, the rest of it above the plane (+z side).
    auto resting = [&](glm::vec3 q) {
        return meshOf({a, b, c, q, q + glm::vec3(0, 0, 0.25f), q + glm::vec3(0.1f, 0, 0.25f)},
                      {0, 1, 2, 3, 4, 5});
    };
    EXPECT_TRUE(onlyDefect(resting(p), MeshDefect::Intersecting));
    // One float step up leaves the plane: clean. One step down: through it.
    EXPECT_TRUE(test::noSelfIntersections(resting({p.x, p.y, std::nextafter(p.z, 1.0f)})));
    EXPECT_TRUE(
        onlyDefect(resting({p.x, p.y, std::nextafter(p.z, 0.0f)}), MeshDefect::Intersecting));
    // The same contact through a shared vertex: the second triangle's edge from a runs in the
    // plane to p, inside the first; one step up it leaves the plane at a.
    auto fromA = [&](glm::vec3 q) {
        return meshOf({a, b, c, q, q + glm::vec3(0, 0.01f, 0.25f)}, {0, 1, 2, 0, 3, 4});
    };
    EXPECT_TRUE(onlyDefect(fromA(p), MeshDefect::MeetAtSharedVertex));
    EXPECT_TRUE(test::noSelfIntersections(fromA({p.x, p.y, std::nextafter(p.z, 1.0f)})));
}

TEST(MeshIntersections, APillowOfEightyThousandTrianglesIsClean) {
    // Two 200 x 200 grids bulging apart, their rims at the same positions (vertices of their own):
    // welded, a closed mesh. Prints the cost.
    constexpr int kN = 200;
    MeshBuffers m;
    auto at = [](int side, int i, int j) { return uint32_t((side * (kN + 1) + i) * (kN + 1) + j); };
    for (int side = 0; side < 2; ++side)
        for (int i = 0; i <= kN; ++i)
            for (int j = 0; j <= kN; ++j) {
                const float x = float(i) / kN, y = float(j) / kN;
                const float bulge = 1.6f * x * (1.0f - x) * y * (1.0f - y);  // 0 on the rim
                m.positions.push_back({x, y, side == 0 ? -bulge : bulge});
            }
    for (int side = 0; side < 2; ++side)
        for (int i = 0; i < kN; ++i)
            for (int j = 0; j < kN; ++j) {
                const uint32_t v00 = at(side, i, j), v10 = at(side, i + 1, j),
                               v01 = at(side, i, j + 1), v11 = at(side, i + 1, j + 1);
                // Diagonals that keep an inner vertex in every corner triangle (three rim vertices
                // would make the two sides' triangles duplicates).
                std::array<uint32_t, 6> t =
                    (i < kN / 2) == (j < kN / 2)
                        ? std::array<uint32_t, 6>{v00, v01, v11, v00, v11, v10}
                        : std::array<uint32_t, 6>{v00, v01, v10, v10, v01, v11};
                if (side == 1) {
                    std::swap(t[1], t[2]);
                    std::swap(t[4], t[5]);
                }
                m.indices.insert(m.indices.end(), t.begin(), t.end());
            }
    const auto start = std::chrono::steady_clock::now();
    const std::clock_t startCpu = std::clock();
    const MeshIntersections r = findMeshIntersections(m);
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    const double cpuMs = 1000.0 * double(std::clock() - startCpu) / CLOCKS_PER_SEC;
    std::printf("%zu triangles, %zu candidate pairs: %.1f ms (%.1f ms CPU)\n", m.triangleCount(),
                r.candidatePairs, ms, cpuMs);
    EXPECT_EQ(r.coincidentVertexGroups, std::size_t(4 * kN));
    EXPECT_EQ(r.violations(), r.coincidentVertexGroups) << r.describe(m);
    EXPECT_TRUE(test::closedOrientedManifold(test::weldByPosition(m)));
}

}  // namespace
}  // namespace kizamu
