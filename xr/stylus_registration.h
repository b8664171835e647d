// SPDX-License-Identifier: Apache-2.0
/// @file stylus_registration.h
/// @brief Registers a force-feedback stylus's workspace in the headset's space, so the clay felt
/// is the clay seen: the artist touches a few points with the stylus tip and the controller
/// together, and the similarity that best maps the stylus's points onto the controller's (least
/// squares: Horn's closed form with unit quaternions, scale from the spreads) is the
/// registration.
///
/// Pure; any thread.
#pragma once

#include "xr/pose.h"

#include <span>

namespace kizamu::xr {

struct StylusRegistration {
    Similarity deviceToSpace;  ///< stylus workspace (m) to the headset's reference space (m)
    double rmsM = 0.0;         ///< the fit's root-mean-square residual
};

/// The best similarity taking `device[i]` to `space[i]`. At least three pairs, not on one line.
/// @throw std::invalid_argument with what is wrong (too few, different counts, collinear)
/// Complexity O(n).
StylusRegistration registerStylus(std::span<const glm::dvec3> device, std::span<const glm::dvec3> space);

}  // namespace kizamu::xr
