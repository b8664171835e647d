// SPDX-License-Identifier: Apache-2.0
/// @file clay_renderer_test.cpp
/// @brief Off-screen renders: a sphere's silhouette covers its projected area, its centre is
/// lit, the corners are background; painted colours show; every mode draws; the level-7 test
/// part matches its reference image (tests/data/render/).
#include "render/clay_renderer.h"
#include "adf/colour_layer.h"
#include "adf/generate.h"
#include "adf/test_part.h"
#include "mesh/surface_nets.h"
#include "render/camera.h"
#include "render/offscreen.h"
#include "tests/unit/render/render_fixture.h"
#include "tests/util/icosphere.h"
#include "util/thread_pool.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

namespace kizamu::render {
namespace {

namespace fs = std::filesystem;
using test::backgroundOf;
using test::countNot;
using test::differs;

constexpr float kPi = 3.14159265358979f;

class ClayRenderTest : public test::RenderTest {};

/// The sphere's silhouette radius in pixels, as the camera projects a sphere of radius r at
/// its target, for an image `height` pixels tall.
double silhouetteRadiusPx(const OrbitCamera& c, double r, int height) {
    const double halfFov = 0.5 * double(c.fovYRad);
    if (c.projection == Projection::Orthographic)
        return r / (double(c.distance) * std::tan(halfFov)) * 0.5 * height;
    // The cone from the eye that touches the sphere has half-angle asin(r / d).
    return std::tan(std::asin(r / double(c.distance))) / std::tan(halfFov) * 0.5 * height;
}

TEST_F(ClayRenderTest, SphereCoversItsProjectedArea) {
    const float r = 0.1f;
    ClayRenderer renderer(shaders());
    renderer.setMesh(test::icosphere(r, 5));
    const int w = 480, h = 360;
    for (Projection p : {Projection::Perspective, Projection::Orthographic}) {
        SCOPED_TRACE(p == Projection::Perspective ? "perspective" : "orthographic");
        OrbitCamera camera;
        camera.projection = p;
        camera.setView(ViewAxis::Front);
        camera.frame(glm::vec3(-r), glm::vec3(r), float(w) / float(h));
        RenderSettings settings;
        const Image image = renderer.renderToImage(camera, w, h, settings);
        EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
        ASSERT_EQ(image.width, w);
        ASSERT_EQ(image.height, h);
        const glm::u8vec4 bg = backgroundOf(settings.backgroundSrgb);
        // Edge pixels are partly covered (MSAA); counting every pixel off the background
        // overestimates by about half the perimeter, under 1% at this size.
        const double covered = double(countNot(image, bg, 2));
        const double rho = silhouetteRadiusPx(camera, r, h);
        const double expected = kPi * rho * rho;
        EXPECT_NEAR(covered / expected, 1.0, 0.03)
            << "covered " << covered << " px, expected " << expected;
        // Corners: background, exactly.
        for (auto [x, y] : {std::pair{0, 0}, {w - 1, 0}, {0, h - 1}, {w - 1, h - 1}})
            EXPECT_FALSE(differs(image.at(x, y), bg, 0)) << "corner " << x << "," << y;
        // The centre faces the viewer: lit clay, well above the background, warm (r > g > b).
        const glm::u8vec4 c = image.at(w / 2, h / 2);
        EXPECT_GT(int(c.r), int(bg.r) + 80)
            << "centre " << int(c.r) << "," << int(c.g) << "," << int(c.b);
        EXPECT_GT(c.r, c.g);
        EXPECT_GT(c.g, c.b);
        // Lit from the upper left: the upper left of the disc is brighter than the lower right.
        const int off = int(0.5 * rho);
        const glm::u8vec4 ul = image.at(w / 2 - off, h / 2 - off),
                          lr = image.at(w / 2 + off, h / 2 + off);
        EXPECT_GT(int(ul.r) + ul.g + ul.b, int(lr.r) + lr.g + lr.b + 30);
    }
}

TEST_F(ClayRenderTest, PaintedColoursShow) {
    mesh::MeshBuffers m = test::icosphere(0.1f, 4);
    // The upper half (z > 0: the top of the front view) painted blue; the rest left pale.
    const glm::u8vec3 blue{30, 70, 230}, pale{230, 225, 215};
    for (const glm::vec3& p : m.positions) m.colours.push_back(p.z > 0.0f ? blue : pale);
    ClayRenderer renderer(shaders());
    renderer.setMesh(m);
    OrbitCamera camera;
    camera.setView(ViewAxis::Front);
    camera.frame(glm::vec3(-0.1f), glm::vec3(0.1f), 1.0f);
    const Image image = renderer.renderToImage(camera, 200, 200, RenderSettings{});
    const glm::u8vec4 top = image.at(100, 75), bottom = image.at(100, 125);
    EXPECT_GT(int(top.b), int(top.r) + 60)
        << "top " << int(top.r) << "," << int(top.g) << "," << int(top.b);
    EXPECT_LT(std::abs(int(bottom.r) - int(bottom.b)), 40)
        << "bottom " << int(bottom.r) << "," << int(bottom.g) << "," << int(bottom.b);
}

TEST_F(ClayRenderTest, UnpaintedLooksLikeTheColourLayersClay) {
    // A painted mesh's unpainted vertices carry the layer's clay colour; a mesh with no colours
    // at all must look the same, or painting one spot would recolour the whole model.
    mesh::MeshBuffers plain = test::icosphere(0.1f, 4);
    mesh::MeshBuffers clay = plain;
    const adf::Rgb8 k = adf::kClayColour;
    clay.colours.assign(clay.positions.size(), k);
    ClayRenderer renderer(shaders());
    OrbitCamera camera;
    camera.setView(ViewAxis::Iso);
    camera.frame(glm::vec3(-0.1f), glm::vec3(0.1f), 1.0f);
    renderer.setMesh(plain);
    const Image a = renderer.renderToImage(camera, 128, 128, RenderSettings{});
    renderer.setMesh(clay);
    const Image b = renderer.renderToImage(camera, 128, 128, RenderSettings{});
    std::size_t off = 0;
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x) off += differs(a.at(x, y), b.at(x, y), 1) ? 1 : 0;
    EXPECT_EQ(off, 0u);
    // Warm: red above blue where the clay faces the viewer.
    const glm::u8vec4 c = a.at(64, 64);
    EXPECT_GT(int(c.r), int(c.b) + 10) << int(c.r) << "," << int(c.g) << "," << int(c.b);
}

TEST_F(ClayRenderTest, ModesDrawDifferently) {
    ClayRenderer renderer(shaders());
    renderer.setMesh(test::icosphere(0.1f, 3));
    OrbitCamera camera;
    camera.setView(ViewAxis::Iso);
    camera.frame(glm::vec3(-0.1f), glm::vec3(0.1f), 1.0f);
    RenderSettings lit, matcap, wire;
    ASSERT_TRUE(applyModeName("matcap", matcap));
    ASSERT_TRUE(applyModeName("wireframe", wire));
    EXPECT_FALSE(applyModeName("xray", wire));
    const Image a = renderer.renderToImage(camera, 128, 128, lit);
    const Image b = renderer.renderToImage(camera, 128, 128, matcap);
    const Image c = renderer.renderToImage(camera, 128, 128, wire);
    auto changed = [](const Image& x, const Image& y) {
        std::size_t n = 0;
        for (int j = 0; j < x.height; ++j)
            for (int i = 0; i < x.width; ++i) n += differs(x.at(i, j), y.at(i, j), 8) ? 1 : 0;
        return n;
    };
    EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
    EXPECT_GT(changed(a, b), 1000u) << "matcap looks like lit";
    EXPECT_GT(changed(a, c), 500u) << "no wireframe lines";
    // Silhouettes agree: the same pixels are off the background in every mode.
    const glm::u8vec4 bg = backgroundOf(lit.backgroundSrgb);
    EXPECT_NEAR(double(countNot(a, bg, 2)), double(countNot(b, bg, 2)),
                0.01 * double(countNot(a, bg, 2)));
}

TEST_F(ClayRenderTest, PointsCoverAboutTheLitMeshsPixels) {
    // The level-8 test part (adaptive: large triangles on its flat faces, small ones on its
    // features), and a level-7 rounded box (faces of a few large triangles, large discs), whole
    // (setMesh) and tiled (applyDelta), from two sides and in both projections.
    util::ThreadPool pool(2);
    const adf::Domain d = adf::testPartDomain(8);
    adf::Domain boxDomain;
    boxDomain.maxLevel = 7;
    for (int part = 0; part < 2; ++part) {
        SCOPED_TRACE(part == 0 ? "test part" : "rounded box");
        mesh::SurfaceMesher mesher(&pool);
        mesher.build(part == 0 ? adf::generate(*adf::makeTestPart(d), d, adf::testPartSettings(), &pool)
                               : adf::generate(*adf::makeTranslated(adf::makeRoundedBox({0.3, 0.3, 0.3}, 0.02), glm::dvec3(0.5)),
                                               boxDomain, adf::GenerationSettings{}, &pool));
        ClayRenderer whole(shaders()), tiled(shaders());
        whole.setMesh(mesher.mesh());
        ASSERT_TRUE(tiled.applyDelta(mesher.takeDelta()));
        RenderSettings lit, points;
        ASSERT_TRUE(applyModeName("points", points));
        EXPECT_EQ(points.shade, ShadeMode::Points);
        const glm::u8vec4 bg = backgroundOf(lit.backgroundSrgb);
        for (ClayRenderer* r : {&whole, &tiled})
            for (ViewAxis axis : {ViewAxis::Iso, ViewAxis::Top})
                for (Projection p : {Projection::Perspective, Projection::Orthographic}) {
                    SCOPED_TRACE(std::string(r == &whole ? "whole" : "tiled") + (axis == ViewAxis::Iso ? " iso" : " top") +
                                 (p == Projection::Perspective ? " perspective" : " orthographic"));
                    OrbitCamera camera;
                    camera.projection = p;
                    camera.setView(axis);
                    camera.frame(r->boundsMin(), r->boundsMax(), 4.0f / 3.0f);
                    const Image a = r->renderToImage(camera, 640, 480, lit);
                    const Image b = r->renderToImage(camera, 640, 480, points);
                    std::size_t covered = 0, missed = 0, extra = 0, shadedAlike = 0;
                    for (int y = 0; y < a.height; ++y)
                        for (int x = 0; x < a.width; ++x) {
                            const bool inA = differs(a.at(x, y), bg, 2), inB = differs(b.at(x, y), bg, 2);
                            covered += inA;
                            missed += inA && !inB;
                            extra += inB && !inA;
                            shadedAlike += inA && inB && !differs(a.at(x, y), b.at(x, y), 24);
                        }
                    std::printf("%zu pixels covered: points miss %zu, add %zu; %zu shaded alike\n", covered, missed, extra,
                                shadedAlike);
                    EXPECT_GT(covered, 640u * 480u / 8);
                    EXPECT_LT(double(missed), 0.03 * double(covered)) << "holes between the discs";
                    EXPECT_LT(double(extra), 0.06 * double(covered)) << "discs beyond the silhouette";
                    EXPECT_GT(double(shadedAlike), 0.8 * double(covered)) << "points are lit unlike the clay";
                }
    }
    EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
}

TEST_F(ClayRenderTest, GroundShowsFromAboveOnly) {
    ClayRenderer renderer(shaders());
    renderer.setMesh(test::icosphere(0.1f, 4));
    RenderSettings plain, ground;
    ground.ground = true;
    const glm::u8vec4 bg = backgroundOf(plain.backgroundSrgb);
    for (ViewAxis v : {ViewAxis::Iso, ViewAxis::Bottom}) {
        SCOPED_TRACE(nameOf(v));
        OrbitCamera camera;
        camera.setView(v);
        camera.frame(glm::vec3(-0.1f), glm::vec3(0.1f), 1.0f);
        const Image a = renderer.renderToImage(camera, 128, 128, plain);
        const Image b = renderer.renderToImage(camera, 128, 128, ground);
        EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
        std::size_t changedOnBackground = 0, changedOnModel = 0, model = 0;
        for (int y = 0; y < a.height; ++y)
            for (int x = 0; x < a.width; ++x) {
                model += differs(a.at(x, y), bg, 0) ? 1 : 0;
                if (!differs(a.at(x, y), b.at(x, y), 2)) continue;
                (differs(a.at(x, y), bg, 0) ? changedOnModel : changedOnBackground)++;
            }
        // Only silhouette pixels (partly covered: their samples behind the model see the floor).
        EXPECT_LT(changedOnModel, model / 20) << "the floor changed the model's pixels";
        EXPECT_FALSE(differs(a.at(64, 64), b.at(64, 64), 0));
        if (v == ViewAxis::Bottom)
            EXPECT_EQ(changedOnBackground, 0u) << "the floor is drawn from below";
        else
            EXPECT_GT(changedOnBackground, 1000u) << "no floor";
    }
}

TEST_F(ClayRenderTest, TheToolsRingAndItsFloorSpotShowWhereTheToolIs) {
    // The tool at the top of a sphere seen from the front, with the floor: the ring's pixels
    // change about the sphere's top, the floor spot's under the sphere (behind it: hidden) or
    // beside it; nothing changes in the image's lower left corner far from both.
    ClayRenderer renderer(shaders());
    const float r = 0.1f;
    renderer.setMesh(test::icosphere(r, 4));
    OrbitCamera camera;
    camera.setView(ViewAxis::Front);
    camera.pitchRad = 0.3f;  // a little above, so the floor shows
    camera.frame(glm::vec3(-r), glm::vec3(r), 1.0f);
    RenderSettings settings;
    settings.ground = true;
    ToolMark tool;
    tool.centre = glm::vec3(0.0f, 0.0f, r);
    tool.normal = glm::vec3(0.0f, 0.0f, 1.0f);
    tool.radius = 0.03f;
    const int n = 200;
    const Image a = renderer.renderToImage(camera, n, n, settings);
    const Image b = renderer.renderToImage(camera, n, n, settings, &tool);
    EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
    // Where the tool's centre lands on screen.
    const glm::vec4 clip = camera.projectionMatrix(1.0f) * camera.viewMatrix() * glm::vec4(tool.centre, 1.0f);
    const glm::vec2 px((clip.x / clip.w * 0.5f + 0.5f) * n, (0.5f - clip.y / clip.w * 0.5f) * n);
    std::size_t nearTool = 0, farCorner = 0;
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            if (!differs(a.at(x, y), b.at(x, y), 8)) continue;
            if (glm::length(glm::vec2(x, y) - px) < 0.35f * n) ++nearTool;
            if (x < n / 6 && y > 5 * n / 6) ++farCorner;
        }
    EXPECT_GT(nearTool, 50u) << "the ring shows about the tool";
    EXPECT_EQ(farCorner, 0u);
}

