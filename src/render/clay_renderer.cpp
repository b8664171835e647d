// SPDX-License-Identifier: Apache-2.0
/// @file clay_renderer.cpp
/// @brief The clay's draw calls and the off-screen render (see clay_renderer.h).
#include "render/clay_renderer.h"

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/mat3x3.hpp>
#include <glm/vec2.hpp>

#include <algorithm>
#include <cassert>

namespace kizamu::render {

bool applyModeName(std::string_view name, RenderSettings& settings) {
    if (name == "lit") {
        settings.shade = ShadeMode::Lit;
        settings.wireframe = false;
    } else if (name == "matcap") {
        settings.shade = ShadeMode::Matcap;
        settings.wireframe = false;
    } else if (name == "points") {
        settings.shade = ShadeMode::Points;
        settings.wireframe = false;
    } else if (name == "wireframe") {
        settings.shade = ShadeMode::Lit;
        settings.wireframe = true;
    } else {
        return false;
    }
    return true;
}

ClayRenderer::ClayRenderer(const ShaderLibrary& shaders)
    : mLit(shaders.build({"clay.vert", "clay.frag", "clay_shading.frag"})),
      mMatcap(shaders.build({"clay.vert", "matcap.frag"})),
      mPoints(shaders.build({"points.vert", "points.frag", "clay_shading.frag"})),
      mWire(shaders.build({"clay.vert", "wire.frag"})),
      mGround(shaders.build({"ground.vert", "ground.frag"})),
      mTool(shaders.build({"tool.vert", "tool.frag"})),
      mCells(shaders.build({"cells.vert", "cells.frag"})) {
    glGenVertexArrays(1, &mEmptyVao);
    GLfloat pointSizes[2] = {1.0f, 1.0f};
    glGetFloatv(GL_POINT_SIZE_RANGE, pointSizes);
    mMaxPointSize = pointSizes[1];
}

ClayRenderer::~ClayRenderer() {
    if (mEmptyVao) glDeleteVertexArrays(1, &mEmptyVao);
}

ViewSetup ViewSetup::of(const OrbitCamera& camera, int width, int height) {
    ViewSetup v;
    v.view = camera.viewMatrix();
    v.projection = camera.projectionMatrix(float(width) / float(std::max(height, 1)));
    v.viewportHeight = std::max(height, 1);
    v.eye = camera.eye();
    v.orthographic = camera.projection == Projection::Orthographic;
    return v;
}

void ClayRenderer::drawGround(const ViewSetup& v, const RenderSettings& settings) const {
    const glm::vec3 lo = boundsMin(), hi = boundsMax();
    // Seen from below, the floor would hide the model: it is drawn only from above.
    if (v.eye.z <= lo.z) return;
    const glm::mat4& view = v.view;
    const glm::mat4& projection = v.projection;
    const glm::vec2 centre = 0.5f * (glm::vec2(lo) + glm::vec2(hi));
    const glm::vec2 footprintHalf = 0.5f * (glm::vec2(hi) - glm::vec2(lo));
    const float halfSize = 2.5f * std::max(glm::length(footprintHalf), 0.5f * (hi.z - lo.z));
    mGround.use();
    mGround.set("uView", view);
    mGround.set("uProjection", projection);
    mGround.set("uCentre", centre);
    mGround.set("uHalfSize", halfSize);
    // A hair below the model, so its lowest triangles win the depth test.
    mGround.set("uGroundZ", lo.z - 1e-4f * halfSize);
    mGround.set("uFootprintHalf", footprintHalf);
    mGround.set("uBackgroundSrgb", settings.backgroundSrgb);
    mGround.set("uFloorSrgb", settings.floorSrgb);
    glBindVertexArray(mEmptyVao);
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    glBindVertexArray(0);
}

void ClayRenderer::setMesh(const mesh::MeshBuffers& m) {
    mMesh.upload(m);
    mTiled = TiledGpuMesh();
    mDrawsTiled = false;
}

bool ClayRenderer::applyDelta(mesh::MeshDelta&& delta, const VertexColourFunction& colour) {
    if (!mTiled.apply(std::move(delta), colour)) return false;
    if (!mDrawsTiled) mMesh = GpuMesh();
    mDrawsTiled = true;
    return true;
}

std::size_t ClayRenderer::triangleCount() const {
    return mDrawsTiled ? mTiled.triangleCount() : mMesh.triangleCount();
}

void ClayRenderer::drawMesh() const {
    if (mDrawsTiled)
        mTiled.draw();
    else
        mMesh.draw();
}

void ClayRenderer::drawMeshPoints() const {
    if (mDrawsTiled)
        mTiled.drawPoints();
    else
        mMesh.drawPoints();
}

void ClayRenderer::drawCells(const glm::mat4& view, const glm::mat4& projection) const {
    mCells.use();
    mCells.set("uView", view);
    mCells.set("uProjection", projection);
    mCells.set("uLevelRange",
               glm::vec2(float(mCellBoxes.minLevel()), float(mCellBoxes.maxLevel())));
    mCells.set("uAlpha", 0.85f);
    // Depth tested: a cell straddles the surface, its edges outside the clay show.
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    glDepthFunc(GL_LEQUAL);
    mCellBoxes.draw();
    glDepthFunc(GL_LESS);
    glDisable(GL_BLEND);
}

void ClayRenderer::drawTool(const ToolMark& tool, const glm::mat4& view, const glm::mat4& projection,
                            bool floor) const {
    mTool.use();
    mTool.set("uView", view);
    mTool.set("uProjection", projection);
    mTool.set("uCentre", tool.centre);
    mTool.set("uNormal", tool.normal);
    mTool.set("uRadius", tool.radius);
    // The floor's height as drawGround puts it (a hair above, so the spot wins the depth test).
    const float floorZ = boundsMin().z;
    mTool.set("uFloorZ", floorZ);
    glBindVertexArray(mEmptyVao);
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    if (floor && tool.centre.z > floorZ) {
        mTool.set("uMode", 2);
        mTool.set("uColourSrgba", glm::vec4(0.0f, 0.0f, 0.0f, 0.45f));
        glDrawArrays(GL_TRIANGLE_FAN, 0, 34);
        mTool.set("uMode", 1);
        mTool.set("uColourSrgba", glm::vec4(tool.ringSrgba.r, tool.ringSrgba.g, tool.ringSrgba.b, 0.5f));
        glDrawArrays(GL_LINES, 0, 2);
    }
    // The ring over everything: a cursor must never hide behind the bump it is on.
    glDisable(GL_DEPTH_TEST);
    mTool.set("uMode", 0);
    mTool.set("uColourSrgba", tool.ringSrgba);
    glDrawArrays(GL_LINE_LOOP, 0, 64);
    glEnable(GL_DEPTH_TEST);
    glDisable(GL_BLEND);
    glBindVertexArray(0);
}

void ClayRenderer::drawToolBody(const ToolMark& tool, const glm::mat4& view, const glm::mat4& projection) const {
    std::optional<GpuMesh>& body = mToolBodies[std::size_t(tool.body)];
    if (!body) {
        body.emplace();
        body->upload(unitToolBody(tool.body));
    }
    const glm::mat4 model = glm::scale(glm::translate(glm::mat4(1.0f), tool.centre), glm::vec3(tool.radius));
    mWire.use();
    mWire.set("uView", view * model);
    mWire.set("uProjection", projection);
    mWire.set("uNormalView", glm::mat3(view));
    mWire.set("uWireSrgba", glm::vec4(tool.ringSrgba.r, tool.ringSrgba.g, tool.ringSrgba.b, 0.6f));
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
    body->draw();
    glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    glDisable(GL_BLEND);
}

void ClayRenderer::draw(const OrbitCamera& camera, int width, int height,
                        const RenderSettings& settings, const ToolMark* tool) const {
    draw(ViewSetup::of(camera, width, height), settings, tool);
}

void ClayRenderer::draw(const ViewSetup& v, const RenderSettings& settings, const ToolMark* tool) const {
    const glm::vec3 bg = settings.backgroundSrgb;
    glClearColor(bg.r, bg.g, bg.b, 1.0f);
    glClearDepth(1.0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    if (meshEmpty()) return;

    const glm::mat4& view = v.view;
    const glm::mat4& projection = v.projection;
    const int ortho = v.orthographic ? 1 : 0;

    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    // Not culled: a mesh with holes shows its inside (clay.frag lights back faces as such).
    glDisable(GL_CULL_FACE);
    glDisable(GL_BLEND);
    glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    if (settings.ground) drawGround(v, settings);
    if (settings.wireframe) {
        // The surface is pushed back a little so the lines drawn at its exact depth pass the test.
        glEnable(GL_POLYGON_OFFSET_FILL);
        glPolygonOffset(1.0f, 1.0f);
    }
    const bool points = settings.shade == ShadeMode::Points;
    const ShaderProgram& surface =
        points ? mPoints : settings.shade == ShadeMode::Matcap ? mMatcap : mLit;
    surface.use();
    surface.set("uView", view);
    surface.set("uProjection", projection);
    surface.set("uNormalView", glm::mat3(view));
    surface.set("uClaySrgb", settings.claySrgb);
    surface.set("uOrthographic", ortho);
    if (points) {
        surface.set("uViewportHeight", float(v.viewportHeight));
        surface.set("uMaxPointSize", mMaxPointSize);
        glEnable(GL_PROGRAM_POINT_SIZE);
        drawMeshPoints();
        glDisable(GL_PROGRAM_POINT_SIZE);
    } else {
        drawMesh();
    }
    glDisable(GL_POLYGON_OFFSET_FILL);

    if (settings.wireframe) {
        mWire.use();
        mWire.set("uView", view);
        mWire.set("uProjection", projection);
        mWire.set("uNormalView", glm::mat3(view));
        mWire.set("uWireSrgba", settings.wireSrgba);
        glEnable(GL_BLEND);
        glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
        glDepthFunc(GL_LEQUAL);
        glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
        drawMesh();
        glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
        glDepthFunc(GL_LESS);
        glDisable(GL_BLEND);
    }
    if (settings.cells && mCellBoxes.boxCount() > 0) drawCells(view, projection);
    if (tool) drawTool(*tool, view, projection, settings.ground);
    if (tool && tool->body != ToolBody::None) drawToolBody(*tool, view, projection);
    glUseProgram(0);
    // Debug builds only: glGetError stalls some drivers (style: GL errors are bugs, asserted).
    assert(glGetError() == GL_NO_ERROR && "ClayRenderer::draw left a GL error");
}

Image ClayRenderer::renderToImage(const OrbitCamera& camera, int width, int height,
                                  const RenderSettings& settings, const ToolMark* tool) {
    if (!mTarget || mTarget->width() != width || mTarget->height() != height ||
        mTarget->samples() > std::max(settings.samples, 1))
        mTarget.emplace(width, height, settings.samples);
    mTarget->bind();
    draw(camera, width, height, settings, tool);
    return mTarget->read();
}

}  // namespace kizamu::render
