// SPDX-License-Identifier: Apache-2.0
// Live strokes (Sculptor::beginStroke .. endStroke): a stroke applied segment by segment while
// the button is held equals the same stroke applied whole, within the error bound plus one
// quantisation step, for every tool that segments; it is one undo record; cancelling leaves
// none; and what it measures against is the clay from its start.
#include "sculpt/script_start.h"
#include "sculpt/sculptor.h"
#include "sculpt/stroke_script.h"

#include "adf/error_bound.h"
#include "adf/generate.h"
#include "util/thread_pool.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <random>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace kizamu {
namespace {

using namespace sculpt;

const glm::dquat kIdentity(1.0, 0.0, 0.0, 0.0);

Script slabScript() {
    Script s;
    s.domain.maxLevel = 7;
    s.start.kind = Shape::Kind::Box;  // x, y in [0.15, 0.85], top face at z = 0.5
    s.start.centre = {0.5, 0.5, 0.4};
    s.start.halfSize = {0.35, 0.35, 0.1};
    return s;
}

/// `n` poses from a to b, bending by `bend` (m) in y at the middle.
std::vector<ToolSample> curve(glm::dvec3 a, glm::dvec3 b, int n, double bend, glm::dquat q = kIdentity) {
    std::vector<ToolSample> out;
    for (int i = 0; i < n; ++i) {
        const double t = double(i) / (n - 1);
        out.push_back({glm::mix(a, b, t) + glm::dvec3(0.0, bend * 4.0 * t * (1.0 - t), 0.0), q});
    }
    return out;
}

/// Applies `stroke` live in `segments` pieces of its poses (the dwell divided by time: the poses
/// are evenly spaced in time). Checks the clay changed after the first piece, before the end.
Stroke applyLive(Sculptor& s, const Stroke& stroke, int segments) {
    Stroke header = stroke;
    header.samples.clear();
    header.dwell = 0.0;
    const adf::AdfPtr before = s.current();
    s.beginStroke(header);
    EXPECT_TRUE(s.stroking());
    EXPECT_EQ(s.current().get(), before.get()) << "nothing applied yet";
    const std::size_t n = stroke.samples.size();
    for (int k = 0; k < segments; ++k) {
        const std::size_t lo = n * k / segments, hi = n * (k + 1) / segments;
        s.extendStroke(std::span<const ToolSample>(stroke.samples).subspan(lo, hi - lo), stroke.dwell * double(hi - lo) / double(n));
        if (k == 0) {
            EXPECT_NE(s.current().get(), before.get()) << "the first segment is published before the stroke ends";
            EXPECT_GT(s.lastEdit().tilesRebuilt, 0u);
        }
    }
    return s.endStroke();
}

struct Agreement {
    double worst = 0.0;  ///< m, largest |whole - live| at the points compared
    int compared = 0;
};

/// |a - b| at random points of `box` where `a` is within the accurate band (4 epsilon).
Agreement compare(const adf::Adf& a, const adf::Adf& b, const adf::BoxWorld& box, double eps) {
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    Agreement out;
    for (int i = 0; i < 30000; ++i) {
        const glm::dvec3 p = box.min + (box.max - box.min) * glm::dvec3(u(rng), u(rng), u(rng));
        const double da = a.distance(glm::vec3(p));
        if (std::abs(da) > 4.0 * eps) continue;
        out.worst = std::max(out.worst, std::abs(da - double(b.distance(glm::vec3(p)))));
        ++out.compared;
    }
    return out;
}

struct LiveCase {
    std::string name;
    std::vector<Stroke> before;  ///< strokes applied (whole) before, to both
    Stroke stroke;
};

std::vector<LiveCase> liveCases(double h) {
    std::vector<LiveCase> cases;
    {
        LiveCase c{"carve", {}, {}};
        c.stroke.tool.radius = 0.03;
        c.stroke.samples = curve({0.3, 0.35, 0.5}, {0.7, 0.55, 0.51}, 12, 0.08);
        cases.push_back(c);
    }
    {
        LiveCase c{"add (tilted cube)", {}, {}};
        c.stroke.tool.op = ToolOp::Add;
        c.stroke.tool.shape = ToolShape::Cube;
        c.stroke.tool.radius = 0.02;
        c.stroke.samples = curve({0.3, 0.35, 0.52}, {0.7, 0.55, 0.52}, 12, 0.08,
                                 glm::angleAxis(0.6, glm::normalize(glm::dvec3(1, 1, 0))));
        cases.push_back(c);
    }
    {
        LiveCase c{"build", {}, {}};
        c.stroke.tool.op = ToolOp::Build;
        c.stroke.tool.radius = 0.05;
        c.stroke.tool.amount = 3.0 * h;
        c.stroke.samples = curve({0.3, 0.4, 0.5}, {0.7, 0.6, 0.5}, 12, 0.06);
        cases.push_back(c);
    }
    {
        LiveCase c{"heat gun", {}, {}};
        c.stroke.tool.op = ToolOp::HeatGun;
        c.stroke.tool.radius = 0.05;
        c.stroke.tool.rate = 0.02;  // m/s
        c.stroke.dwell = 0.3;       // s: 6 mm at the core
        c.stroke.samples = curve({0.35, 0.4, 0.5}, {0.65, 0.6, 0.5}, 12, 0.05);
        cases.push_back(c);
    }
    {
        LiveCase c{"smooth", {}, {}};
        c.stroke.tool.op = ToolOp::Smooth;
        c.stroke.tool.radius = 0.05;
        c.stroke.samples = curve({0.15, 0.3, 0.5}, {0.15, 0.7, 0.5}, 12, 0.0);  // along the slab's top edge
        cases.push_back(c);
    }
    {
        LiveCase c{"flatten", {}, {}};
        Stroke bump;
        bump.tool.op = ToolOp::Add;
        bump.tool.radius = 0.03;
        bump.samples = curve({0.45, 0.5, 0.5}, {0.55, 0.5, 0.5}, 2, 0.0);
        c.before.push_back(bump);
        c.stroke.tool.op = ToolOp::Flatten;
        c.stroke.tool.radius = 0.05;
        c.stroke.samples = curve({0.38, 0.48, 0.5}, {0.62, 0.52, 0.505}, 12, 0.03);
        cases.push_back(c);
    }
    return cases;
}

adf::BoxWorld strokeBox(const Stroke& st, double reach) {
    adf::BoxWorld b{glm::dvec3(1e9), glm::dvec3(-1e9)};
    for (const ToolSample& t : st.samples) {
        b.min = glm::min(b.min, t.position - reach);
        b.max = glm::max(b.max, t.position + reach);
    }
    return b;
}

TEST(LiveStroke, SegmentsAddUpToTheWholeStrokeForEveryTool) {
    util::ThreadPool pool;
    const Script script = slabScript();
    const adf::AdfPtr start = startAdf(script, 0, &pool);
    const adf::Domain& d = start->domain();
    const double h = d.finestCellSize();
    const double eps = start->settings().errorBound(d).epsilon;
    const double step = 4.0 / 127.0 * h;  // one leaf step: the coarsest quantisation (tile.h)
    for (const LiveCase& c : liveCases(h)) {
        auto whole = makeSculptor(script, 0, &pool);
        for (const Stroke& b : c.before) whole->apply(b);
        const adf::AdfPtr beforeStroke = whole->current();
        whole->apply(c.stroke);
        const adf::BoxWorld box = strokeBox(c.stroke, c.stroke.tool.boundingRadius() + 6.0 * h);
        // The stroke did something.
        EXPECT_GT(compare(*whole->current(), *beforeStroke, box, eps).worst, eps) << c.name;
        const int n = int(c.stroke.samples.size());
        for (int segments : {1, 2, 7, n}) {
            auto live = makeSculptor(script, 0, &pool);
            for (const Stroke& b : c.before) live->apply(b);
            const std::size_t depth = live->undoDepth();
            const adf::AdfPtr liveBefore = live->current();
            const Stroke journal = applyLive(*live, c.stroke, segments);
            EXPECT_EQ(journal.samples.size(), c.stroke.samples.size()) << c.name;
            EXPECT_NEAR(journal.dwell, c.stroke.dwell, 1e-12) << c.name;
            const Agreement a = compare(*whole->current(), *live->current(), box, eps);
            std::printf("[ live ] %-18s %2d segments: max |whole - live| = %.3f eps (%d points)\n", c.name.c_str(), segments,
                        a.worst / eps, a.compared);
            EXPECT_GT(a.compared, 1000) << c.name;
            EXPECT_LE(a.worst, eps + step) << c.name << ", " << segments << " segments";
            // One undo record, one correction zone.
            EXPECT_EQ(live->undoDepth(), depth + 1) << c.name;
            EXPECT_EQ(live->pendingCorrections().size(), whole->pendingCorrections().size()) << c.name;
            const adf::AdfPtr end = live->current();
            ASSERT_TRUE(live->undo());
            EXPECT_EQ(live->current().get(), liveBefore.get()) << c.name << ": undo returns the snapshot before the stroke";
            ASSERT_TRUE(live->redo());
            EXPECT_EQ(live->current().get(), end.get()) << c.name;
        }
    }
}

TEST(LiveStroke, UndoRedoAndCancelWorkOnTheWholeStroke) {
    util::ThreadPool pool;
    const Script script = slabScript();
    auto s = makeSculptor(script, 0, &pool);
    const adf::AdfPtr start = s->current();
    Stroke st;
    st.tool.radius = 0.03;
    st.samples = curve({0.3, 0.4, 0.5}, {0.7, 0.6, 0.5}, 9, 0.05);
    // Cancelling restores the start and leaves no record.
    s->beginStroke({st.tool, {}, false, {}, 0, 0.0});
    s->extendStroke(std::span<const ToolSample>(st.samples).first(4));
    ASSERT_NE(s->current(), start);
    EXPECT_GT(s->current()->distance(glm::vec3(st.samples[0].position)), 0.0f) << "carved before the stroke ends";
    EXPECT_THROW(s->apply(st), std::logic_error);
    EXPECT_THROW(s->undo(), std::logic_error);
    EXPECT_THROW(s->beginStroke(st), std::logic_error);
    s->cancelStroke();
    EXPECT_FALSE(s->stroking());
    EXPECT_EQ(s->current(), start);
    EXPECT_EQ(s->undoDepth(), 0u);
    EXPECT_TRUE(s->pendingCorrections().empty());
    EXPECT_THROW(s->extendStroke(st.samples), std::logic_error);
    EXPECT_THROW(s->endStroke(), std::logic_error);
    // Ending: one record; undo returns the start bits, redo the end bits.
    s->beginStroke({st.tool, {}, false, {}, 0, 0.0});
    s->extendStroke(std::span<const ToolSample>(st.samples).first(3));
    s->extendStroke(std::span<const ToolSample>(st.samples).subspan(3));
    const Stroke journal = s->endStroke();
    EXPECT_EQ(journal.samples.size(), st.samples.size());
    const adf::AdfPtr end = s->current();
    EXPECT_EQ(s->undoDepth(), 1u);
    EXPECT_EQ(s->pendingCorrections().size(), 1u) << "one correction zone";
    ASSERT_TRUE(s->undo());
    EXPECT_EQ(s->current(), start);
    EXPECT_FALSE(s->undo());
    ASSERT_TRUE(s->redo());
    EXPECT_EQ(s->current(), end);
    // A stroke that applied nothing leaves no record.
    s->beginStroke({st.tool, {}, false, {}, 0, 0.0});
    s->endStroke();
    EXPECT_EQ(s->undoDepth(), 1u);
    EXPECT_EQ(s->current(), end);
    // A Bezier header is not a live path.
    Stroke bezier = st;
    bezier.samples.resize(4);
    bezier.bezier = true;
    EXPECT_THROW(s->beginStroke(bezier), std::invalid_argument);
    EXPECT_FALSE(s->stroking());
}

TEST(LiveStroke, SurfaceFollowingReadsTheClayFromTheStrokesStart) {
    // Poses above the top face, following it (offset 0): each lands on z = 0.5 of the start
    // clay. Following the clay being cut would drop every pose into the groove the previous
    // segment carved, deeper and deeper.
    util::ThreadPool pool;
    const Script script = slabScript();
    const adf::Domain d = startAdf(script, 0, &pool)->domain();
    const double h = d.finestCellSize();
    const double eps = startAdf(script, 0, &pool)->settings().errorBound(d).epsilon;
    Stroke st;
    st.tool.radius = 0.03;
    st.constraints.followOffset = 0.0;
    st.samples = curve({0.3, 0.5, 0.54}, {0.7, 0.5, 0.54}, 16, 0.0);
    auto whole = makeSculptor(script, 0, &pool);
    whole->apply(st);
    auto live = makeSculptor(script, 0, &pool);
    applyLive(*live, st, int(st.samples.size()));
    const Agreement a = compare(*whole->current(), *live->current(), strokeBox(st, 0.03 + 6.0 * h), eps);
    std::printf("[ live ] following, 16 segments: max |whole - live| = %.3f eps\n", a.worst / eps);
    EXPECT_LE(a.worst, eps + 4.0 / 127.0 * h);
    // The groove is one tool radius deep along the whole path, no deeper.
    for (double x : {0.35, 0.5, 0.65}) {
        EXPECT_GT(live->current()->distance(glm::vec3(x, 0.5, 0.5 - 0.5 * 0.03)), 0.0f) << x;
        EXPECT_LT(live->current()->distance(glm::vec3(x, 0.5, 0.5 - 0.03 - 2.0 * h)), 0.0f) << x << ": followed the groove";
    }
}

TEST(LiveStroke, DepthLimitsAndFlattensPlaneStayWithTheStrokesStart) {
    util::ThreadPool pool;
    const Script script = slabScript();
    const adf::AdfPtr start = startAdf(script, 0, &pool);
    const double h = start->domain().finestCellSize();
    const double eps = start->settings().errorBound(start->domain()).epsilon;
    // A carve that passes the same spot three times in one stroke, limited to 2 cells deep:
    // each pass would cut a tool radius deeper if the limit read the clay being cut.
    Stroke st;
    st.tool.radius = 0.03;
    st.constraints.depthLimit = 2.0 * h;
    for (int pass = 0; pass < 3; ++pass)
        for (const ToolSample& t : curve({0.4, 0.5, 0.5 - 0.01 * pass}, {0.6, 0.5, 0.5 - 0.01 * pass}, 4, 0.0))
            st.samples.push_back(t);
    auto whole = makeSculptor(script, 0, &pool);
    whole->apply(st);
    auto live = makeSculptor(script, 0, &pool);
    applyLive(*live, st, int(st.samples.size()));
    const Agreement a = compare(*whole->current(), *live->current(), strokeBox(st, 0.03 + 6.0 * h), eps);
    EXPECT_LE(a.worst, eps + 4.0 / 127.0 * h);
    EXPECT_GT(live->current()->distance(glm::vec3(0.5f, 0.5f, float(0.5 - 1.5 * h))), 0.0f) << "carved to the limit";
    EXPECT_LT(live->current()->distance(glm::vec3(0.5f, 0.5f, float(0.5 - 3.0 * h))), 0.0f) << "and no deeper";
    // Flatten: the plane is the first pose's, even when a later segment starts elsewhere.
    Stroke flatten;
    flatten.tool.op = ToolOp::Flatten;
    flatten.tool.radius = 0.05;
    flatten.samples = {{{0.4, 0.5, 0.52}, kIdentity}, {{0.5, 0.5, 0.46}, kIdentity}, {{0.6, 0.5, 0.46}, kIdentity}};
    auto w = makeSculptor(script, 0, &pool);
    w->apply(flatten);
    auto l = makeSculptor(script, 0, &pool);
    applyLive(*l, flatten, 3);
    const Agreement f = compare(*w->current(), *l->current(), strokeBox(flatten, 0.05 + 6.0 * h), eps);
    EXPECT_LE(f.worst, eps + 4.0 / 127.0 * h);
    EXPECT_LT(l->current()->distance(glm::vec3(0.45f, 0.5f, 0.505f)), 0.0f) << "raised toward the plane z = 0.52";
}

}  // namespace
}  // namespace kizamu
