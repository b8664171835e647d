// SPDX-License-Identifier: Apache-2.0
/// @file input_filter.cpp
/// @brief InputFilter: the alpha-beta tracker.
#include "haptics/input_filter.h"

#include <cmath>
#include <stdexcept>

namespace kizamu::haptics {

InputFilter::InputFilter(const InputFilterSettings& settings) : mSettings(settings) {
    const InputFilterSettings& s = mSettings;
    if (!(s.alpha > 0.0 && s.alpha <= 1.0)) throw std::invalid_argument("input filter: alpha must be in (0, 1]");
    if (!(s.beta >= 0.0 && 4.0 - 2.0 * s.alpha - s.beta > 0.0))
        throw std::invalid_argument("input filter: beta must be in [0, 4 - 2 alpha) for a stable tracker");
    if (!(s.lead >= 0.0 && std::isfinite(s.lead))) throw std::invalid_argument("input filter: lead must be >= 0 s");
}

void InputFilter::update(DeviceState& state, double dt) noexcept {
    if (!mSettings.enabled) return;
    const glm::dvec3& z = state.position;
    if (!std::isfinite(z.x + z.y + z.z) || !(dt > 0.0) || !std::isfinite(dt)) return;
    if (!mSeeded) {
        mPosition = z;
        mVelocity = glm::dvec3(std::isfinite(state.velocity.x + state.velocity.y + state.velocity.z) ? state.velocity
                                                                                                       : glm::dvec3(0.0));
        mSeeded = true;
    } else {
        const glm::dvec3 predicted = mPosition + mVelocity * dt;
        const glm::dvec3 residual = z - predicted;
        mPosition = predicted + mSettings.alpha * residual;
        mVelocity += (mSettings.beta / dt) * residual;
    }
    state.position = mPosition + mVelocity * mSettings.lead;
    state.velocity = mVelocity;
}

}  // namespace kizamu::haptics
