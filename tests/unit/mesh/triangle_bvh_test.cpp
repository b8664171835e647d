// SPDX-License-Identifier: Apache-2.0
// BVH closest point against brute force, winding numbers inside/outside and with holes, and an
// imported mesh turned into an ADF.
#include "mesh/mesh_source.h"

#include "adf/generate.h"
#include "tests/util/icosphere.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>

using namespace kizamu;
using namespace kizamu::mesh;
using kizamu::test::icosphere;

namespace {

TEST(TriangleBvh, ClosestPointMatchesBruteForce) {
    const MeshBuffers mesh = icosphere(0.3f, 3);
    const TriangleBvh bvh(mesh);
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> u(-0.6, 0.6);
    for (int i = 0; i < 300; ++i) {
        const glm::dvec3 p(u(rng), u(rng), u(rng));
        double brute = 1e300;
        // Brute force through single-triangle BVHs keeps this test independent of the traversal.
        for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
            MeshBuffers one;
            one.positions = {mesh.positions[mesh.indices[3 * t]], mesh.positions[mesh.indices[3 * t + 1]],
                             mesh.positions[mesh.indices[3 * t + 2]]};
            one.indices = {0, 1, 2};
            brute = std::min(brute, TriangleBvh(one).closest(p).distanceSquared);
        }
        ASSERT_NEAR(bvh.closest(p).distanceSquared, brute, 1e-12);
        // Any hint gives the same answer (it only seeds the bound).
        const TriangleBvh::Closest hinted = bvh.closest(p, uint32_t(i * 7919) % uint32_t(mesh.triangleCount()));
        ASSERT_EQ(hinted.distanceSquared, bvh.closest(p).distanceSquared);
        ASSERT_EQ(hinted.triangle, bvh.closest(p).triangle);
    }
}

TEST(TriangleBvh, DegenerateTrianglesStillAnswer) {
    MeshBuffers m;
    m.positions = {{0, 0, 0}, {0, 0, 0}, {1, 0, 0}};  // two equal corners, as welding leaves them
    m.indices = {0, 1, 2};
    const TriangleBvh::Closest c = TriangleBvh(m).closest({0.5, 1.0, 0.0});
    EXPECT_NEAR(c.distanceSquared, 1.0, 1e-12);
    EXPECT_NEAR(c.point.x, 0.5, 1e-12);
}

TEST(TriangleBvh, HintsNeverChangeTheAnswerNearSharedEdges) {
    const MeshBuffers mesh = icosphere(0.3f, 3);
    const TriangleBvh bvh(mesh);
    std::mt19937_64 rng(8);
    std::uniform_real_distribution<double> tiny(-1e-7, 1e-7);
    for (std::size_t t = 0; t < mesh.triangleCount(); t += 7) {
        // Just off the midpoint of an edge, where two triangles tie.
        const glm::dvec3 a(mesh.positions[mesh.indices[3 * t]]), b(mesh.positions[mesh.indices[3 * t + 1]]);
        const glm::dvec3 p = 0.5 * (a + b) * (1.0 + tiny(rng)) + glm::dvec3(tiny(rng), tiny(rng), tiny(rng));
        const TriangleBvh::Closest plain = bvh.closest(p);
        for (uint32_t hint : {0u, uint32_t(t), uint32_t(mesh.triangleCount() - 1)}) {
            const TriangleBvh::Closest hinted = bvh.closest(p, hint);
            ASSERT_EQ(hinted.distanceSquared, plain.distanceSquared);
            ASSERT_EQ(hinted.triangle, plain.triangle);
            ASSERT_EQ(hinted.point, plain.point);
        }
    }
}

TEST(TriangleBvh, WindingNumberIsOneInsideZeroOutsideAndSurvivesHoles) {
    MeshBuffers mesh = icosphere(0.3f, 3);
    const TriangleBvh closed(mesh);
    // Exact sums are exact; the first-order far field is within a few percent (beta = 2).
    EXPECT_NEAR(closed.windingNumberExact({0, 0, 0}), 1.0, 1e-9);
    EXPECT_NEAR(closed.windingNumberExact({0.5, 0.0, 0.0}), 0.0, 1e-9);
    EXPECT_NEAR(closed.windingNumber({0, 0, 0}), 1.0, 0.05);
    EXPECT_NEAR(closed.windingNumber({0.1, 0.05, -0.1}), 1.0, 0.05);
    EXPECT_NEAR(closed.windingNumber({0.5, 0.0, 0.0}), 0.0, 0.05);
    EXPECT_NEAR(closed.windingNumber({2.0, 1.0, 0.0}), 0.0, 0.01);
    EXPECT_NEAR(closed.windingNumber({0.1, 0.05, -0.1}, 1e9), closed.windingNumberExact({0.1, 0.05, -0.1}), 1e-9);
    // Punch a hole: remove 10 % of the triangles; the centre is still clearly inside.
    mesh.indices.resize(mesh.indices.size() * 9 / 10 / 3 * 3);
    const TriangleBvh holed(mesh);
    EXPECT_GT(holed.windingNumber({0, 0, 0}), 0.6);
    EXPECT_LT(holed.windingNumber({0.8, 0, 0}), 0.4);
}

TEST(MeshSource, AnImportedMeshBecomesAnAdf) {
    const MeshBuffers mesh = icosphere(0.3f, 4);
    const adf::SourcePtr src = makeMeshSource(mesh);
    const adf::Domain d = domainAround(mesh, 7, 10.0);
    const adf::AdfPtr a = adf::generate(*src, d, adf::GenerationSettings{});
    const double h = d.finestCellSize();
    EXPECT_LT(a->distance({0, 0, 0}), -0.25f);
    EXPECT_GT(a->distance({0.4f, 0, 0}), 0.05f);
    // Within the band the ADF follows the mesh's own distance (not the ideal sphere's).
    std::mt19937_64 rng(6);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int i = 0; i < 500; ++i) {
        const glm::dvec3 dir = glm::normalize(glm::dvec3(u(rng), u(rng), u(rng)));
        const glm::dvec3 p = dir * (0.3 + 4.0 * h * u(rng));
        EXPECT_NEAR(a->distance(glm::vec3(p)), src->distance(p), 0.5 * h);
    }
}

}  // namespace
