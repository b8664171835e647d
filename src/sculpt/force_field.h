// SPDX-License-Identifier: Apache-2.0
/// @file force_field.h
/// @brief Keep-out regions as force fields (Kizamu 4.4): regions the tool may not enter.
///
/// Each region is a distance source (negative inside). A tool, bounded by a sphere of radius
/// `clearance` around its pose, penetrates a region by max(0, clearance − d(p)); the field
/// pushes it out along the region's outward normal. `force` is what a haptic device renders (a
/// spring, N/m × m = N); `constrain` is where an infinitely stiff field holds the tool, which is
/// what a scripted or mouse-driven stroke uses.
/// Immutable after construction; thread-safe; `force` and `constrain` allocate nothing, take no
/// lock and do no I/O (the haptic thread may call them). Complexity: O(regions) per call
/// (`constrain`: up to 16 rounds where regions overlap).
#pragma once

#include "adf/distance_source.h"

#include <glm/vec3.hpp>

#include <vector>

namespace kizamu::sculpt {

class ForceField {
public:
    /// @param stiffness  N/m, > 0
    explicit ForceField(std::vector<adf::SourcePtr> regions, double stiffness = 1000.0);

    /// Force on a tool at `p` (m) of bounding radius `clearance` (m), N; zero when it is clear.
    glm::dvec3 force(const glm::dvec3& p, double clearance) const;
    /// `p` moved out of every region until the tool clears each by `clearance` (m).
    glm::dvec3 constrain(glm::dvec3 p, double clearance) const;

private:
    std::vector<adf::SourcePtr> mRegions;
    double mStiffness;
};

/// Outward unit normal of `source` at `p` (central differences); zero where it vanishes.
glm::dvec3 sourceNormal(const adf::DistanceSource& source, const glm::dvec3& p);

}  // namespace kizamu::sculpt
