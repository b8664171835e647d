// SPDX-License-Identifier: Apache-2.0
/// @file gpu_mesh.cpp
/// @brief MeshBuffers to vertex and index buffers (see gpu_mesh.h).
#include "render/gpu_mesh.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cassert>
#include <utility>
#include <vector>

namespace kizamu::render {

mesh::MeshBuffers::Buffer<glm::vec3> computeVertexNormals(const mesh::MeshBuffers& m) {
    mesh::MeshBuffers::Buffer<glm::vec3> n(m.positions.size());
    std::fill(n.begin(), n.end(), glm::vec3(0.0f));
    for (std::size_t t = 0; t + 2 < m.indices.size(); t += 3) {
        const uint32_t a = m.indices[t], b = m.indices[t + 1], c = m.indices[t + 2];
        const glm::vec3 area =
            glm::cross(m.positions[b] - m.positions[a], m.positions[c] - m.positions[a]);
        n[a] += area;
        n[b] += area;
        n[c] += area;
    }
    for (glm::vec3& v : n) {
        const float len = glm::length(v);
        v = len > 0.0f ? v / len : glm::vec3(0.0f, 0.0f, 1.0f);
    }
    return n;
}

std::vector<float> computeVertexSpacings(const mesh::MeshBuffers& m) {
    std::vector<float> spacing(m.positions.size(), 0.0f);
    for (std::size_t t = 0; t + 2 < m.indices.size(); t += 3) {
        const uint32_t v[3] = {m.indices[t], m.indices[t + 1], m.indices[t + 2]};
        const float longest = std::max({glm::distance(m.positions[v[0]], m.positions[v[1]]),
                                        glm::distance(m.positions[v[1]], m.positions[v[2]]),
                                        glm::distance(m.positions[v[2]], m.positions[v[0]])});
        for (uint32_t i : v) spacing[i] = std::max(spacing[i], longest);
    }
    return spacing;
}

GpuMesh::GpuMesh(GpuMesh&& other) noexcept {
    *this = std::move(other);
}

GpuMesh& GpuMesh::operator=(GpuMesh&& other) noexcept {
    if (this != &other) {
        release();
        mVao = std::exchange(other.mVao, 0);
        mPositions = std::exchange(other.mPositions, 0);
        mNormals = std::exchange(other.mNormals, 0);
        mColours = std::exchange(other.mColours, 0);
        mIndices = std::exchange(other.mIndices, 0);
        mSpacings = std::exchange(other.mSpacings, 0);
        mIndexCount = std::exchange(other.mIndexCount, 0);
        mVertexCount = std::exchange(other.mVertexCount, 0);
        mHasColours = other.mHasColours;
        mBoundsMin = other.mBoundsMin;
        mBoundsMax = other.mBoundsMax;
    }
    return *this;
}

GpuMesh::~GpuMesh() {
    release();
}

void GpuMesh::release() noexcept {
    if (mVao) glDeleteVertexArrays(1, &mVao);
    for (GLuint* b : {&mPositions, &mNormals, &mColours, &mIndices, &mSpacings})
        if (*b) glDeleteBuffers(1, b);
    mVao = mPositions = mNormals = mColours = mIndices = mSpacings = 0;
    mIndexCount = mVertexCount = 0;
}

void GpuMesh::upload(const mesh::MeshBuffers& m) {
    assert(m.valid() && "GpuMesh::upload: the mesh's sizes disagree or an index is out of range");
    release();
    mHasColours = !m.colours.empty();
    mBoundsMin = mBoundsMax = glm::vec3(0.0f);
    if (!m.positions.empty()) {
        mBoundsMin = mBoundsMax = m.positions.front();
        for (const glm::vec3& p : m.positions) {
            mBoundsMin = glm::min(mBoundsMin, p);
            mBoundsMax = glm::max(mBoundsMax, p);
        }
    }
    glGenVertexArrays(1, &mVao);
    glBindVertexArray(mVao);

    auto arrayBuffer = [](GLuint& buffer, const void* data, std::size_t bytes) {
        glGenBuffers(1, &buffer);
        glBindBuffer(GL_ARRAY_BUFFER, buffer);
        glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(bytes), data, GL_STATIC_DRAW);
    };
    arrayBuffer(mPositions, m.positions.data(), m.positions.size() * sizeof(glm::vec3));
    glEnableVertexAttribArray(attrib::kPosition);
    glVertexAttribPointer(attrib::kPosition, 3, GL_FLOAT, GL_FALSE, sizeof(glm::vec3), nullptr);

    if (m.normals.size() == m.positions.size()) {
        arrayBuffer(mNormals, m.normals.data(), m.normals.size() * sizeof(glm::vec3));
    } else {
        const auto normals = computeVertexNormals(m);
        arrayBuffer(mNormals, normals.data(), normals.size() * sizeof(glm::vec3));
    }
    glEnableVertexAttribArray(attrib::kNormal);
    glVertexAttribPointer(attrib::kNormal, 3, GL_FLOAT, GL_FALSE, sizeof(glm::vec3), nullptr);

    if (mHasColours) {
        // RGBA bytes: the alpha channel tells the shader the vertex carries a colour.
        std::vector<glm::u8vec4> rgba(m.colours.size());
        for (std::size_t i = 0; i < rgba.size(); ++i) rgba[i] = glm::u8vec4(m.colours[i], 255);
        arrayBuffer(mColours, rgba.data(), rgba.size() * sizeof(glm::u8vec4));
        glEnableVertexAttribArray(attrib::kColour);
        glVertexAttribPointer(attrib::kColour, 4, GL_UNSIGNED_BYTE, GL_TRUE, sizeof(glm::u8vec4),
                              nullptr);
    } else {
        glDisableVertexAttribArray(attrib::kColour);
    }

    const std::vector<float> spacings = computeVertexSpacings(m);
    arrayBuffer(mSpacings, spacings.data(), spacings.size() * sizeof(float));
    glEnableVertexAttribArray(attrib::kSpacing);
    glVertexAttribPointer(attrib::kSpacing, 1, GL_FLOAT, GL_FALSE, sizeof(float), nullptr);

    glGenBuffers(1, &mIndices);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, mIndices);  // recorded in the vertex array
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(m.indices.size() * sizeof(uint32_t)),
                 m.indices.data(), GL_STATIC_DRAW);
    mIndexCount = m.indices.size();
    mVertexCount = m.positions.size();
    glBindVertexArray(0);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
}

void GpuMesh::draw() const {
    if (mIndexCount == 0) return;
    glBindVertexArray(mVao);
    // The constant colour attribute (0, 0, 0, 0) is context state, not vertex-array state:
    // set it for every draw of an unpainted mesh.
    if (!mHasColours) glVertexAttrib4f(attrib::kColour, 0.0f, 0.0f, 0.0f, 0.0f);
    glDrawElements(GL_TRIANGLES, GLsizei(mIndexCount), GL_UNSIGNED_INT, nullptr);
    glBindVertexArray(0);
}

void GpuMesh::drawPoints() const {
    if (mIndexCount == 0) return;
    glBindVertexArray(mVao);
    if (!mHasColours) glVertexAttrib4f(attrib::kColour, 0.0f, 0.0f, 0.0f, 0.0f);
    glDrawArrays(GL_POINTS, 0, GLsizei(mVertexCount));
    glBindVertexArray(0);
}

}  // namespace kizamu::render
