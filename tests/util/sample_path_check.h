// SPDX-License-Identifier: Apache-2.0
/// @file sample_path_check.h
/// @brief Test helpers for SampleQueue: a smooth tool path with button presses, and a check of
/// what a consumer received against what the producer pushed (the guarantee in
/// engine/sample_queue.h, checked independently of the queue's carried bounds).
#pragma once

#include "engine/sample_queue.h"

#include <glm/gtc/quaternion.hpp>
#include <glm/vec4.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <string>
#include <vector>

namespace kizamu::test {

/// `n` samples at 4 kHz of a hand moving at about 0.2 m/s on a Lissajous figure in a 10 cm box,
/// the tool turning about a wandering axis at about 1 rad/s and the pressure varying slowly;
/// the primary button is held for `pressLength` samples out of every `period` (from sample
/// `period - pressLength`), so every stroke has a first and a last sample.
inline std::vector<engine::ToolSample> smoothToolPath(std::size_t n, std::size_t period = 2500,
                                                      std::size_t pressLength = 2000) {
    std::vector<engine::ToolSample> out(n);
    for (std::size_t i = 0; i < n; ++i) {
        const double t = double(i) / 4000.0;  // s
        engine::ToolSample& s = out[i];
        s.timeNs = int64_t(i) * 250'000;
        s.posWorld = glm::dvec3(0.05 * std::sin(2.0 * t), 0.05 * std::sin(3.0 * t + 0.5),
                                0.02 * std::cos(1.3 * t));
        const glm::dvec3 axis =
            glm::normalize(glm::dvec3(std::cos(0.3 * t), std::sin(0.3 * t), 0.5));
        s.orientation = glm::quat(glm::angleAxis(1.0 * t, axis));
        s.strength = float(0.5 + 0.4 * std::sin(0.7 * t));
        s.buttons = (i % period) >= period - pressLength ? engine::kButtonPrimary : 0u;
    }
    return out;
}

/// What checkDelivered found.
struct DeliveredReport {
    std::string error;  ///< empty when the guarantee holds
    std::size_t kept = 0, merged = 0;
    double worstPosition = 0.0, worstAngle = 0.0, worstStrength = 0.0;  ///< m, rad, -
};

/// Checks that `delivered` is a subsequence of `pushed` (bit for bit, in order), that it keeps
/// the first and the last sample, every button edge and the sample before each, and that every
/// sample left out lies within the settings' tolerances × 2^maxCoarsening of the delivered
/// samples around it (position: of their segment; orientation: of their slerp; strength: of
/// their lerp, both at its time). `pushed` holds only accepted samples.
inline DeliveredReport checkDelivered(const std::vector<engine::ToolSample>& pushed,
                                      const std::vector<engine::ToolSample>& delivered,
                                      const engine::SampleQueueSettings& settings,
                                      int maxCoarsening) {
    DeliveredReport r;
    const auto same = [](const engine::ToolSample& a, const engine::ToolSample& b) {
        return std::memcmp(&a, &b, sizeof(engine::ToolSample)) == 0;
    };
    std::vector<std::size_t> keptAt;  // indices into `pushed`
    std::size_t j = 0;
    for (std::size_t i = 0; i < pushed.size() && j < delivered.size(); ++i)
        if (same(pushed[i], delivered[j])) {
            keptAt.push_back(i);
            ++j;
        }
    if (j != delivered.size()) {
        r.error =
            "delivered sample " + std::to_string(j) + " is not the next pushed sample in order";
        return r;
    }
    if (pushed.empty()) return r;
    std::vector<char> kept(pushed.size(), 0);
    for (const std::size_t i : keptAt) kept[i] = 1;
    r.kept = keptAt.size();
    r.merged = pushed.size() - keptAt.size();
    if (!kept.front() || !kept.back()) {
        r.error = "the first or the last pushed sample is missing";
        return r;
    }
    for (std::size_t i = 1; i < pushed.size(); ++i)
        if (pushed[i].buttons != pushed[i - 1].buttons && (!kept[i] || !kept[i - 1])) {
            r.error = "button edge at pushed sample " + std::to_string(i) +
                      " (or the sample before it) is missing";
            return r;
        }
    const double scale = std::ldexp(1.0, maxCoarsening);
    const double slack = 1e-9;  // rounding of the bound's own arithmetic
    for (std::size_t k = 0; k + 1 < keptAt.size(); ++k) {
        const engine::ToolSample& a = pushed[keptAt[k]];
        const engine::ToolSample& c = pushed[keptAt[k + 1]];
        const glm::dquat qa = glm::normalize(glm::dquat(a.orientation));
        const glm::dquat qc = glm::normalize(glm::dquat(c.orientation));
        for (std::size_t i = keptAt[k] + 1; i < keptAt[k + 1]; ++i) {
            const engine::ToolSample& m = pushed[i];
            const glm::dvec3 ac = c.posWorld - a.posWorld;
            const double len2 = glm::dot(ac, ac);
            const double t =
                len2 > 0.0 ? std::clamp(glm::dot(m.posWorld - a.posWorld, ac) / len2, 0.0, 1.0)
                           : 0.0;
            const double pos = glm::length(m.posWorld - (a.posWorld + t * ac));
            const double tau = c.timeNs > a.timeNs
                                   ? double(m.timeNs - a.timeNs) / double(c.timeNs - a.timeNs)
                                   : 0.5;
            const glm::dquat qm = glm::normalize(glm::dquat(m.orientation));
            glm::dquat qi = glm::slerp(qa, qc, tau);
            if (glm::dot(qm, qi) < 0.0) qi = -qi;
            const glm::dvec4 dq(qm.x - qi.x, qm.y - qi.y, qm.z - qi.z, qm.w - qi.w);
            const glm::dvec4 sq(qm.x + qi.x, qm.y + qi.y, qm.z + qi.z, qm.w + qi.w);
            const double angle = 2.0 * std::atan2(glm::length(dq), glm::length(sq));
            const double str =
                std::abs(double(m.strength) -
                         (double(a.strength) + tau * (double(c.strength) - double(a.strength))));
            r.worstPosition = std::max(r.worstPosition, pos);
            r.worstAngle = std::max(r.worstAngle, angle);
            r.worstStrength = std::max(r.worstStrength, str);
            if (pos > settings.positionTolerance * scale + slack * 1e-3 ||
                angle > settings.angleTolerance * scale + slack ||
                str > settings.strengthTolerance * scale + slack) {
                r.error =
                    "merged sample " + std::to_string(i) + " is outside the tolerance: position " +
                    std::to_string(pos) + " m, angle " + std::to_string(angle) + " rad, strength " +
                    std::to_string(str) + " (coarsening " + std::to_string(maxCoarsening) + ")";
                return r;
            }
        }
    }
    return r;
}

}  // namespace kizamu::test
