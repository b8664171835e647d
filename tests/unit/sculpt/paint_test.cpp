// SPDX-License-Identifier: Apache-2.0
// The paint tool: colours where the stroke meets the surface, opacity, untouched distance tiles,
// undo/redo, carving after painting, mirrored paint, incremental meshes with colours, scripts.
#include "sculpt/paint.h"
#include "sculpt/script_start.h"
#include "sculpt/sculptor.h"
#include "sculpt/stroke_script.h"

#include "adf/adf_file.h"
#include "adf/colour_layer.h"
#include "mesh/surface_nets.h"
#include "tests/util/adf_compare.h"
#include "tests/util/mesh_check.h"
#include "util/file_error.h"
#include "util/thread_pool.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

namespace kizamu {
namespace {

using namespace sculpt;

const glm::dquat kIdentity(1.0, 0.0, 0.0, 0.0);  // glm's default constructor leaves it uninitialised
const adf::Rgb8 kRed(220, 30, 40);

/// A slab whose top face is the plane z = 0.5 (x, y in [0.15, 0.85]).
Script slab(int level) {
    Script s;
    s.domain.maxLevel = level;
    s.domain.tileSpanLevels = 4;
    s.start.kind = Shape::Kind::Box;
    s.start.centre = {0.5, 0.5, 0.4};
    s.start.halfSize = {0.35, 0.35, 0.1};
    return s;
}

Stroke paintDab(const glm::dvec3& at, double radius, adf::Rgb8 colour, double strength = 1.0) {
    Stroke s;
    s.tool.op = ToolOp::Paint;
    s.tool.radius = radius;
    s.tool.strength = strength;
    s.tool.colour = colour;
    s.samples = {{at, kIdentity}};
    return s;
}

/// Vertices of `m` on the top face (z near 0.5) within `r` of (x, y), or beyond `r` when `outside`.
std::vector<std::size_t> topVertices(const mesh::MeshBuffers& m, glm::dvec2 c, double r, bool outside) {
    std::vector<std::size_t> out;
    for (std::size_t i = 0; i < m.vertexCount(); ++i) {
        const glm::vec3 p = m.positions[i];
        if (std::abs(p.z - 0.5f) > 0.01f) continue;
        const double d = glm::distance(glm::dvec2(p.x, p.y), c);
        if (outside ? d > r : d < r) out.push_back(i);
    }
    return out;
}

/// The material's colour on the top face (z = 0.5) at the points of a fine grid (a quarter of a
/// finest cell at level 7) within `r` of `c`, or between `r` and 0.25 from it when `outside`:
/// where any mesh vertex could sit (the flat face's big cells hold few vertices).
std::vector<adf::Rgb8> faceColours(const adf::Adf& a, glm::dvec2 c, double r, bool outside) {
    std::vector<adf::Rgb8> out;
    EXPECT_NE(a.colours(), nullptr);
    if (!a.colours()) return out;
    const double step = 1.0 / 512.0, reach = outside ? 0.25 : r;
    for (double y = c.y - reach; y <= c.y + reach; y += step)
        for (double x = c.x - reach; x <= c.x + reach; x += step) {
            const double d = glm::distance(glm::dvec2(x, y), c);
            if (outside ? (d > r && d < reach) : d < r) out.push_back(a.colours()->colourAt(glm::vec3(float(x), float(y), 0.5f)));
        }
    return out;
}

/// Every entry of `colours` is `want` (and there are some).
::testing::AssertionResult allAre(const std::vector<adf::Rgb8>& colours, adf::Rgb8 want, float tolerance = 0.0f) {
    if (colours.empty()) return ::testing::AssertionFailure() << "no points";
    for (std::size_t i = 0; i < colours.size(); ++i)
        if (glm::length(glm::vec3(colours[i]) - glm::vec3(want)) > tolerance)
            return ::testing::AssertionFailure() << "point " << i << " of " << colours.size() << " is (" << int(colours[i].r) << ", "
                                                 << int(colours[i].g) << ", " << int(colours[i].b) << ")";
    return ::testing::AssertionSuccess();
}

TEST(Paint, VerticesInsideTheStrokeGetThePaintAndFarOnesKeepTheClayColour) {
    util::ThreadPool pool;
    const Script script = slab(7);
    Sculptor s(startAdf(script, 0, &pool), &pool);
    EXPECT_TRUE(mesh::meshAdf(s.current(), &pool).colours.empty()) << "unpainted clay has no colours";
    // A stroke along x on the top face: the core (weight 1) is within half the radius of the path.
    Stroke st = paintDab({0.4, 0.5, 0.5}, 0.06, kRed);
    st.samples.push_back({{0.6, 0.5, 0.5}, kIdentity});
    s.apply(st);
    EXPECT_EQ(s.lastEdit().tilesRebuilt, 0u);
    EXPECT_GT(s.lastEdit().colourTilesPainted, 0u);
    const mesh::MeshBuffers m = mesh::meshAdf(s.current(), &pool);
    ASSERT_EQ(m.colours.size(), m.vertexCount());
    std::size_t core = 0, far = 0;
    for (std::size_t i = 0; i < m.vertexCount(); ++i) {
        const glm::vec3 p = m.positions[i];
        if (std::abs(p.z - 0.5f) > 0.01f) continue;
        const double along = std::clamp(double(p.x), 0.4, 0.6);
        const double d = glm::distance(glm::dvec2(p.x, p.y), glm::dvec2(along, 0.5));
        if (d < 0.02) {
            EXPECT_EQ(m.colours[i], kRed) << "vertex " << i << " at " << p.x << "," << p.y;
            ++core;
        } else if (d > 0.07) {
            EXPECT_EQ(m.colours[i], adf::kClayColour) << "vertex " << i << " at " << p.x << "," << p.y;
            ++far;
        }
    }
    EXPECT_GT(core + far, 10u);
    // Everywhere a vertex could sit: the core of each end of the stroke and its middle, and
    // around it.
    for (const glm::dvec2 c : {glm::dvec2(0.4, 0.5), glm::dvec2(0.5, 0.5), glm::dvec2(0.6, 0.5)})
        EXPECT_TRUE(allAre(faceColours(*s.current(), c, 0.02, false), kRed));
    EXPECT_TRUE(allAre(faceColours(*s.current(), {0.5, 0.5}, 0.1 + 0.06 + 0.015, true), adf::kClayColour));
    // The slab's underside (z = 0.3) is far from the stroke: clay.
    for (std::size_t i = 0; i < m.vertexCount(); ++i)
        if (m.positions[i].z < 0.31f) {
            EXPECT_EQ(m.colours[i], adf::kClayColour);
        }
}

TEST(Paint, HalfStrengthBlendsHalfwayAndASecondPassCloser) {
    util::ThreadPool pool;
    Sculptor s(startAdf(slab(7), 0, &pool), &pool);
    s.apply(paintDab({0.5, 0.5, 0.5}, 0.06, kRed, 0.5));
    const glm::vec3 half = 0.5f * (glm::vec3(adf::kClayColour) + glm::vec3(kRed));
    EXPECT_TRUE(allAre(faceColours(*s.current(), {0.5, 0.5}, 0.02, false), adf::Rgb8(glm::round(half)), 1.0f));
    const mesh::MeshBuffers m = mesh::meshAdf(s.current(), &pool);
    for (std::size_t i : topVertices(m, {0.5, 0.5}, 0.02, false)) EXPECT_LE(glm::length(glm::vec3(m.colours[i]) - half), 1.0f) << "vertex " << i;
    s.apply(paintDab({0.5, 0.5, 0.5}, 0.06, kRed, 0.5));  // half of what is left
    const glm::vec3 threeQuarters = 0.25f * glm::vec3(adf::kClayColour) + 0.75f * glm::vec3(kRed);
    EXPECT_TRUE(allAre(faceColours(*s.current(), {0.5, 0.5}, 0.02, false), adf::Rgb8(glm::round(threeQuarters)), 1.5f));
    // Nothing beyond the tool, but for the blend of a lattice cell (√3 / 128 m) at its rim.
    EXPECT_TRUE(allAre(faceColours(*s.current(), {0.5, 0.5}, 0.06 + 0.014, true), adf::kClayColour)) << "nothing beyond the tool";
}

TEST(Paint, ChangesNoDistanceTileAndUndoRedoSwapThePaint) {
    util::ThreadPool pool;
    const adf::AdfPtr start = startAdf(slab(7), 0, &pool);
    Sculptor s(start, &pool);
    s.apply(paintDab({0.5, 0.5, 0.5}, 0.05, kRed));
    const adf::AdfPtr painted = s.current();
    ASSERT_NE(painted->colours(), nullptr);
    EXPECT_EQ(start->colours(), nullptr);
    const uint32_t n = start->domain().slotsPerAxis();
    for (uint32_t z = 0; z < n; ++z)
        for (uint32_t y = 0; y < n; ++y)
            for (uint32_t x = 0; x < n; ++x)
                ASSERT_EQ(painted->tileAtSlot({x, y, z}), start->tileAtSlot({x, y, z})) << "paint shares every distance tile";
    ASSERT_TRUE(s.undo());
    EXPECT_EQ(s.current(), start);
    EXPECT_TRUE(mesh::meshAdf(s.current(), &pool).colours.empty()) << "undo removes the paint";
    ASSERT_TRUE(s.redo());
    EXPECT_EQ(s.current(), painted);
    const mesh::MeshBuffers m = mesh::meshAdf(s.current(), &pool);
    for (std::size_t i : topVertices(m, {0.5, 0.5}, 0.015, false)) EXPECT_EQ(m.colours[i], kRed) << "redo restores it";
    // A second stroke elsewhere copies only the colour tiles it touches.
    s.apply(paintDab({0.25, 0.25, 0.5}, 0.03, {10, 200, 10}));
    const adf::ColourLayer& before = *painted->colours();
    const adf::ColourLayer& after = *s.current()->colours();
    std::size_t shared = 0;
    for (std::size_t i = 0; i < before.slotCount(); ++i) shared += after.tileAt(before.slotKeys()[i]) == before.tiles()[i].get();
    EXPECT_GT(shared, 0u);
    EXPECT_GT(after.slotCount(), before.slotCount());
}

TEST(Paint, CarvingAfterPaintingKeepsThePaintOnUntouchedSurface) {
    util::ThreadPool pool;
    Sculptor s(startAdf(slab(7), 0, &pool), &pool);
    Stroke wide = paintDab({0.5, 0.5, 0.5}, 0.12, kRed);
    s.apply(wide);
    const auto layer = s.current()->colours();
    Stroke carve;
    carve.tool.radius = 0.03;
    carve.samples = {{{0.5, 0.5, 0.5}, kIdentity}};
    s.apply(carve);
    EXPECT_GT(s.lastEdit().tilesRebuilt, 0u);
    EXPECT_EQ(s.current()->colours(), layer) << "a carve carries the colour layer unchanged";
    const mesh::MeshBuffers m = mesh::meshAdf(s.current(), &pool);
    // Top face between the hole's rim and the edge of the paint's core: still red.
    std::size_t red = 0, other = 0;
    for (double a = 0.0; a < 6.28; a += 0.05)
        for (double r = 0.036; r < 0.055; r += 0.002) {
            const adf::Rgb8 c = s.current()->colours()->colourAt(glm::vec3(float(0.5 + r * std::cos(a)), float(0.5 + r * std::sin(a)), 0.5f));
            (c == kRed ? red : other)++;
        }
    EXPECT_GT(red, 100u);
    EXPECT_EQ(other, 0u);
    for (std::size_t i : topVertices(m, {0.5, 0.5}, 0.036, true))
        if (glm::distance(glm::dvec2(m.positions[i].x, m.positions[i].y), glm::dvec2(0.5)) < 0.055) {
            EXPECT_EQ(m.colours[i], kRed) << "vertex " << i;
        }
    // The bottom of the hole (3 cm down, far deeper than the painted shell) is bare clay.
    std::size_t bottom = 0;
    for (std::size_t i = 0; i < m.vertexCount(); ++i)
        if (m.positions[i].z < 0.48f && glm::distance(glm::dvec2(m.positions[i].x, m.positions[i].y), glm::dvec2(0.5)) < 0.01) {
            EXPECT_EQ(m.colours[i], adf::kClayColour) << "vertex " << i;
            ++bottom;
        }
    EXPECT_GT(bottom, 0u);
}

TEST(Paint, MirroredPaintColoursEveryCopy) {
    util::ThreadPool pool;
    Sculptor s(startAdf(slab(7), 0, &pool), &pool);
    Stroke st = paintDab({0.3, 0.35, 0.5}, 0.04, kRed);
    st.mirror = 0b011;
    s.apply(st);
    EXPECT_EQ(s.undoDepth(), 1u);
    const mesh::MeshBuffers m = mesh::meshAdf(s.current(), &pool);
    for (const glm::dvec2 c : {glm::dvec2(0.3, 0.35), glm::dvec2(0.7, 0.35), glm::dvec2(0.3, 0.65), glm::dvec2(0.7, 0.65)}) {
        // The core is half the radius (0.02); a point's blend reaches a cell (0.011 m) further.
        EXPECT_TRUE(allAre(faceColours(*s.current(), c, 0.008, false), kRed)) << c.x << "," << c.y;
        for (std::size_t i : topVertices(m, c, 0.008, false)) EXPECT_EQ(m.colours[i], kRed) << c.x << "," << c.y;
    }
    EXPECT_TRUE(allAre(faceColours(*s.current(), {0.5, 0.5}, 0.05, false), adf::kClayColour));
}

TEST(Paint, IncrementalMeshEqualsAFullMeshWithColours) {
    util::ThreadPool pool(3);
    Sculptor s(startAdf(slab(7), 0, &pool), &pool);
    mesh::SurfaceMesher mesher(&pool);
    mesher.build(s.current());
    Stroke carve;
    carve.tool.radius = 0.025;
    carve.samples = {{{0.45, 0.5, 0.5}, kIdentity}};
    Stroke onEdge = paintDab({0.15, 0.5, 0.5}, 0.05, {0, 0, 255});  // the slab's top edge
    onEdge.samples.push_back({{0.15, 0.7, 0.5}, kIdentity});
    for (const Stroke& st : {paintDab({0.5, 0.5, 0.5}, 0.06, kRed), carve, onEdge, paintDab({0.45, 0.5, 0.48}, 0.03, {0, 255, 0}, 0.7)}) {
        s.apply(st);
        mesher.update(s.current());
        const mesh::MeshBuffers spliced = mesher.mesh(), fresh = mesh::meshAdf(s.current(), &pool);
        ASSERT_EQ(spliced.colours.size(), spliced.vertexCount());
        EXPECT_TRUE(test::canonical(spliced) == test::canonical(fresh)) << opName(st.tool.op);
    }
    ASSERT_TRUE(s.undo());
    mesher.update(s.current());
    EXPECT_TRUE(test::canonical(mesher.mesh()) == test::canonical(mesh::meshAdf(s.current(), &pool)));
}

TEST(Paint, ScriptsCarryTheColourAndReplayIdenticallyOnAnyThreadCount) {
    Script script = slab(6);
    Stroke a = paintDab({0.4, 0.4, 0.5}, 0.05, kRed, 0.6);
    a.samples.push_back({{0.6, 0.45, 0.5}, kIdentity});
    a.tool.shape = ToolShape::Cube;
    Stroke b = paintDab({0.5, 0.5, 0.5}, 0.03, {1, 2, 3});
    b.tool.shape = ToolShape::Cylinder;
    b.tool.halfLength = 0.02;
    b.mirror = 0b001;
    Stroke carve;
    carve.tool.radius = 0.02;
    carve.samples = {{{0.5, 0.45, 0.5}, kIdentity}};
    script.add(a);
    script.add(carve);
    script.add(b);
    const Script r = parseScript(formatScript(script), "mem");
    ASSERT_EQ(r.steps.size(), 3u);
    EXPECT_EQ(r.steps[0].stroke.tool.op, ToolOp::Paint);
    EXPECT_EQ(r.steps[0].stroke.tool.colour, kRed);
    EXPECT_EQ(r.steps[2].stroke.tool.colour, adf::Rgb8(1, 2, 3));
    EXPECT_EQ(formatScript(r), formatScript(script));
    util::ThreadPool pool(3);
    auto replay = [&](util::ThreadPool* p) {
        Sculptor sc(startAdf(r, 0, p), p);
        for (const Step& st : r.steps) sc.replay(st);
        return sc.current();
    };
    const adf::AdfPtr x = replay(&pool), y = replay(nullptr), z = replay(&pool);
    EXPECT_TRUE(test::sameAdf(*x, *y));
    ASSERT_NE(x->colours(), nullptr);
    EXPECT_GT(x->colours()->pointCount(), 100u);
    EXPECT_EQ(adf::encodeAdf(*x), adf::encodeAdf(*y)) << "paint does not depend on threads";
    EXPECT_EQ(adf::encodeAdf(*x), adf::encodeAdf(*z)) << "replaying twice gives the same bytes";

    // Readable errors for bad colours, naming the line.
    const std::string header = headerLine(script) + "\n";
    auto error = [&](const std::string& stroke) {
        try {
            parseScript(header + stroke + "\n", "p.jsonl");
        } catch (const FileError& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    const std::string dab = R"("op": "paint", "shape": "sphere", "radius": 0.1, "path": [[0.5, 0.5, 0.5]])";
    EXPECT_NE(error("{" + dab + "}").find("line 2: paint needs a \"color\""), std::string::npos) << error("{" + dab + "}");
    for (const char* bad : {"[256, 0, 0]", "[-1, 0, 0]", "[1.5, 0, 0]", "[1, 2]", "\"red\"", "[1, 2, \"3\"]"}) {
        const std::string msg = error("{" + dab + ", \"color\": " + bad + "}");
        EXPECT_NE(msg.find("line 2: color must be [r, g, b] with integers 0-255"), std::string::npos) << bad << ": " << msg;
    }
    EXPECT_EQ(error("{" + dab + ", \"color\": [0, 128, 255]}"), "no error");
}

}  // namespace
}  // namespace kizamu
