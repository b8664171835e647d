// SPDX-License-Identifier: Apache-2.0
#include "xr/clay_grab.h"

#include <algorithm>
#include <cmath>

namespace kizamu::xr {

namespace {

/// The shortest rotation taking unit direction `from` to unit direction `to`.
glm::dquat rotationBetween(const glm::dvec3& from, const glm::dvec3& to) {
    const double c = glm::dot(from, to);
    if (c > 1.0 - 1e-12) return glm::dquat(1.0, 0.0, 0.0, 0.0);
    if (c < -1.0 + 1e-12) {
        // Opposite: half a turn about any axis orthogonal to `from`.
        glm::dvec3 axis = glm::cross(from, glm::dvec3(1.0, 0.0, 0.0));
        if (glm::length(axis) < 1e-6) axis = glm::cross(from, glm::dvec3(0.0, 1.0, 0.0));
        return glm::angleAxis(M_PI, glm::normalize(axis));
    }
    const glm::dvec3 axis = glm::cross(from, to);
    return glm::normalize(glm::dquat(1.0 + c, axis.x, axis.y, axis.z));
}

}  // namespace

Similarity ClayGrab::update(const std::array<std::optional<Pose>, 2>& hands, const Similarity& placement) {
    const std::array<bool, 2> held{hands[0].has_value(), hands[1].has_value()};
    if (held != mHeld) {  // a hand took hold or let go: the present is the new reference
        mHeld = held;
        mStartPlacement = placement;
        for (std::size_t i = 0; i < 2; ++i)
            if (hands[i]) mStartHands[i] = *hands[i];
        return placement;
    }
    if (held[0] && held[1]) {
        const glm::dvec3 a0 = mStartHands[0].position, b0 = mStartHands[1].position;
        const glm::dvec3 a = hands[0]->position, b = hands[1]->position;
        const double d0 = glm::length(b0 - a0), d = glm::length(b - a);
        if (d0 < 1e-4 || d < 1e-4) return placement;  // hands together: no line to follow
        Similarity move;
        move.rotation = rotationBetween((b0 - a0) / d0, (b - a) / d);
        const double scale = std::clamp(mStartPlacement.scale * d / d0, mMinScale, mMaxScale);
        move.scale = scale / mStartPlacement.scale;
        move.translation = 0.5 * (a + b) - move.scale * (move.rotation * (0.5 * (a0 + b0)));
        return move * mStartPlacement;
    }
    for (std::size_t i = 0; i < 2; ++i) {
        if (!held[i]) continue;
        // The clay rides the hand rigidly: hand now ∘ hand at the start⁻¹ ∘ placement then.
        return Similarity::of(*hands[i]) * Similarity::of(mStartHands[i]).inverse() * mStartPlacement;
    }
    return placement;
}

}  // namespace kizamu::xr
