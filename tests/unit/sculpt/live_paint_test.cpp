// SPDX-License-Identifier: Apache-2.0
// Live paint strokes (Sculptor::beginStroke .. endStroke with the paint tool): painted segment
// by segment, the colour layer equals the stroke painted whole (bit for bit for a sphere,
// mirrored or not; within one 8-bit step per channel for other shapes), compared tile by tile;
// one undo record of the colour tiles replaced, no correction zone, every distance tile shared.
#include "sculpt/paint.h"
#include "sculpt/script_start.h"
#include "sculpt/sculptor.h"
#include "sculpt/stroke_script.h"

#include "adf/colour_layer.h"
#include "util/thread_pool.h"

#include <gtest/gtest.h>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <span>
#include <string>
#include <vector>

namespace kizamu {
namespace {

using namespace sculpt;

const glm::dquat kIdentity(1.0, 0.0, 0.0, 0.0);
const adf::Rgb8 kRed(220, 30, 40);

/// A slab whose top face is the plane z = 0.5 (x, y in [0.15, 0.85]).
Script slab() {
    Script s;
    s.domain.maxLevel = 7;
    s.domain.tileSpanLevels = 4;
    s.start.kind = Shape::Kind::Box;
    s.start.centre = {0.5, 0.5, 0.4};
    s.start.halfSize = {0.35, 0.35, 0.1};
    return s;
}

/// `n` poses from a to b, bending by `bend` (m) in y at the middle.
std::vector<ToolSample> curve(glm::dvec3 a, glm::dvec3 b, int n, double bend,
                              glm::dquat q = kIdentity) {
    std::vector<ToolSample> out;
    for (int i = 0; i < n; ++i) {
        const double t = double(i) / (n - 1);
        out.push_back({glm::mix(a, b, t) + glm::dvec3(0.0, bend * 4.0 * t * (1.0 - t), 0.0), q});
    }
    return out;
}

Stroke paintStrokeAlong(std::vector<ToolSample> samples, double radius, adf::Rgb8 colour,
                        double opacity) {
    Stroke s;
    s.tool.op = ToolOp::Paint;
    s.tool.radius = radius;
    s.tool.strength = opacity;
    s.tool.colour = colour;
    s.samples = std::move(samples);
    return s;
}

/// Every distance tile of `a` is `b`'s (shared, not rebuilt).
::testing::AssertionResult sharesDistanceTiles(const adf::Adf& a, const adf::Adf& b) {
    const uint32_t n = a.domain().slotsPerAxis();
    for (uint32_t z = 0; z < n; ++z)
        for (uint32_t y = 0; y < n; ++y)
            for (uint32_t x = 0; x < n; ++x)
                if (a.tileAtSlot({x, y, z}) != b.tileAtSlot({x, y, z}))
                    return ::testing::AssertionFailure()
                           << "slot " << x << "," << y << "," << z << " differs";
    return ::testing::AssertionSuccess();
}

struct ColourDiff {
    int worst = 0;            ///< largest channel difference (8-bit steps)
    std::size_t differ = 0;   ///< points whose colours differ
    std::size_t painted = 0;  ///< points painted in either layer
};

/// The two layers compared slot by slot and point by point (an unstored point has the base colour).
ColourDiff diffColours(const adf::ColourLayer* a, const adf::ColourLayer* b) {
    ColourDiff out;
    std::vector<uint32_t> keys;
    for (const adf::ColourLayer* l : {a, b})
        if (l) keys.insert(keys.end(), l->slotKeys().begin(), l->slotKeys().end());
    std::sort(keys.begin(), keys.end());
    keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
    const adf::Rgb8 baseA = a ? a->baseColour() : adf::kClayColour,
                    baseB = b ? b->baseColour() : adf::kClayColour;
    for (uint32_t key : keys) {
        const adf::ColourTile* ta = a ? a->tileAt(key) : nullptr;
        const adf::ColourTile* tb = b ? b->tileAt(key) : nullptr;
        std::vector<uint32_t> points;
        for (const adf::ColourTile* t : {ta, tb})
            if (t) points.insert(points.end(), t->points().begin(), t->points().end());
        std::sort(points.begin(), points.end());
        points.erase(std::unique(points.begin(), points.end()), points.end());
        for (uint32_t p : points) {
            const adf::Rgb8* ca = ta ? ta->find(p) : nullptr;
            const adf::Rgb8* cb = tb ? tb->find(p) : nullptr;
            const glm::ivec3 d =
                glm::abs(glm::ivec3(ca ? *ca : baseA) - glm::ivec3(cb ? *cb : baseB));
            const int m = std::max({d.x, d.y, d.z});
            out.worst = std::max(out.worst, m);
            out.differ += m > 0;
            ++out.painted;
        }
    }
    return out;
}

/// Paints `stroke` live in `segments` pieces of its poses; checks each piece is published at
/// once and shares every distance tile with the start.
Stroke paintLive(Sculptor& s, const Stroke& stroke, int segments) {
    Stroke header = stroke;
    header.samples.clear();
    const adf::AdfPtr before = s.current();
    s.beginStroke(header);
    const std::size_t n = stroke.samples.size();
    for (int k = 0; k < segments; ++k) {
        const std::size_t lo = n * k / segments, hi = n * (k + 1) / segments;
        s.extendStroke(std::span<const ToolSample>(stroke.samples).subspan(lo, hi - lo));
        if (k == 0) {
            EXPECT_NE(s.current()->colours(), before->colours())
                << "the first segment is published before the stroke ends";
            EXPECT_GT(s.lastEdit().colourTilesPainted, 0u);
            EXPECT_EQ(s.lastEdit().tilesRebuilt, 0u);
        }
        EXPECT_TRUE(sharesDistanceTiles(*s.current(), *before)) << "segment " << k;
    }
    return s.endStroke();
}

struct PaintCase {
    std::string name;
    std::vector<Stroke> before;  ///< strokes applied (whole) to both first
    Stroke stroke;
    int tolerance = 0;  ///< 8-bit steps per channel
};

std::vector<PaintCase> paintCases() {
    std::vector<PaintCase> cases;
    cases.push_back(
        {"sphere",
         {},
         paintStrokeAlong(curve({0.3, 0.35, 0.5}, {0.7, 0.55, 0.5}, 12, 0.08), 0.04, kRed, 0.6)});
    {
        // Back and forth over itself: the weight grows again where the path returns.
        std::vector<ToolSample> path = curve({0.35, 0.5, 0.5}, {0.6, 0.5, 0.5}, 6, 0.03);
        for (const ToolSample& t : curve({0.6, 0.48, 0.5}, {0.4, 0.53, 0.5}, 6, -0.02))
            path.push_back(t);
        cases.push_back(
            {"sphere, doubling back", {}, paintStrokeAlong(path, 0.03, {20, 90, 200}, 0.45)});
    }
    {
        PaintCase c{
            "mirrored sphere",
            {},
            paintStrokeAlong(curve({0.38, 0.3, 0.5}, {0.52, 0.6, 0.5}, 12, 0.05), 0.05, kRed, 0.5)};
        c.stroke.mirror = 0b011;  // the copies overlap across x = 0.5
        cases.push_back(c);
    }
    {
        PaintCase c{
            "tilted cube",
            {},
            paintStrokeAlong(curve({0.3, 0.35, 0.51}, {0.7, 0.55, 0.5}, 12, 0.08,
                                   glm::angleAxis(0.6, glm::normalize(glm::dvec3(1, 1, 0)))),
                             0.03, {30, 160, 60}, 0.7)};
        c.stroke.tool.shape = ToolShape::Cube;
        c.tolerance = 1;
        cases.push_back(c);
    }
    {
        // Over a groove and over earlier paint: the blend starts from the start's colours.
        Stroke carve;
        carve.tool.radius = 0.025;
        carve.samples = curve({0.35, 0.5, 0.5}, {0.65, 0.5, 0.5}, 4, 0.0);
        Stroke under = paintStrokeAlong(curve({0.5, 0.3, 0.5}, {0.5, 0.7, 0.5}, 3, 0.0), 0.05,
                                        {250, 240, 20}, 1.0);
        cases.push_back({"after a carve and paint",
                         {carve, under},
                         paintStrokeAlong(curve({0.3, 0.45, 0.5}, {0.7, 0.55, 0.49}, 12, 0.04),
                                          0.04, kRed, 0.55)});
    }
    return cases;
}

TEST(LivePaint, SegmentsPaintWhatTheWholeStrokePaints) {
    util::ThreadPool pool;
    const Script script = slab();
    for (const PaintCase& c : paintCases()) {
        auto whole = makeSculptor(script, 0, &pool);
        for (const Stroke& b : c.before) whole->apply(b);
        const adf::AdfPtr beforeStroke = whole->current();
        whole->apply(c.stroke);
        const EditStats wholeEdit = whole->lastEdit();
        const ColourDiff changed =
            diffColours(beforeStroke->colours().get(), whole->current()->colours().get());
        ASSERT_GT(changed.differ, 500u) << c.name << ": the stroke painted";
        const int n = int(c.stroke.samples.size());
        for (int segments : {1, 2, 7, n}) {
            auto live = makeSculptor(script, 0, &pool);
            for (const Stroke& b : c.before) live->apply(b);
            const std::size_t depth = live->undoDepth();
            const adf::AdfPtr liveBefore = live->current();
            const Stroke journal = paintLive(*live, c.stroke, segments);
            EXPECT_EQ(journal.samples.size(), c.stroke.samples.size()) << c.name;
            const ColourDiff diff =
                diffColours(whole->current()->colours().get(), live->current()->colours().get());
            std::printf(
                "[ live paint ] %-24s %2d segments: %zu of %zu points differ, by at most %d\n",
                c.name.c_str(), segments, diff.differ, diff.painted, diff.worst);
            EXPECT_LE(diff.worst, c.tolerance) << c.name << ", " << segments << " segments";
            EXPECT_TRUE(sharesDistanceTiles(*live->current(), *liveBefore)) << c.name;
            // One undo record of the colour tiles replaced, as apply() counts them; no correction
            // zone.
            EXPECT_EQ(live->undoDepth(), depth + 1) << c.name;
            EXPECT_EQ(live->pendingCorrections().size(), whole->pendingCorrections().size())
                << c.name;
            if (!c.stroke.mirror) {  // apply() counts each mirrored copy's replacement on its own
                EXPECT_EQ(live->lastEdit().colourTilesPainted, wholeEdit.colourTilesPainted)
                    << c.name << ", " << segments;
                EXPECT_EQ(live->lastEdit().replacedBytes, wholeEdit.replacedBytes)
                    << c.name << ", " << segments;
            }
            const adf::AdfPtr end = live->current();
            ASSERT_TRUE(live->undo());
            EXPECT_EQ(live->current().get(), liveBefore.get())
                << c.name << ": undo returns the snapshot before the stroke";
            ASSERT_TRUE(live->redo());
            EXPECT_EQ(live->current().get(), end.get()) << c.name;
        }
    }
}

TEST(LivePaint, UndoRedoAndCancelWorkOnTheWholeStroke) {
    util::ThreadPool pool;
    auto s = makeSculptor(slab(), 0, &pool);
    Stroke carve;
    carve.tool.radius = 0.03;
    carve.samples = curve({0.3, 0.4, 0.5}, {0.7, 0.6, 0.5}, 5, 0.05);
    s->apply(carve);
    const adf::AdfPtr start = s->current();
    const std::size_t pending = s->pendingCorrections().size();
    const Stroke st =
        paintStrokeAlong(curve({0.3, 0.4, 0.5}, {0.7, 0.6, 0.5}, 9, 0.05), 0.05, kRed, 0.8);
    Stroke header = st;
    header.samples.clear();
    // Cancelling restores the start and leaves no record.
    s->beginStroke(header);
    s->extendStroke(std::span<const ToolSample>(st.samples).first(4));
    ASSERT_NE(s->current(), start);
    ASSERT_NE(s->current()->colours(), nullptr);
    const glm::vec3 groove(st.samples[1].position -
                           glm::dvec3(0.0, 0.0, 0.03));  // the carve's bottom
    EXPECT_NE(s->current()->colours()->colourAt(groove), adf::kClayColour)
        << "painted before the stroke ends";
    EXPECT_THROW(s->apply(st), std::logic_error);
    EXPECT_THROW(s->undo(), std::logic_error);
    s->cancelStroke();
    EXPECT_FALSE(s->stroking());
    EXPECT_EQ(s->current(), start);
    EXPECT_EQ(s->undoDepth(), 1u);
    // Ending: one record; undo returns the start, redo the end; no correction owed.
    s->beginStroke(header);
    s->extendStroke(std::span<const ToolSample>(st.samples).first(3));
    s->extendStroke(std::span<const ToolSample>(st.samples).subspan(3));
    const Stroke journal = s->endStroke();
    EXPECT_EQ(journal.samples.size(), st.samples.size());
    const adf::AdfPtr end = s->current();
    EXPECT_EQ(s->undoDepth(), 2u);
    EXPECT_EQ(s->pendingCorrections().size(), pending) << "paint owes no correction";
    EXPECT_GT(s->lastEdit().colourTilesPainted, 0u);
    EXPECT_TRUE(sharesDistanceTiles(*end, *start));
    ASSERT_TRUE(s->undo());
    EXPECT_EQ(s->current(), start);
    EXPECT_EQ(s->pendingCorrections().size(), pending);
    ASSERT_TRUE(s->redo());
    EXPECT_EQ(s->current(), end);
    // The journal replays to the same colours.
    auto again = makeSculptor(slab(), 0, &pool);
    again->apply(carve);
    again->apply(journal);
    EXPECT_EQ(diffColours(again->current()->colours().get(), end->colours().get()).worst, 0);
}

}  // namespace
}  // namespace kizamu
