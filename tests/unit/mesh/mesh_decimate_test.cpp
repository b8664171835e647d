// SPDX-License-Identifier: Apache-2.0
// The decimated export copy (mesh_decimate.h): about the asked fraction of the triangles, a
// closed mesh stays closed and oriented, the copy stays near the source both ways (a symmetric
// Hausdorff-like distance), colours ride with their vertices, an open mesh keeps its border.
#include "mesh/mesh_decimate.h"
#include "mesh/triangle_bvh.h"
#include "tests/util/icosphere.h"
#include "tests/util/mesh_check.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <stdexcept>

namespace kizamu {
namespace {

/// The farthest any vertex of `from` lies from the surface of `to` (m).
double farthestVertex(const mesh::MeshBuffers& from, const mesh::MeshBuffers& to) {
    const mesh::TriangleBvh bvh(to);
    double far = 0.0;
    for (const glm::vec3& p : from.positions) far = std::max(far, std::sqrt(bvh.closest(glm::dvec3(p)).distanceSquared));
    return far;
}

/// The farthest triangle centroid of `m` from the sphere of `radius` about the origin (m).
double farthestCentroidFromSphere(const mesh::MeshBuffers& m, double radius) {
    double far = 0.0;
    for (std::size_t t = 0; t < m.triangleCount(); ++t) {
        const glm::dvec3 c = (glm::dvec3(m.positions[m.indices[3 * t]]) + glm::dvec3(m.positions[m.indices[3 * t + 1]]) +
                              glm::dvec3(m.positions[m.indices[3 * t + 2]])) / 3.0;
        far = std::max(far, std::abs(glm::length(c) - radius));
    }
    return far;
}

TEST(Decimate, KeepsAboutTheAskedFractionClosedAndNearTheSource) {
    const float radius = 0.05f;
    mesh::MeshBuffers source = test::icosphere(radius, 4);
    ASSERT_TRUE(test::closedOrientedManifold(source));
    // Painted: red above z = 0, blue below, so a colour that moved to another vertex shows.
    source.colours.resize(source.vertexCount());
    for (std::size_t v = 0; v < source.vertexCount(); ++v)
        source.colours[v] = source.positions[v].z >= 0.0f ? glm::u8vec3(220, 30, 30) : glm::u8vec3(30, 30, 220);
    for (const double ratio : {0.5, 0.25, 0.1}) {
        mesh::DecimateReport report;
        const mesh::MeshBuffers d = mesh::decimateMesh(source, {ratio, 1.0}, &report);
        const double kept = double(d.triangleCount()) / double(source.triangleCount());
        std::printf("[ decimate ] ratio %.2f: %zu -> %zu triangles (%.3f), error %.2e m\n", ratio, source.triangleCount(), d.triangleCount(),
                    kept, report.errorWorld);
        EXPECT_EQ(report.trianglesAfter, d.triangleCount());
        EXPECT_NEAR(kept, ratio, 0.1 * ratio + 0.01) << "about the asked fraction";
        EXPECT_TRUE(d.valid());
        EXPECT_TRUE(test::closedOrientedManifold(d)) << "watertight as the source is, at ratio " << ratio;
        EXPECT_EQ(test::eulerCharacteristic(d), 2) << "still a sphere";
        // Both ways: the source's vertices near the copy's surface, the copy's faces near the sphere.
        EXPECT_LT(farthestVertex(source, d), 0.05 * radius);
        EXPECT_LT(farthestCentroidFromSphere(d, radius), 0.05 * radius);
        ASSERT_EQ(d.colours.size(), d.vertexCount());
        for (std::size_t v = 0; v < d.vertexCount(); ++v)
            EXPECT_EQ(d.colours[v], d.positions[v].z >= 0.0f ? glm::u8vec3(220, 30, 30) : glm::u8vec3(30, 30, 220));
    }
    EXPECT_THROW(mesh::decimateMesh(source, {0.0, 1.0}), std::invalid_argument);
    EXPECT_THROW(mesh::decimateMesh(source, {1.5, 1.0}), std::invalid_argument);
}

TEST(Decimate, AnOpenMeshKeepsItsBorder) {
    // The upper half of a sphere: its rim is a border.
    const mesh::MeshBuffers sphere = test::icosphere(0.05f, 4);
    mesh::MeshBuffers half;
    half.positions = sphere.positions;
    for (std::size_t t = 0; t < sphere.triangleCount(); ++t) {
        float zMin = 1.0f;
        for (int k = 0; k < 3; ++k) zMin = std::min(zMin, sphere.positions[sphere.indices[3 * t + k]].z);
        if (zMin < 0.0f) continue;
        for (int k = 0; k < 3; ++k) half.indices.push_back(sphere.indices[3 * t + k]);
    }
    std::map<std::pair<uint32_t, uint32_t>, int> edges;
    for (std::size_t t = 0; t < half.triangleCount(); ++t)
        for (int k = 0; k < 3; ++k) {
            const uint32_t a = half.indices[3 * t + k], b = half.indices[3 * t + (k + 1) % 3];
            ++edges[{std::min(a, b), std::max(a, b)}];
        }
    std::set<std::tuple<float, float, float>> rim;
    for (const auto& [e, n] : edges)
        if (n == 1)
            for (const uint32_t v : {e.first, e.second}) rim.insert({half.positions[v].x, half.positions[v].y, half.positions[v].z});
    ASSERT_FALSE(rim.empty());
    const mesh::MeshBuffers d = mesh::decimateMesh(half, {0.25, 1.0});
    EXPECT_LT(d.triangleCount(), half.triangleCount() / 2);
    std::set<std::tuple<float, float, float>> kept;
    for (const glm::vec3& p : d.positions) kept.insert({p.x, p.y, p.z});
    for (const auto& p : rim) EXPECT_TRUE(kept.count(p)) << "a rim vertex was collapsed";
}

TEST(Decimate, TheCopysPathSitsBesideTheExport) {
    EXPECT_EQ(mesh::decimatedPath("/tmp/out/bust.stl"), "/tmp/out/bust.decimated.stl");
    EXPECT_EQ(mesh::decimatedPath("bust.obj"), "bust.decimated.obj");
}

}  // namespace
}  // namespace kizamu
