// SPDX-License-Identifier: Apache-2.0
/// @file cell_box_lines_test.cpp
/// @brief The cells debug view off screen: boxes drawn over the clay change the picture only
/// where RenderSettings::cells asks, in one draw call; an empty set draws nothing.
#include "render/cell_box_lines.h"

#include "render/camera.h"
#include "render/clay_renderer.h"
#include "tests/unit/render/render_fixture.h"
#include "tests/util/icosphere.h"

#include <gtest/gtest.h>

#include <vector>

namespace kizamu::render {
namespace {

class CellBoxLinesTest : public test::RenderTest {};

TEST_F(CellBoxLinesTest, BoxesShowOverTheClayWhenAsked) {
    ClayRenderer renderer(shaders());
    renderer.setMesh(test::icosphere(0.1f, 3));
    // A shell of boxes around the sphere, two levels.
    std::vector<CellBox> boxes;
    for (int i = 0; i < 8; ++i)
        for (int j = 0; j < 8; ++j) {
            const float x = -0.12f + 0.03f * float(i), y = -0.12f + 0.03f * float(j);
            boxes.push_back({glm::vec3(x, y, 0.07f), 0.03f, 7});
            boxes.push_back({glm::vec3(x, y, -0.11f), 0.015f, 8});
        }
    renderer.setCellBoxes(boxes);
    EXPECT_EQ(renderer.cellBoxes().boxCount(), boxes.size());
    EXPECT_EQ(renderer.cellBoxes().minLevel(), 7);
    EXPECT_EQ(renderer.cellBoxes().maxLevel(), 8);
    OrbitCamera camera;
    camera.setView(ViewAxis::Iso);
    camera.frame(glm::vec3(-0.12f), glm::vec3(0.12f), 1.0f);
    RenderSettings plain, cells;
    cells.cells = true;
    const Image a = renderer.renderToImage(camera, 160, 160, plain);
    const Image b = renderer.renderToImage(camera, 160, 160, cells);
    EXPECT_GT(test::countDiffering(a, b, 8), 500u) << "no cell edges drawn";
    // No boxes: the cells view draws nothing more.
    renderer.setCellBoxes({});
    const Image c = renderer.renderToImage(camera, 160, 160, cells);
    EXPECT_EQ(test::countDiffering(a, c, 0), 0u);
    EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
}

}  // namespace
}  // namespace kizamu::render
