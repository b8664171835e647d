// SPDX-License-Identifier: Apache-2.0
/// @file surface_ray.h
/// @brief Where a ray (the one under the mouse cursor) meets the clay: sphere tracing on the
/// ADF's distance field, to the surface or to an offset surface.
///
/// The ADF's distance is exact near the surface and a bounded under- or over-estimate far from
/// it (coarse cells interpolate), so the march steps by kStepFactor times the distance, never
/// less than a minimum step, checks each step's end for a sign change and bisects the last step
/// that crossed: a hit is a crossing, never a guess from one sample. Complexity: O(kMaxSteps +
/// kBisectSteps) samples. Threading: any thread with its own accessor (the render/UI thread reads
/// a published snapshot through adf::GuardedAccessor). Memory: none.
#pragma once

#include "adf/adf.h"

#include <glm/vec3.hpp>

#include <optional>

namespace kizamu::interact {

struct RayHit {
    glm::dvec3 point{0.0};   ///< m, world: on the (offset) surface
    glm::dvec3 normal{0.0};  ///< unit, the field's gradient there (points out of the clay)
    double t = 0.0;          ///< m along the ray from its origin
};

struct RayTraceSettings {
    double offset = 0.0;       ///< m: hit where the distance equals this (> 0: above the surface)
    double maxDistance = 0.0;  ///< m along the ray; 0: to where it leaves the clay's domain
};

inline constexpr int kMaxRaySteps = 256;
inline constexpr int kRayBisectSteps = 24;
inline constexpr double kStepFactor = 0.9;

/// The first point along origin + t·direction (t >= 0; direction need not be unit) where the
/// distance falls to `settings.offset`, inside the clay's domain; nothing when the ray misses
/// (or starts inside the offset surface: a ray from inside the clay hits nothing).
std::optional<RayHit> traceRay(adf::AdfAccessor& clay, const adf::Domain& domain, const glm::dvec3& origin,
                               const glm::dvec3& direction, const RayTraceSettings& settings = {}) noexcept;

}  // namespace kizamu::interact
