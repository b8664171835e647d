// SPDX-License-Identifier: Apache-2.0
/// @file gpu_mesh_test.cpp
/// @brief The GPU mesh: normals made for meshes without them point outward; bounds; upload of
/// meshes with and without colours.
#include "render/gpu_mesh.h"
#include "tests/unit/render/render_fixture.h"
#include "tests/util/icosphere.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

namespace kizamu::render {
namespace {

TEST(VertexNormals, OutwardOnASphere) {
    const mesh::MeshBuffers m = test::icosphere(2.0f, 3);
    const auto n = computeVertexNormals(m);
    ASSERT_EQ(n.size(), m.positions.size());
    for (std::size_t i = 0; i < n.size(); ++i) {
        EXPECT_NEAR(glm::length(n[i]), 1.0f, 1e-5f);
        EXPECT_GT(glm::dot(n[i], glm::normalize(m.positions[i])), 0.99f) << "vertex " << i;
    }
}

TEST(VertexNormals, UnusedVertexGetsUp) {
    mesh::MeshBuffers m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {5, 5, 5}};
    m.indices = {0, 1, 2};
    const auto n = computeVertexNormals(m);
    EXPECT_EQ(n[0], glm::vec3(0, 0, 1));
    EXPECT_EQ(n[3], glm::vec3(0, 0, 1));
}

class GpuMeshTest : public test::RenderTest {};

TEST_F(GpuMeshTest, UploadKeepsCountsAndBounds) {
    mesh::MeshBuffers m = test::icosphere(0.5f, 2);
    GpuMesh g;
    EXPECT_TRUE(g.empty());
    g.upload(m);
    EXPECT_EQ(g.triangleCount(), m.triangleCount());
    EXPECT_FALSE(g.hasColours());
    EXPECT_NEAR(g.boundsMax().x, 0.5f, 1e-6f);
    EXPECT_NEAR(g.boundsMin().z, -0.5f, 1e-6f);
    m.colours.assign(m.positions.size(), glm::u8vec3(10, 20, 30));
    g.upload(m);
    EXPECT_TRUE(g.hasColours());
    GpuMesh moved = std::move(g);
    EXPECT_TRUE(g.empty());
    EXPECT_EQ(moved.triangleCount(), m.triangleCount());
    EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
}

}  // namespace
}  // namespace kizamu::render
