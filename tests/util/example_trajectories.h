// SPDX-License-Identifier: Apache-2.0
/// @file example_trajectories.h
/// @brief Test helper: the generator of the example trajectories in examples/ (deterministic:
/// integer times, positions rounded to 0.1 µm, no randomness).
///
/// tests/unit/engine/trajectory_test.cpp checks that the committed files are exactly what this
/// writes; `KIZAMU_WRITE_EXAMPLES=1 build/release/tests/kizamu_engine_tests
/// --gtest_filter='*Examples*'` rewrites them. Both are on the test part's top face (z = 0.8 of
/// the unit domain, docs/TEST-PART.md), away from the sphere that caps its middle.
#pragma once

#include "engine/trajectory.h"

#include <glm/gtc/quaternion.hpp>

#include <cmath>
#include <cstdint>
#include <functional>

namespace kizamu::engine::examples {

inline constexpr int64_t kMs = 1'000'000;  ///< ns
inline constexpr double kTopZ = 0.8;       ///< m: the test part's top face

inline TrajectoryStart testPartStart(int level) {
    TrajectoryStart s;
    s.domain.originWorld = glm::dvec3(0.0);
    s.domain.sizeWorld = 1.0;
    s.domain.maxLevel = level;
    s.shape.kind = sculpt::Shape::Kind::TestPart;
    return s;
}

/// Rounds to 0.1 µm, so positions print short.
inline double tenthMicron(double x) { return std::round(x * 1e7) / 1e7; }

inline ToolChange toolChange(int64_t timeNs, sculpt::ToolOp op, sculpt::ToolShape shape, double radius) {
    ToolChange c;
    c.timeNs = timeNs;
    c.tool.op = op;
    c.tool.shape = shape;
    c.tool.radius = radius;
    c.tool.halfLength = radius;
    return c;
}

/// One stroke at 1 kHz from `from` to `to` (m) over `durationMs`: a hovering sample 10 ms
/// before, the pressed samples, and the release 1 ms after the last. `pose` may set the
/// orientation and strength of sample k of n. Returns the time after the release, ns.
inline int64_t lineStroke(Trajectory& t, int64_t startNs, glm::dvec3 from, glm::dvec3 to, int durationMs,
                          const std::function<void(ToolSample&, int, int)>& pose = {}) {
    ToolSample s;
    s.timeNs = startNs;
    s.posWorld = from + glm::dvec3(0.0, 0.0, 0.005);
    if (pose) pose(s, 0, durationMs);
    t.add(s);
    startNs += 10 * kMs;
    for (int k = 0; k <= durationMs; ++k) {
        const double u = double(k) / double(durationMs);
        s.timeNs = startNs + k * kMs;
        s.posWorld = glm::dvec3(tenthMicron(from.x + (to.x - from.x) * u), tenthMicron(from.y + (to.y - from.y) * u),
                                tenthMicron(from.z + (to.z - from.z) * u));
        s.buttons = kButtonPrimary;
        if (pose) pose(s, k, durationMs);
        t.add(s);
    }
    s.timeNs += kMs;
    s.buttons = 0;
    s.posWorld.z += 0.005;
    t.add(s);
    return s.timeNs;
}

/// examples/carve_line.trajectory.jsonl: one 2 s carve at 1 kHz across the top face, a sphere
/// of radius 1 % of the domain at 10 cm/s, its centre on the surface (x 0.4 -> 0.6, y 0.3).
inline Trajectory carveLine() {
    Trajectory t;
    t.device = "generator: tests/util/example_trajectories.h carveLine";
    t.start = testPartStart(10);
    t.add(toolChange(0, sculpt::ToolOp::Carve, sculpt::ToolShape::Sphere, 0.01));
    for (int i = 0; i <= 2000; ++i) {
        ToolSample s;
        s.timeNs = int64_t(i) * kMs;
        s.posWorld = glm::dvec3(double(4000 + i) / 10000.0, 0.3, kTopZ);  // 0.1 mm per ms
        s.buttons = i < 2000 ? kButtonPrimary : 0u;
        t.add(s);
    }
    return t;
}

/// examples/sculpt_session.trajectory.jsonl: a carve groove; a tilted chisel under rising
/// pressure, undone; a mirrored bead of clay; a smoothing pass, undone and redone; paint; a
/// stroke cancelled half-way (the cancel at the same time as a sample, after it).
inline Trajectory sculptSession() {
    using sculpt::ToolOp;
    using sculpt::ToolShape;
    Trajectory t;
    t.device = "generator: tests/util/example_trajectories.h sculptSession";
    t.start = testPartStart(9);
    int64_t now = 0;
    t.add(toolChange(now, ToolOp::Carve, ToolShape::Sphere, 0.01));
    now = lineStroke(t, now, {0.3, 0.3, kTopZ}, {0.3, 0.7, kTopZ}, 400);

    ToolChange chisel = toolChange(now + 100 * kMs, ToolOp::Carve, ToolShape::Cylinder, 0.006);
    chisel.tool.halfLength = 0.015;
    chisel.tool.strength = 0.8;
    chisel.constraints.depthLimit = 0.004;
    t.add(chisel);
    now = lineStroke(t, now + 200 * kMs, {0.35, 0.7, kTopZ}, {0.65, 0.7, kTopZ}, 300, [](ToolSample& s, int k, int n) {
        const double u = double(k) / double(n);
        const glm::dquat q = glm::angleAxis(0.5 * u, glm::dvec3(1.0, 0.0, 0.0));  // tilts by up to 0.5 rad
        s.orientation = glm::quat(float(q.w), float(q.x), float(q.y), float(q.z));
        s.strength = float(0.5 + 0.5 * u);
    });
    t.add(CommandEvent{now + 150 * kMs, TrajectoryCommand::Undo});

    ToolChange bead = toolChange(now + 300 * kMs, ToolOp::Add, ToolShape::Sphere, 0.008);
    bead.mirror = 2;  // y: also at y = 0.7
    bead.constraints.heightLimit = 0.006;
    t.add(bead);
    now = lineStroke(t, now + 400 * kMs, {0.4, 0.3, kTopZ}, {0.6, 0.3, kTopZ}, 250);

    ToolChange smooth = toolChange(now + 100 * kMs, ToolOp::Smooth, ToolShape::Sphere, 0.02);
    smooth.tool.strength = 0.5;
    t.add(smooth);
    now = lineStroke(t, now + 200 * kMs, {0.3, 0.35, kTopZ}, {0.3, 0.65, kTopZ}, 200);
    t.add(CommandEvent{now + 100 * kMs, TrajectoryCommand::Undo});
    t.add(CommandEvent{now + 200 * kMs, TrajectoryCommand::Redo});
    now += 200 * kMs;

    ToolChange paint = toolChange(now + 100 * kMs, ToolOp::Paint, ToolShape::Sphere, 0.015);
    paint.tool.colour = {200, 30, 30};
    t.add(paint);
    now = lineStroke(t, now + 200 * kMs, {0.7, 0.35, kTopZ}, {0.7, 0.65, kTopZ}, 200);

    t.add(toolChange(now + 100 * kMs, ToolOp::Carve, ToolShape::Cube, 0.008));
    // Pressed for 150 ms, cancelled, then released: the stroke leaves no trace.
    Trajectory tail;
    const int64_t cancelStart = now + 200 * kMs;
    lineStroke(tail, cancelStart, {0.65, 0.3, kTopZ}, {0.65, 0.4, kTopZ}, 150);
    for (const TrajectoryEvent& e : tail.events) {
        const ToolSample& s = tail.samples[e.index];
        t.add(s);
        if (s.timeNs == cancelStart + 10 * kMs + 100 * kMs) t.add(CommandEvent{s.timeNs, TrajectoryCommand::Cancel});
    }
    return t;
}

}  // namespace kizamu::engine::examples
