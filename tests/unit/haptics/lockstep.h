// SPDX-License-Identifier: Apache-2.0
// Shared by the haptics tests: small clay in a 10 cm domain centred on the origin (the sim
// stylus's workspace), exact distances of the shapes it starts from, and a rig that runs the
// simulated stylus and the proxy renderer in lock step at 1 kHz (read, render, write, step).
#pragma once

#include "adf/adf.h"
#include "haptics/proxy_renderer.h"
#include "sculpt/script_start.h"
#include "sim/simulated_stylus.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <utility>

namespace kizamu::test {

inline constexpr double kPeriod = 1e-3;  ///< s, the servo period of every lock-step test
inline constexpr double kSphereRadius = 0.03;      ///< m, centred on the origin
inline constexpr double kBoxHalf = 0.025;          ///< m, a cube centred on the origin

inline sculpt::Script hapticScript(const sculpt::Shape& shape, int level) {
    sculpt::Script s;
    s.domain.originWorld = glm::dvec3(-0.05);
    s.domain.sizeWorld = 0.1;
    s.domain.maxLevel = level;
    s.domain.tileSpanLevels = 4;
    s.start = shape;
    return s;
}

inline adf::AdfPtr sphereClay(double radius = kSphereRadius, int level = 7) {
    sculpt::Shape s;
    s.kind = sculpt::Shape::Kind::Sphere;
    s.centre = glm::dvec3(0.0);
    s.radius = radius;
    return sculpt::startAdf(hapticScript(s, level), 0);
}

inline adf::AdfPtr boxClay(int level = 7) {
    sculpt::Shape s;
    s.kind = sculpt::Shape::Kind::Box;
    s.centre = glm::dvec3(0.0);
    s.halfSize = glm::dvec3(kBoxHalf);
    return sculpt::startAdf(hapticScript(s, level), 0);
}

/// The ADF's error bound at the surface for the clay above (m).
inline double surfaceError(const adf::Adf& clay) { return clay.settings().errorBound(clay.domain()).epsilon; }

/// Exact signed distances (m) of the start shapes.
inline double sphereDistance(const glm::dvec3& p, double radius = kSphereRadius) { return glm::length(p) - radius; }
inline double boxDistance(const glm::dvec3& p) {
    const glm::dvec3 q = glm::abs(p) - glm::dvec3(kBoxHalf);
    return glm::length(glm::max(q, glm::dvec3(0.0))) + std::min(std::max(q.x, std::max(q.y, q.z)), 0.0);
}

/// The stylus, the renderer and the clay, ticked together.
struct Rig {
    sim::SimulatedStylus stylus;
    haptics::ProxyRenderer renderer;
    adf::AdfPtr clay;
    adf::AdfAccessor accessor;
    uint64_t clayId = 1;
    haptics::ProxyOutput last;
    haptics::DeviceState state;

    Rig(sim::Hand hand, adf::AdfPtr c, const haptics::ProxySettings& ps = {}, const sim::StylusSettings& ss = {})
        : stylus(std::move(hand), ss), renderer(stylus.spec(), kPeriod, ps), clay(std::move(c)), accessor(*clay) {}

    /// One servo tick; carving while the hand holds button 1 (or `carve`).
    const haptics::ProxyOutput& tick(bool carve = false) {
        stylus.read(state);
        last = renderer.update(state, accessor, clayId, kPeriod, carve || (state.buttons & 1u) != 0);
        stylus.write(last.force);
        stylus.step(kPeriod);
        return last;
    }
    /// A new snapshot, as the servo loop sees one: another clay under a new id.
    void setClay(adf::AdfPtr c) {
        clay = std::move(c);
        accessor.reset(*clay);
        ++clayId;
    }
};

/// A hand that rests at `from` for `rest` s, moves to `to` in `move` s, holds it for `hold` s,
/// and goes back in `move` s.
inline sim::Hand pressHand(const glm::dvec3& from, const glm::dvec3& to, double rest = 0.3, double move = 0.2,
                           double hold = 0.4, uint32_t buttons = 0) {
    sim::Hand h;
    h.add(0.0, from);
    h.add(rest, from, buttons);
    h.add(rest + move, to, buttons);
    h.add(rest + move + hold, to, buttons);
    h.add(rest + 2.0 * move + hold, from, 0);
    return h;
}

}  // namespace kizamu::test