TEST_F(ClayRenderTest, EmptyMeshClearsToBackground) {
    ClayRenderer renderer(shaders());
    renderer.setMesh(mesh::MeshBuffers{});
    OrbitCamera camera;
    RenderSettings s;
    const Image image = renderer.renderToImage(camera, 64, 48, s);
    EXPECT_EQ(countNot(image, backgroundOf(s.backgroundSrgb), 0), 0u);
}

TEST_F(ClayRenderTest, PngRoundTrip) {
    ClayRenderer renderer(shaders());
    renderer.setMesh(test::icosphere(0.1f, 2));
    OrbitCamera camera;
    camera.frame(glm::vec3(-0.1f), glm::vec3(0.1f), 1.5f);
    const Image image = renderer.renderToImage(camera, 96, 64, RenderSettings{});
    const fs::path path =
        fs::temp_directory_path() / ("kizamu-render-" + std::to_string(::getpid()) + ".png");
    writePng(path.string(), image);
    const Image back = readPng(path.string());
    EXPECT_EQ(back.width, 96);
    EXPECT_EQ(back.height, 64);
    EXPECT_EQ(back.pixels, image.pixels);
    fs::remove(path);
}

/// The reference comparison: the level-7 test part from the iso view, lit, 256 × 256.
/// KIZAMU_WRITE_REFERENCES=1 rewrites the reference instead (look at it before committing).
TEST(ClayRenderReference, TestPartLevel7MatchesReference) {
    setenv("LP_NUM_THREADS", "2", 0);
    util::ThreadPool pool(2);
    const adf::Domain d = adf::testPartDomain(7);
    const mesh::MeshBuffers m = mesh::meshAdf(
        adf::generate(*adf::makeTestPart(d), d, adf::testPartSettings(), &pool), &pool);
    OffscreenView view;
    view.width = view.height = 256;
    view.view = ViewAxis::Iso;
    view.shaderDirectory = KIZAMU_SOURCE_SHADER_DIR;
    const Image actual = renderMeshImage(m, view);

    const fs::path reference =
        fs::path(KIZAMU_SOURCE_DIR) / "tests/data/render/test_part_level7_iso.png";
    if (const char* w = std::getenv("KIZAMU_WRITE_REFERENCES"); w && std::string(w) == "1") {
        writePng(reference.string(), actual);
        GTEST_SKIP() << "wrote " << reference;
    }
    const Image expected = readPng(reference.string());
    ASSERT_EQ(expected.width, actual.width);
    ASSERT_EQ(expected.height, actual.height);
    double sumAbs = 0.0;
    std::size_t far = 0;
    for (std::size_t i = 0; i < actual.pixels.size(); i += 4) {
        int worst = 0;
        for (int c = 0; c < 3; ++c) {
            const int diff = std::abs(int(actual.pixels[i + c]) - int(expected.pixels[i + c]));
            sumAbs += diff;
            worst = std::max(worst, diff);
        }
        far += worst > 16 ? 1 : 0;
    }
    const double pixels = double(actual.width) * actual.height;
    const double meanAbs = sumAbs / (pixels * 3.0);
    const double farFraction = double(far) / pixels;
    std::printf(
        "reference %s: mean |difference| %.3f/255, %.3f%% of pixels off by more than 16/255\n",
        reference.filename().c_str(), meanAbs, 100.0 * farFraction);
    if (meanAbs >= 2.0 || farFraction >= 0.01) {
        const fs::path out = fs::path(KIZAMU_RENDER_ACTUAL_DIR) / "test_part_level7_iso.actual.png";
        fs::create_directories(out.parent_path());
        writePng(out.string(), actual);
        ADD_FAILURE()
            << "the render differs from the reference " << reference << ": mean |difference| "
            << meanAbs << "/255 (limit 2), " << 100.0 * farFraction
            << "% of pixels off by more than 16/255 (limit 1%). The render is at " << out
            << "; if the change is meant, look at it and rerun with KIZAMU_WRITE_REFERENCES=1.";
    }
}

}  // namespace
}  // namespace kizamu::render
