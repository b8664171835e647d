// SPDX-License-Identifier: Apache-2.0
/// @file cell_box_lines.cpp
/// @brief Boxes to a line buffer (see cell_box_lines.h).
#include "render/cell_box_lines.h"

#include <glm/vec4.hpp>

#include <algorithm>
#include <utility>
#include <vector>

namespace kizamu::render {

namespace {

/// The 12 edges of the unit cube as pairs of corners (corner bits: x 1, y 2, z 4).
constexpr int kEdges[12][2] = {{0, 1}, {2, 3}, {4, 5}, {6, 7}, {0, 2}, {1, 3},
                               {4, 6}, {5, 7}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};

}  // namespace

CellBoxLines::CellBoxLines(CellBoxLines&& other) noexcept {
    *this = std::move(other);
}

CellBoxLines& CellBoxLines::operator=(CellBoxLines&& other) noexcept {
    if (this != &other) {
        release();
        mVao = std::exchange(other.mVao, 0);
        mBuffer = std::exchange(other.mBuffer, 0);
        mBoxCount = std::exchange(other.mBoxCount, 0);
        mMinLevel = other.mMinLevel;
        mMaxLevel = other.mMaxLevel;
    }
    return *this;
}

CellBoxLines::~CellBoxLines() {
    release();
}

void CellBoxLines::release() noexcept {
    if (mVao) glDeleteVertexArrays(1, &mVao);
    if (mBuffer) glDeleteBuffers(1, &mBuffer);
    mVao = mBuffer = 0;
    mBoxCount = 0;
}

void CellBoxLines::upload(std::span<const CellBox> boxes) {
    // Per line vertex: the position (m, world) and the level, as one vec4.
    std::vector<glm::vec4> vertices;
    vertices.reserve(24 * boxes.size());
    mMinLevel = mMaxLevel = boxes.empty() ? 0 : boxes.front().level;
    for (const CellBox& b : boxes) {
        mMinLevel = std::min(mMinLevel, b.level);
        mMaxLevel = std::max(mMaxLevel, b.level);
        for (const auto& edge : kEdges)
            for (int corner : edge) {
                const glm::vec3 offset(corner & 1, (corner >> 1) & 1, (corner >> 2) & 1);
                vertices.emplace_back(b.minWorld + offset * b.sizeWorld, float(b.level));
            }
    }
    if (!mVao) {
        glGenVertexArrays(1, &mVao);
        glGenBuffers(1, &mBuffer);
        glBindVertexArray(mVao);
        glBindBuffer(GL_ARRAY_BUFFER, mBuffer);
        glEnableVertexAttribArray(0);
        glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(glm::vec4), nullptr);
        glEnableVertexAttribArray(1);
        glVertexAttribPointer(1, 1, GL_FLOAT, GL_FALSE, sizeof(glm::vec4),
                              reinterpret_cast<const void*>(3 * sizeof(float)));
        glBindVertexArray(0);
    }
    glBindBuffer(GL_ARRAY_BUFFER, mBuffer);
    glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(vertices.size() * sizeof(glm::vec4)), vertices.data(),
                 GL_STATIC_DRAW);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    mBoxCount = boxes.size();
}

void CellBoxLines::draw() const {
    if (mBoxCount == 0) return;
    glBindVertexArray(mVao);
    glDrawArrays(GL_LINES, 0, GLsizei(24 * mBoxCount));
    glBindVertexArray(0);
}

}  // namespace kizamu::render
