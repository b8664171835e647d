// SPDX-License-Identifier: Apache-2.0
/// @file cell_box_lines.h
/// @brief The cells debug view's geometry: axis-aligned boxes (the ADF's leaf cells near the
/// surface, as the app lists them) as the 12 edges of each, in one line buffer drawn with one
/// call.
///
/// The renderer never reads the octree: the app turns the published snapshot's cells into
/// CellBoxes (app/cell_view.h) and hands them over; ClayRenderer draws them over the clay,
/// coloured by octree level (cells.vert, cells.frag).
/// Threading: GL objects of the context current at the first upload; use them on its thread only.
#pragma once

#include <epoxy/gl.h>
#include <glm/vec3.hpp>

#include <cstddef>
#include <span>

namespace kizamu::render {

/// One cell: plain data.
struct CellBox {
    glm::vec3 minWorld{0.0f};  ///< m, world: the minimum corner
    float sizeWorld = 0.0f;    ///< m: the edge length
    int level = 0;             ///< octree level (0: the root), for the colour
};

/// Owned by its renderer; move-only; not thread-safe.
class CellBoxLines {
public:
    CellBoxLines() = default;
    CellBoxLines(CellBoxLines&& other) noexcept;
    CellBoxLines& operator=(CellBoxLines&& other) noexcept;
    CellBoxLines(const CellBoxLines&) = delete;
    CellBoxLines& operator=(const CellBoxLines&) = delete;
    ~CellBoxLines();

    /// Replaces the boxes drawn (empty: none).
    /// Complexity: O(boxes) CPU and upload. Threading: a current GL context.
    /// Memory: 24 line vertices of 16 bytes per box, on the GL side and in a temporary.
    void upload(std::span<const CellBox> boxes);
    /// Draws every edge as GL_LINES with the program and state in use: one call; nothing when
    /// empty. The vertex attributes: 0 position (m, world), 1 level (float).
    void draw() const;

    std::size_t boxCount() const { return mBoxCount; }
    /// The coarsest and finest levels among the boxes (both 0 when empty).
    int minLevel() const { return mMinLevel; }
    int maxLevel() const { return mMaxLevel; }

private:
    void release() noexcept;
    GLuint mVao = 0, mBuffer = 0;
    std::size_t mBoxCount = 0;
    int mMinLevel = 0, mMaxLevel = 0;
};

}  // namespace kizamu::render
