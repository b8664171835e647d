// SPDX-License-Identifier: Apache-2.0
// Bezier tool paths (Kizamu 4.2) and distance-based constraints (Kizamu 4.4): surface
// following at an offset, depth and height limits, masks and keep-out force fields.
#include "sculpt/bezier_path.h"
#include "sculpt/force_field.h"
#include "sculpt/script_start.h"
#include "sculpt/sculptor.h"
#include "sculpt/stroke_path.h"
#include "sculpt/stroke_script.h"

#include "adf/colour_layer.h"
#include "adf/generate.h"
#include "mesh/surface_nets.h"
#include "util/thread_pool.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <cmath>

namespace kizamu {
namespace {

using namespace sculpt;

const glm::dquat kIdentity(1.0, 0.0, 0.0, 0.0);

double distanceToPolyline(const glm::dvec3& p, const std::vector<ToolSample>& line) {
    double best = 1e9;
    for (std::size_t i = 0; i + 1 < line.size(); ++i) {
        const glm::dvec3 a = line[i].position, ab = line[i + 1].position - a;
        const double t = glm::clamp(glm::dot(p - a, ab) / std::max(1e-30, glm::dot(ab, ab)), 0.0, 1.0);
        best = std::min(best, glm::length(p - (a + t * ab)));
    }
    return best;
}

TEST(BezierPath, FlattensWithinTheToleranceAndKeepsStraightPathsShort) {
    const std::vector<ToolSample> controls = {
        {{0.1, 0.2, 0.5}, kIdentity}, {{0.3, 0.9, 0.5}, kIdentity}, {{0.7, -0.3, 0.6}, kIdentity}, {{0.9, 0.5, 0.4}, kIdentity}};
    const BezierControls c{controls[0].position, controls[1].position, controls[2].position, controls[3].position};
    for (double tol : {1e-2, 1e-3, 1e-4}) {
        const std::vector<ToolSample> line = bezierSamples(controls, tol);
        EXPECT_EQ(line.front().position, c[0]);
        EXPECT_EQ(line.back().position, c[3]);
        double worst = 0.0;
        for (int i = 0; i <= 5000; ++i) worst = std::max(worst, distanceToPolyline(bezierPoint(c, i / 5000.0), line));
        EXPECT_LE(worst, tol) << tol;
        EXPECT_LT(line.size(), std::size_t(8.0 / std::sqrt(tol)));  // O(1/sqrt(tol)) for a smooth curve
    }
    // Collinear control points: the curve is its chord, two poses.
    const BezierControls straight{glm::dvec3(0), glm::dvec3(0.2, 0, 0), glm::dvec3(0.5, 0, 0), glm::dvec3(1, 0, 0)};
    EXPECT_EQ(flattenBezier(straight, 1e-6).size(), 2u);
    EXPECT_THROW(flattenBezier(straight, 0.0), std::invalid_argument);
    // A straight curve whose tool turns keeps the turn: the controls' orientations are poses.
    const glm::dquat quarter = glm::angleAxis(1.5707963267948966, glm::dvec3(0, 0, 1));
    const std::vector<ToolSample> turning = {{straight[0], kIdentity}, {straight[1], quarter}, {straight[2], kIdentity}, {straight[3], quarter}};
    const std::vector<ToolSample> poses = bezierSamples(turning, 1e-6);
    ASSERT_EQ(poses.size(), 4u);
    EXPECT_EQ(poses[0].orientation, kIdentity);
    EXPECT_GT(std::abs(glm::dot(poses[1].orientation, quarter)), 1.0 - 1e-12);
    EXPECT_GT(std::abs(glm::dot(poses[2].orientation, kIdentity)), 1.0 - 1e-12);
    EXPECT_EQ(poses[3].orientation, quarter);
}

Script boxScript(int level) {
    Script s;
    s.domain.maxLevel = level;
    s.start.kind = Shape::Kind::Box;
    s.start.centre = {0.5, 0.5, 0.4};
    s.start.halfSize = {0.35, 0.35, 0.1};  // top face at z = 0.5
    return s;
}

Script sphereScript(int level) {
    Script s;
    s.domain.maxLevel = level;
    s.start.kind = Shape::Kind::Sphere;
    s.start.centre = glm::dvec3(0.5);
    s.start.radius = 0.3;
    return s;
}

Stroke sphereStroke(ToolOp op, double radius, std::vector<glm::dvec3> path) {
    Stroke s;
    s.tool.op = op;
    s.tool.radius = radius;
    for (const glm::dvec3& p : path) s.samples.push_back({p, kIdentity});
    return s;
}

/// Max |difference| of two fields near the surface of `a` (vertices and points beside them).
double fieldDifference(const adf::AdfPtr& a, const adf::AdfPtr& b) {
    double worst = 0.0;
    for (const glm::vec3& p : mesh::meshAdf(a).positions)
        for (const glm::vec3& off : {glm::vec3(0), glm::vec3(0.004f, 0, 0), glm::vec3(0, -0.004f, 0.003f)})
            worst = std::max(worst, double(std::abs(a->distance(p + off) - b->distance(p + off))));
    return worst;
}

TEST(BezierPath, ABezierStrokeCarvesTheCurveAsOneSweptVolume) {
    util::ThreadPool pool;
    auto s = makeSculptor(boxScript(7), 0, &pool);
    const adf::AdfPtr start = s->current();
    for (ToolShape shape : {ToolShape::Sphere, ToolShape::Cube}) {
        Stroke curve;
        curve.tool.shape = shape;
        curve.tool.radius = 0.025;
        curve.bezier = true;
        const glm::dquat tilt = glm::angleAxis(0.5, glm::dvec3(0, 0, 1));
        curve.samples = {{{0.2, 0.2, 0.5}, tilt}, {{0.3, 0.9, 0.5}, tilt}, {{0.7, 0.1, 0.5}, tilt}, {{0.8, 0.7, 0.5}, tilt}};
        Stroke dense = curve;
        dense.bezier = false;
        dense.samples.clear();
        const BezierControls c{curve.samples[0].position, curve.samples[1].position, curve.samples[2].position,
                               curve.samples[3].position};
        for (int i = 0; i <= 2000; ++i) dense.samples.push_back({bezierPoint(c, i / 2000.0), tilt});
        Sculptor a(start, &pool), b(start, &pool);
        a.apply(curve);
        b.apply(dense);
        const double eps = adf::GenerationSettings{}.errorBound(start->domain()).epsilon;
        EXPECT_LE(fieldDifference(a.current(), b.current()), eps) << shapeName(shape);
        // The groove follows the curve: carved at its points, not at the chord's middle.
        for (double t : {0.1, 0.35, 0.5, 0.8}) EXPECT_GT(a.current()->distance(glm::vec3(bezierPoint(c, t))), 0.0f) << t;
        EXPECT_LT(a.current()->distance(glm::vec3(0.5, 0.45, 0.47)), 0.0f);
    }
}

TEST(Constraints, FollowingAnOffsetSurfaceCarvesAGrooveOfConstantDepth) {
    util::ThreadPool pool;
    auto s = makeSculptor(sphereScript(8), 0, &pool);
    // A path drawn loosely around the sphere (radius 0.3), some poses outside, some inside.
    Stroke st = sphereStroke(ToolOp::Carve, 0.02, {});
    st.bezier = true;
    for (glm::dvec3 p : {glm::dvec3(0.5, 0.15, 0.5), glm::dvec3(0.95, 0.3, 0.55), glm::dvec3(0.9, 0.8, 0.45), glm::dvec3(0.5, 0.88, 0.5)})
        st.samples.push_back({p, kIdentity});
    st.constraints.followOffset = -0.01;
    const std::vector<ToolSample> path = resolvePath(st, *s->current(), 1e-4);
    for (const ToolSample& t : path) EXPECT_NEAR(glm::length(t.position - glm::dvec3(0.5)), 0.29, 2e-3);
    s->apply(st);
    // Along the path the groove bottom is at radius 0.29 − 0.02 = 0.27 everywhere.
    const double cell = s->current()->domain().finestCellSize();
    for (std::size_t i = 0; i < path.size(); i += 5) {
        const glm::dvec3 dir = glm::normalize(path[i].position - glm::dvec3(0.5));
        EXPECT_GT(s->current()->distance(glm::vec3(glm::dvec3(0.5) + (0.27 + 2 * cell) * dir)), 0.0f) << i;
        EXPECT_LT(s->current()->distance(glm::vec3(glm::dvec3(0.5) + (0.27 - 2 * cell) * dir)), 0.0f) << i;
    }
}

TEST(Constraints, DepthAndHeightLimitsMeasureFromTheOriginalSurface) {
    util::ThreadPool pool;
    const Script script = boxScript(7);
    auto limited = makeSculptor(script, 0, &pool);
    auto free = makeSculptor(script, 0, &pool);
    const double cell = limited->current()->domain().finestCellSize();
    Stroke carve = sphereStroke(ToolOp::Carve, 0.08, {{0.4, 0.5, 0.5}, {0.6, 0.5, 0.5}});
    free->apply(carve);
    carve.constraints.depthLimit = 0.03;
    limited->apply(carve);
    const glm::vec3 shallow(0.5f, 0.5f, float(0.5 - 0.03 + 2 * cell)), deep(0.5f, 0.5f, float(0.5 - 0.03 - 2 * cell));
    EXPECT_GT(limited->current()->distance(shallow), 0.0f);
    EXPECT_LT(limited->current()->distance(deep), 0.0f);
    EXPECT_GT(free->current()->distance(deep), 0.0f);  // without the limit the tool goes deeper

    // A second pass cannot go deeper either: the limit is from the original surface.
    limited->apply(carve);
    EXPECT_LT(limited->current()->distance(deep), 0.0f);

    Stroke add = sphereStroke(ToolOp::Add, 0.08, {{0.3, 0.3, 0.52}});
    add.constraints.heightLimit = 0.02;
    limited->apply(add);
    EXPECT_LT(limited->current()->distance(glm::vec3(0.3f, 0.3f, float(0.52 - 2 * cell))), 0.0f);
    EXPECT_GT(limited->current()->distance(glm::vec3(0.3f, 0.3f, float(0.52 + 2 * cell))), 0.0f);

    Sculptor noReference(limited->current(), &pool);
    EXPECT_THROW(noReference.apply(add), std::invalid_argument);
}

TEST(Constraints, MasksProtectTheirRegion) {
    util::ThreadPool pool;
    auto s = makeSculptor(boxScript(7), 0, &pool);
    Stroke st = sphereStroke(ToolOp::Carve, 0.03, {{0.2, 0.5, 0.5}, {0.8, 0.5, 0.5}});
    Shape mask;
    mask.kind = Shape::Kind::Box;
    mask.centre = {0.5, 0.5, 0.5};
    mask.halfSize = {0.1, 0.2, 0.2};
    st.constraints.masks = {mask};
    s->apply(st);
    const double cell = s->current()->domain().finestCellSize();
    // Inside the mask the top face is where it was; outside it the groove is cut.
    for (double x : {0.42, 0.5, 0.58}) {
        EXPECT_LT(s->current()->distance(glm::vec3(float(x), 0.5f, float(0.5 - 2 * cell))), 0.0f) << x;
        EXPECT_GT(s->current()->distance(glm::vec3(float(x), 0.5f, float(0.5 + 2 * cell))), 0.0f) << x;
    }
    for (double x : {0.25, 0.35, 0.65, 0.75}) EXPECT_GT(s->current()->distance(glm::vec3(float(x), 0.5f, 0.49f)), 0.0f) << x;
}

TEST(Constraints, PaintFollowsABezierPathAndMasksKeepTheirColour) {
    util::ThreadPool pool;
    auto s = makeSculptor(boxScript(7), 0, &pool);
    Stroke st;
    st.tool.op = ToolOp::Paint;
    st.tool.radius = 0.03;
    st.tool.colour = {200, 20, 20};
    st.bezier = true;
    st.samples = {{{0.2, 0.5, 0.5}, kIdentity}, {{0.4, 0.7, 0.5}, kIdentity}, {{0.6, 0.3, 0.5}, kIdentity}, {{0.8, 0.5, 0.5}, kIdentity}};
    Shape mask;
    mask.kind = Shape::Kind::Box;
    mask.centre = {0.5, 0.5, 0.5};
    mask.halfSize = {0.05, 0.2, 0.2};
    st.constraints.masks = {mask};
    const adf::AdfPtr before = s->current();
    s->apply(st);
    ASSERT_TRUE(s->current()->colours());
    const adf::ColourLayer& paint = *s->current()->colours();
    const BezierControls c{st.samples[0].position, st.samples[1].position, st.samples[2].position, st.samples[3].position};
    for (double t : {0.1, 0.3, 0.75, 0.9}) EXPECT_EQ(paint.colourAt(glm::vec3(bezierPoint(c, t))).g, 20) << t;  // on the curve
    EXPECT_EQ(paint.colourAt(glm::vec3(bezierPoint(c, 0.5))), adf::kClayColour);  // the curve's middle is masked
    EXPECT_EQ(paint.colourAt(glm::vec3(0.35f, 0.5f, 0.5f)), adf::kClayColour);  // on the chord, not the curve
    EXPECT_EQ(s->current()->tileAtSlot({0, 0, 0}), before->tileAtSlot({0, 0, 0}));  // the shape is untouched
}

TEST(ForceField, PushesTheToolOutAndRendersASpringForce) {
    Shape sphere;
    sphere.kind = Shape::Kind::Sphere;
    sphere.centre = glm::dvec3(0.5);
    sphere.radius = 0.1;
    adf::Domain d;
    const ForceField field({sphere.source(d)}, 2000.0);
    // Clear of the region: no force, no move.
    EXPECT_EQ(field.force({0.8, 0.5, 0.5}, 0.05), glm::dvec3(0.0));
    EXPECT_EQ(field.constrain({0.8, 0.5, 0.5}, 0.05), glm::dvec3(0.8, 0.5, 0.5));
    // 2 cm into the clearance: 2000 N/m × 0.02 m = 40 N outward (+x).
    const glm::dvec3 f = field.force({0.63, 0.5, 0.5}, 0.05);
    EXPECT_NEAR(f.x, 40.0, 1e-3);
    EXPECT_NEAR(glm::length(f), 40.0, 1e-3);
    const glm::dvec3 p = field.constrain({0.52, 0.51, 0.5}, 0.05);
    EXPECT_NEAR(glm::length(p - glm::dvec3(0.5)), 0.15, 1e-6);
    // Bad input: zero force, never a wild one.
    EXPECT_EQ(field.force(glm::dvec3(std::nan("")), 0.05), glm::dvec3(0.0));
}

TEST(Constraints, KeepOutRegionsStopTheTool) {
    util::ThreadPool pool;
    auto s = makeSculptor(boxScript(7), 0, &pool);
    Stroke st = sphereStroke(ToolOp::Carve, 0.02, {{0.2, 0.5, 0.49}, {0.8, 0.5, 0.49}});
    Shape region;
    region.kind = Shape::Kind::Sphere;
    region.centre = {0.5, 0.5, 0.5};
    region.radius = 0.08;
    st.constraints.keepOut = {region};
    for (const ToolSample& t : resolvePath(st, *s->current(), 1e-4))
        EXPECT_GE(glm::length(t.position - region.centre), 0.08 + st.tool.boundingRadius() - 1e-9);
    s->apply(st);
    // Nothing inside the region was carved; the path on either side was.
    EXPECT_LT(s->current()->distance(glm::vec3(0.5f, 0.5f, 0.49f)), 0.0f);
    EXPECT_LT(s->current()->distance(glm::vec3(0.45f, 0.5f, 0.49f)), 0.0f);
    EXPECT_GT(s->current()->distance(glm::vec3(0.3f, 0.5f, 0.49f)), 0.0f);
    EXPECT_GT(s->current()->distance(glm::vec3(0.7f, 0.5f, 0.49f)), 0.0f);
}

TEST(StrokeScript, BezierAndConstraintsRoundTrip) {
    const std::string line =
        R"({"op":"carve","shape":"sphere","radius":0.02,"bezier":[[0.1,0.2,0.5],[0.3,0.9,0.5],[0.7,0.1,0.5],[0.9,0.5,0.5]],)"
        R"("follow":{"offset":-0.01},"depth":0.02,"masks":[{"shape":"box","centre":[0.5,0.5,0.5],"half":[0.1,0.1,0.1]}],)"
        R"("keep_out":[{"shape":"sphere","centre":[0.2,0.2,0.2],"radius":0.05}]})";
    const Step a = parseStep(line);
    ASSERT_TRUE(a.stroke.bezier);
    ASSERT_EQ(a.stroke.samples.size(), 4u);
    EXPECT_EQ(*a.stroke.constraints.followOffset, -0.01);
    EXPECT_EQ(*a.stroke.constraints.depthLimit, 0.02);
    EXPECT_EQ(a.stroke.constraints.masks.size(), 1u);
    EXPECT_EQ(a.stroke.constraints.keepOut.size(), 1u);
    const std::string again = strokeLine(a.stroke);
    EXPECT_EQ(strokeLine(parseStep(again).stroke), again);
    EXPECT_NE(again.find("\"bezier\""), std::string::npos);
    EXPECT_THROW(parseStep(R"({"op":"carve","shape":"sphere","radius":0.02,"bezier":[[0,0,0],[1,1,1]]})"), std::invalid_argument);
    EXPECT_THROW(parseStep(R"({"op":"add","shape":"sphere","radius":0.02,"path":[[0,0,0]],"depth":0.1})"), std::invalid_argument);
    EXPECT_THROW(parseStep(R"({"op":"carve","shape":"sphere","radius":0.02,"path":[[0,0,0]],"masks":[{"shape":"cone"}]})"),
                 std::invalid_argument);
}

}  // namespace
}  // namespace kizamu
