// SPDX-License-Identifier: Apache-2.0
/// @file input_filter.h
/// @brief Optional predictive smoothing of a noisy device position: an alpha-beta (g-h)
/// tracker that estimates position and velocity and may lead by a fixed time.
///
/// Galyean and Hughes 2.2.2 smooth the tracker's positions with a predictive filter so the tool
/// follows the hand without its jitter and without lagging behind. Per tick of length T, with the
/// measured position z:
///   predict  x⁻ = x + v T,   residual r = z − x⁻,
///   correct  x = x⁻ + α r,   v = v + (β / T) r,
///   output   x + v · lead.
/// α in (0, 1] trades smoothing for lag (α = 1, β = 0: no filtering); β in [0, 4 − 2α) keeps the
/// tracker stable (Kalata's region 0 < α, 0 < β, 4 − 2α − β > 0). A constant velocity is followed
/// with no steady-state lag; the lead then cancels the device's own latency. The filter changes
/// what the renderer sees, so its output velocity (not the device's) is what the renderer damps.
/// A plain value; update() is noexcept, allocates nothing, servo thread.
#pragma once

#include "haptics/device.h"

#include <glm/vec3.hpp>

namespace kizamu::haptics {

struct InputFilterSettings {
    bool enabled = false;
    double alpha = 0.5;  ///< position gain, (0, 1]
    double beta = 0.1;   ///< velocity gain, [0, 4 − 2 alpha)
    double lead = 0.0;   ///< s, how far ahead the output is predicted (>= 0)
};

class InputFilter {
public:
    /// @throw std::invalid_argument for gains outside the stable region or a negative lead
    explicit InputFilter(const InputFilterSettings& settings = {});

    /// Filters `state` in place (position and velocity; the rest untouched); `dt` (s) is the time
    /// since the previous call. The first call after construction or reset() seeds the tracker
    /// with the measurement. Disabled, or a non-finite input or dt: `state` is left as it is.
    void update(DeviceState& state, double dt) noexcept;
    void reset() noexcept { mSeeded = false; }
    const InputFilterSettings& settings() const noexcept { return mSettings; }

private:
    InputFilterSettings mSettings;
    glm::dvec3 mPosition{0.0}, mVelocity{0.0};
    bool mSeeded = false;
};

}  // namespace kizamu::haptics
