// SPDX-License-Identifier: Apache-2.0
// The ray under the cursor traced into the clay, and the mouse as the stylus's hand: hits land
// on the (offset) surface, misses miss, the wheel sets the depth, Ctrl and Shift choose the
// stroke's op at the press, the lazy mouse trails the cursor, and a stroke driven through the
// live engine carves where the cursor went and no deeper where it stays.
#include "interact/mouse_tool.h"
#include "interact/surface_ray.h"

#include "engine/engine.h"
#include "sculpt/script_start.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <thread>

namespace kizamu {
namespace {

constexpr double kR = 0.3;  ///< the sphere's radius in a 1 m domain centred on the origin

sculpt::Script sphereScript(int level) {
    sculpt::Script s;
    s.domain.originWorld = glm::dvec3(-0.5);
    s.domain.sizeWorld = 1.0;
    s.domain.maxLevel = level;
    s.start.kind = sculpt::Shape::Kind::Sphere;
    s.start.centre = glm::dvec3(0.0);
    s.start.radius = kR;
    return s;
}

TEST(SurfaceRay, HitsTheSphereAndItsOffsetSurfaceAndMissesBesideIt) {
    const adf::AdfPtr clay = sculpt::startAdf(sphereScript(7), 0);
    adf::AdfAccessor a(*clay);
    const double eps = 2.0 * clay->domain().finestCellSize();
    // Straight down from far above (outside the domain): the top of the sphere.
    auto hit = interact::traceRay(a, clay->domain(), {0.0, 0.0, 3.0}, {0.0, 0.0, -2.0});
    ASSERT_TRUE(hit);
    EXPECT_NEAR(hit->point.z, kR, eps);
    EXPECT_NEAR(hit->t, 3.0 - kR, eps);
    EXPECT_GT(hit->normal.z, 0.99);
    // An oblique ray through the centre: the near side.
    const glm::dvec3 from(0.45, -0.45, 0.2);
    hit = interact::traceRay(a, clay->domain(), from, -from);
    ASSERT_TRUE(hit);
    EXPECT_NEAR(glm::length(hit->point), kR, eps);
    EXPECT_GT(glm::dot(hit->point, from), 0.0);
    // The offset surface 5 cm out.
    interact::RayTraceSettings off;
    off.offset = 0.05;
    hit = interact::traceRay(a, clay->domain(), {0.0, 0.0, 3.0}, {0.0, 0.0, -1.0}, off);
    ASSERT_TRUE(hit);
    EXPECT_NEAR(hit->point.z, kR + 0.05, eps);
    // Misses: beside the sphere, pointing away, from inside, a degenerate direction.
    EXPECT_FALSE(interact::traceRay(a, clay->domain(), {0.4, 0.0, 3.0}, {0.0, 0.0, -1.0}));
    EXPECT_FALSE(interact::traceRay(a, clay->domain(), {0.0, 0.0, 3.0}, {0.0, 0.0, 1.0}));
    EXPECT_FALSE(interact::traceRay(a, clay->domain(), {0.0, 0.0, 0.0}, {0.0, 0.0, 1.0}));
    EXPECT_FALSE(interact::traceRay(a, clay->domain(), {0.0, 0.0, 3.0}, {0.0, 0.0, 0.0}));
    // Grazing: a ray tangent to the sphere's top just above it misses, just below hits.
    EXPECT_FALSE(interact::traceRay(a, clay->domain(), {-0.6, 0.0, kR + 0.01}, {1.0, 0.0, 0.0}));
    EXPECT_TRUE(interact::traceRay(a, clay->domain(), {-0.6, 0.0, kR - 0.01}, {1.0, 0.0, 0.0}));
}

TEST(MouseTool, ModifiersChooseTheStrokesOpAtThePress) {
    using sculpt::ToolOp;
    EXPECT_EQ(interact::MouseTool::strokeOp(ToolOp::Carve, true, false), ToolOp::Add);
    EXPECT_EQ(interact::MouseTool::strokeOp(ToolOp::Add, true, false), ToolOp::Carve);
    EXPECT_EQ(interact::MouseTool::strokeOp(ToolOp::Build, true, false), ToolOp::HeatGun);
    EXPECT_EQ(interact::MouseTool::strokeOp(ToolOp::Paint, true, false), ToolOp::Paint);
    EXPECT_EQ(interact::MouseTool::strokeOp(ToolOp::Carve, false, true), ToolOp::Smooth);
    EXPECT_EQ(interact::MouseTool::strokeOp(ToolOp::Carve, false, false), ToolOp::Carve);

    const adf::AdfPtr clay = sculpt::startAdf(sphereScript(7), 0);
    adf::AdfAccessor a(*clay);
    interact::MouseTool tool;
    interact::MouseInput in;
    in.hasRay = true;
    in.rayOrigin = {0.0, 0.0, 3.0};
    in.rayDirection = {0.0, 0.0, -1.0};
    in.primary = true;
    in.ctrl = true;
    interact::MouseToolFrame f = tool.update(in, a, clay->domain());
    EXPECT_TRUE(f.strokeBegan && f.stroking);
    EXPECT_EQ(f.op, ToolOp::Add);
    in.ctrl = false;  // letting go of Ctrl mid-stroke does not change the stroke
    f = tool.update(in, a, clay->domain());
    EXPECT_FALSE(f.strokeBegan);
    EXPECT_EQ(f.op, ToolOp::Add);
    in.primary = false;
    f = tool.update(in, a, clay->domain());
    EXPECT_TRUE(f.strokeEnded);
    EXPECT_FALSE(f.stroking);
    // A press off the clay starts nothing.
    in.primary = true;
    in.rayOrigin = {0.45, 0.0, 3.0};
    f = tool.update(in, a, clay->domain());
    EXPECT_FALSE(f.strokeBegan || f.stroking || f.hasTarget);
}

TEST(MouseTool, TheWheelSetsTheDepthAndTheLazyMouseTrailsTheCursor) {
    const adf::AdfPtr clay = sculpt::startAdf(sphereScript(7), 0);
    adf::AdfAccessor a(*clay);
    interact::MouseToolSettings ms;
    ms.lazyRadius = 0.05;
    interact::MouseTool tool(ms);
    sculpt::Tool t;
    t.radius = 0.04;
    tool.setTool(t);
    interact::MouseInput in;
    in.hasRay = true;
    in.rayOrigin = {0.0, 0.0, 3.0};
    in.rayDirection = {0.0, 0.0, -1.0};
    in.wheel = -3.0;  // three notches down: the centre 0.3 radii below the surface
    interact::MouseToolFrame f = tool.update(in, a, clay->domain());
    EXPECT_NEAR(tool.depth(), -0.3, 1e-12);
    EXPECT_NEAR(f.followOffset, -0.012, 1e-12);
    EXPECT_NEAR(f.target.z, kR - 0.012, 0.01);
    in.wheel = -100.0;
    tool.update(in, a, clay->domain());
    EXPECT_EQ(tool.depth(), -1.0) << "clamped";
    tool.setDepth(0.0);
    in.wheel = 0.0;
    // Stroke: the cursor moves 3 cm along x; the tool stays (within the 5 cm string), then the
    // cursor moves 10 cm and the tool trails it by the string's length.
    in.primary = true;
    f = tool.update(in, a, clay->domain());
    const glm::dvec3 start = f.target;
    in.rayOrigin = {0.03, 0.0, 3.0};
    f = tool.update(in, a, clay->domain());
    EXPECT_NEAR(glm::length(f.target - start), 0.0, 1e-9);
    in.rayOrigin = {0.10, 0.0, 3.0};
    f = tool.update(in, a, clay->domain());
    const double cursorX = 0.10;
    EXPECT_NEAR(cursorX - f.target.x, 0.05 * std::abs(f.normal.z) + 0.0, 0.01);
    EXPECT_GT(f.target.x, 0.04);
}

TEST(MouseTool, AStrokeThroughTheEngineCarvesWhereTheCursorWentAndNoDeeperWhereItStays) {
    engine::EngineSettings es;
    es.start = sphereScript(8);
    es.threads = 2;
    es.correctAfterIdle = std::chrono::milliseconds(0);
    engine::Engine e(es);
    interact::MouseTool tool;
    sculpt::Tool carve;
    carve.radius = 0.03;
    tool.setTool(carve);
    adf::SnapshotStore::Reader reader(e.snapshots());
    interact::MouseInput in;
    in.hasRay = true;
    in.rayDirection = {0.0, 0.0, -1.0};
    int64_t tNs = 0;
    // 60 frames a second: the cursor drags 10 cm along x over the top, then stays 1 s.
    for (int frame = 0; frame < 150; ++frame) {
        const double x = -0.05 + 0.1 * std::min(1.0, frame / 60.0);
        in.rayOrigin = {x, 0.0, 3.0};
        in.primary = frame < 140;
        in.timeS = frame / 60.0;
        interact::MouseToolFrame f;
        {
            const auto guard = reader.acquire();
            adf::AdfAccessor a(guard.adf());
            f = tool.update(in, a, guard.adf().domain());
        }
        if (f.strokeBegan) {
            engine::ToolSettings ts;
            ts.tool = carve;
            ts.tool.op = f.op;
            ts.constraints.followOffset = f.followOffset;
            ASSERT_TRUE(e.setTool(ts).get().ok);
        }
        if (!f.hasTarget) continue;
        engine::ToolSample s;
        s.timeNs = tNs += 16'666'667;
        s.posWorld = f.target;
        s.buttons = f.stroking ? engine::kButtonPrimary : 0u;
        while (!e.samples().push(s)) std::this_thread::yield();
        e.sync().get();
    }
    while (!e.samples().flush()) std::this_thread::yield();
    ASSERT_TRUE(e.sync().get().ok);
    EXPECT_EQ(e.stats().strokes, 1u);
    const auto guard = reader.acquire();
    const adf::Adf& clay = guard.adf();
    // Along the path the top is a groove about the tool's radius deep (the centre rode the
    // original surface), the same depth where the cursor stayed for over a second (without the
    // stroke's surface-following constraint each frame's ray meets the groove's floor and the
    // tool drills through the sphere); beside it the sphere is untouched.
    const auto topAt = [&](double x, double y) {
        const auto hit = [&] {
            adf::AdfAccessor a(clay);
            return interact::traceRay(a, clay.domain(), {x, y, 3.0}, {0.0, 0.0, -1.0});
        }();
        return hit ? hit->point.z : -1.0;
    };
    for (const double x : {-0.03, 0.0, 0.03, 0.05}) {
        const double depth = std::sqrt(kR * kR - x * x) - topAt(x, 0.0);
        EXPECT_GT(depth, 0.02) << "x " << x;
        EXPECT_LT(depth, 0.04) << "x " << x << ": no deeper than the radius and a cell or two";
    }
    EXPECT_NEAR(topAt(0.0, 0.1), std::sqrt(kR * kR - 0.01), 0.003) << "beside the groove";
}

}  // namespace
}  // namespace kizamu
