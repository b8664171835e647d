// SPDX-License-Identifier: Apache-2.0
/// @file surface_ray.cpp
/// @brief traceRay: clip to the domain, sphere trace, bisect the crossing.
#include "interact/surface_ray.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <utility>

namespace kizamu::interact {

namespace {

/// [tNear, tFar] of the ray inside the box, or tNear > tFar when it misses (slab method).
std::pair<double, double> clipToBox(const glm::dvec3& o, const glm::dvec3& d, const glm::dvec3& lo, const glm::dvec3& hi) {
    double tNear = 0.0, tFar = HUGE_VAL;
    for (int a = 0; a < 3; ++a) {
        if (d[a] == 0.0) {
            if (o[a] < lo[a] || o[a] > hi[a]) return {1.0, 0.0};
            continue;
        }
        double t0 = (lo[a] - o[a]) / d[a], t1 = (hi[a] - o[a]) / d[a];
        if (t0 > t1) std::swap(t0, t1);
        tNear = std::max(tNear, t0);
        tFar = std::min(tFar, t1);
    }
    return {tNear, tFar};
}

}  // namespace

std::optional<RayHit> traceRay(adf::AdfAccessor& clay, const adf::Domain& domain, const glm::dvec3& origin,
                               const glm::dvec3& direction, const RayTraceSettings& settings) noexcept {
    const double len = glm::length(direction);
    if (!(len > 0.0) || !std::isfinite(len) || !std::isfinite(origin.x + origin.y + origin.z)) return std::nullopt;
    const glm::dvec3 dir = direction / len;
    const glm::dvec3 lo = domain.originWorld, hi = domain.originWorld + glm::dvec3(domain.sizeWorld);
    auto [tNear, tFar] = clipToBox(origin, dir, lo, hi);
    if (settings.maxDistance > 0.0) tFar = std::min(tFar, settings.maxDistance);
    if (tNear > tFar) return std::nullopt;
    const auto gap = [&](double t) {
        return double(clay.sample(glm::vec3(origin + dir * t)).distance) - settings.offset;
    };
    const double minStep = domain.finestCellSize() * 0.5;
    double t = tNear;
    double g = gap(t);
    if (g <= 0.0) return std::nullopt;  // starts inside the (offset) surface
    for (int i = 0; i < kMaxRaySteps && t < tFar; ++i) {
        const double next = std::min(tFar, t + std::max(kStepFactor * g, minStep));
        const double gNext = gap(next);
        if (gNext <= 0.0) {
            double a = t, b = next;  // a outside, b inside
            for (int k = 0; k < kRayBisectSteps; ++k) {
                const double mid = 0.5 * (a + b);
                (gap(mid) > 0.0 ? a : b) = mid;
            }
            RayHit hit;
            hit.t = 0.5 * (a + b);
            hit.point = origin + dir * hit.t;
            const glm::dvec3 grad(clay.sample(glm::vec3(hit.point)).gradient);
            const double gl = glm::length(grad);
            hit.normal = gl > 0.0 ? grad / gl : -dir;
            return hit;
        }
        t = next;
        g = gNext;
    }
    return std::nullopt;
}

}  // namespace kizamu::interact
