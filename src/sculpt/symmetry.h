// SPDX-License-Identifier: Apache-2.0
/// @file symmetry.h
/// @brief Mirror copies of a stroke: reflections across the domain's mid planes.
///
/// Bit k of `reflect` mirrors axis k (x, y, z) about `centre`. A mirrored copy reflects the
/// query point rather than the tool, so a turned, asymmetric tool mirrors exactly.
/// Pure functions; any thread.
#pragma once

#include "adf/domain.h"

#include <cstdint>

namespace kizamu::sculpt {

inline glm::dvec3 mirroredPoint(glm::dvec3 p, uint8_t reflect, const glm::dvec3& centre) {
    for (int k = 0; k < 3; ++k)
        if ((reflect >> k) & 1) p[k] = 2.0 * centre[k] - p[k];
    return p;
}

inline adf::BoxWorld mirroredBox(adf::BoxWorld b, uint8_t reflect, const glm::dvec3& centre) {
    for (int k = 0; k < 3; ++k)
        if ((reflect >> k) & 1) {
            const double lo = 2.0 * centre[k] - b.max[k], hi = 2.0 * centre[k] - b.min[k];
            b.min[k] = lo;
            b.max[k] = hi;
        }
    return b;
}

}  // namespace kizamu::sculpt
