// SPDX-License-Identifier: Apache-2.0
/// @file force_field.cpp
/// @brief Keep-out force fields.
#include "sculpt/force_field.h"

#include <glm/geometric.hpp>

#include <cmath>
#include <stdexcept>

namespace kizamu::sculpt {

glm::dvec3 sourceNormal(const adf::DistanceSource& source, const glm::dvec3& p) {
    constexpr double h = 1e-6;  // m: far below any tool, far above rounding at metre scales
    glm::dvec3 g;
    for (int k = 0; k < 3; ++k) {
        glm::dvec3 a = p, b = p;
        a[k] += h;
        b[k] -= h;
        g[k] = source.distance(a) - source.distance(b);
    }
    const double len = glm::length(g);
    return len > 0.0 && std::isfinite(len) ? g / len : glm::dvec3(0.0);
}

ForceField::ForceField(std::vector<adf::SourcePtr> regions, double stiffness)
    : mRegions(std::move(regions)), mStiffness(stiffness) {
    if (!(stiffness > 0.0) || !std::isfinite(stiffness)) throw std::invalid_argument("force field stiffness must be positive (N/m)");
}

glm::dvec3 ForceField::force(const glm::dvec3& p, double clearance) const {
    glm::dvec3 f(0.0);
    if (!std::isfinite(p.x + p.y + p.z)) return f;  // bad input: no force, never a wild one
    for (const adf::SourcePtr& r : mRegions) {
        const double penetration = clearance - r->distance(p);
        if (penetration > 0.0) f += mStiffness * penetration * sourceNormal(*r, p);
    }
    return f;
}

glm::dvec3 ForceField::constrain(glm::dvec3 p, double clearance) const {
    if (!std::isfinite(p.x + p.y + p.z)) return p;
    // Regions may overlap, and pushing out of one can push into another: a few rounds settle
    // it; the small overshoot keeps rounding from leaving the tool a hair inside.
    for (int round = 0; round < 16; ++round) {
        bool moved = false;
        for (const adf::SourcePtr& r : mRegions) {
            const double penetration = clearance - r->distance(p);
            if (penetration > 0.0) {
                p += (penetration * (1.0 + 1e-9) + 1e-12) * sourceNormal(*r, p);
                moved = true;
            }
        }
        if (!moved) break;
    }
    return p;
}

}  // namespace kizamu::sculpt
