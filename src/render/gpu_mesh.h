// SPDX-License-Identifier: Apache-2.0
/// @file gpu_mesh.h
/// @brief A `mesh::MeshBuffers` on the GPU: one vertex array with position, normal and colour
/// buffers and an index buffer, drawn with one call.
///
/// Vertex attributes (the shaders' `layout(location = N)`): 0 position (m, world), 1 normal
/// (unit), 2 colour (sRGB bytes, normalised; alpha 255 where painted), 3 spacing (m: the longest
/// edge at the vertex, the size of its disc in points mode). A mesh without normals
/// gets area-weighted vertex normals; a mesh without colours gets the constant attribute
/// (0, 0, 0, 0), which the shaders read as "unpainted: the clay colour".
///
/// Threading: GL objects of the context current at upload; use them on its thread only.
#pragma once

#include "mesh/mesh_buffers.h"

#include <epoxy/gl.h>
#include <glm/vec3.hpp>

#include <cstddef>
#include <vector>

namespace kizamu::render {

namespace attrib {
inline constexpr GLuint kPosition = 0;
inline constexpr GLuint kNormal = 1;
inline constexpr GLuint kColour = 2;
inline constexpr GLuint kSpacing = 3;
}  // namespace attrib

/// Owned by its renderer; move-only; not thread-safe.
class GpuMesh {
public:
    GpuMesh() = default;
    GpuMesh(GpuMesh&& other) noexcept;
    GpuMesh& operator=(GpuMesh&& other) noexcept;
    GpuMesh(const GpuMesh&) = delete;
    GpuMesh& operator=(const GpuMesh&) = delete;
    ~GpuMesh();

    /// Replaces the GPU copy with `m` (whole buffers). Precondition: m.valid().
    /// Complexity: O(vertices + triangles) upload and spacing, plus O(triangles) for missing
    /// normals. Threading: a current GL context. Memory: 32 bytes per vertex and 12 per triangle on the
    /// GL side; a temporary normal array when `m` has none.
    void upload(const mesh::MeshBuffers& m);
    /// Draws every triangle with the program and state in use. Nothing when empty.
    void draw() const;
    /// Draws every vertex as a point (points mode) with the program and state in use.
    void drawPoints() const;

    bool empty() const { return mIndexCount == 0; }
    std::size_t triangleCount() const { return mIndexCount / 3; }
    bool hasColours() const { return mHasColours; }
    /// Axis-aligned bounds of the positions (m, world); both zero when empty.
    const glm::vec3& boundsMin() const { return mBoundsMin; }
    const glm::vec3& boundsMax() const { return mBoundsMax; }

private:
    void release() noexcept;
    GLuint mVao = 0;
    GLuint mPositions = 0, mNormals = 0, mColours = 0, mIndices = 0;
    GLuint mSpacings = 0;
    std::size_t mIndexCount = 0, mVertexCount = 0;
    bool mHasColours = false;
    glm::vec3 mBoundsMin{0.0f}, mBoundsMax{0.0f};
};

/// Area-weighted unit vertex normals of `m` (a triangle's cross product added to its three
/// corners). A vertex on no triangle gets (0, 0, 1).
/// Complexity: O(vertices + triangles). Threading: any. Memory: the returned array.
mesh::MeshBuffers::Buffer<glm::vec3> computeVertexNormals(const mesh::MeshBuffers& m);

/// Per vertex, the longest edge of the triangles on it (m); 0 for a vertex on no triangle
/// (points mode draws none there).
/// Complexity: O(vertices + triangles). Threading: any. Memory: the returned array.
std::vector<float> computeVertexSpacings(const mesh::MeshBuffers& m);

}  // namespace kizamu::render
