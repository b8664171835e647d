// SPDX-License-Identifier: Apache-2.0
/// @file hand.h
/// @brief A scripted hand: time-ordered waypoints (time, position, buttons), interpolated
/// linearly, that the simulated stylus's hand impedance follows (simulated_stylus.h).
///
/// Read from hand files (hand_file.h, docs/HAND.md) or built in code by tests. Units SI (m, s).
/// A plain value; at() is const, noexcept and allocates nothing, so the servo loop may call it.
#pragma once

#include <glm/vec3.hpp>

#include <algorithm>
#include <cstdint>
#include <vector>

namespace kizamu::sim {

struct HandWaypoint {
    double t = 0.0;              ///< s from the start
    glm::dvec3 position{0.0};    ///< m, device frame
    uint32_t buttons = 0;        ///< engine::ToolButton bits held from this waypoint on
};

/// The hand at one instant.
struct HandPose {
    glm::dvec3 position{0.0};  ///< m
    glm::dvec3 velocity{0.0};  ///< m/s, the slope of the segment it is on (0 before and after)
    uint32_t buttons = 0;
};

/// Waypoints with non-decreasing times (the reader guarantees it; add() asserts nothing, the
/// caller keeps the order). Two waypoints at one time make a jump.
struct Hand {
    std::vector<HandWaypoint> waypoints;

    void add(double t, const glm::dvec3& p, uint32_t buttons = 0) { waypoints.push_back({t, p, buttons}); }
    /// s, the last waypoint's time (0 when empty).
    double duration() const { return waypoints.empty() ? 0.0 : waypoints.back().t; }

    /// Linear interpolation at `t` (s): before the first waypoint its position, after the last
    /// the last's, both at rest; buttons are those of the waypoint the segment starts at.
    /// Complexity: O(log n). Memory: none. Any thread.
    HandPose at(double t) const noexcept {
        HandPose pose;
        if (waypoints.empty()) return pose;
        const auto after = std::upper_bound(waypoints.begin(), waypoints.end(), t,
                                            [](double time, const HandWaypoint& w) { return time < w.t; });
        if (after == waypoints.begin()) {
            pose.position = waypoints.front().position;
            pose.buttons = waypoints.front().buttons;
            return pose;
        }
        const HandWaypoint& a = *(after - 1);
        pose.buttons = a.buttons;
        if (after == waypoints.end()) {
            pose.position = a.position;
            return pose;
        }
        const HandWaypoint& b = *after;
        const double span = b.t - a.t;  // > 0: upper_bound skipped every waypoint at a.t
        const double u = (t - a.t) / span;
        pose.position = a.position + (b.position - a.position) * u;
        pose.velocity = (b.position - a.position) / span;
        return pose;
    }
};

}  // namespace kizamu::sim
