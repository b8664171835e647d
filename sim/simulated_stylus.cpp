// SPDX-License-Identifier: Apache-2.0
/// @file simulated_stylus.cpp
/// @brief The stylus's integration and energy bookkeeping (model in simulated_stylus.h).
#include "sim/simulated_stylus.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <utility>

namespace kizamu::sim {

SimulatedStylus::SimulatedStylus(Hand hand, const StylusSettings& settings) : mHand(std::move(hand)), mSettings(settings) {
    assert(settings.mass > 0.0 && settings.rate > 0.0 && settings.substeps >= 1 && "SimulatedStylus: bad settings");
    mSpec.name = "sim";
    mSpec.maxForce = settings.maxForce;
    mSpec.damping = settings.damping;
    mSpec.rate = settings.rate;
    mSpec.maxStiffness =
        settings.maxStiffness > 0.0 ? settings.maxStiffness : haptics::passiveStiffnessBound(settings.damping, 0.0, 1.0 / settings.rate);
    mSpec.workspaceMin = settings.workspaceMin;
    mSpec.workspaceMax = settings.workspaceMax;
    mSpec.orientation = false;
    mPosition = mHand.at(0.0).position;
}

bool SimulatedStylus::read(haptics::DeviceState& out) noexcept {
    out.timeNs = mTimeNs;
    out.position = mPosition;
    out.orientation = glm::dquat(1.0, 0.0, 0.0, 0.0);
    out.velocity = mVelocity;
    out.buttons = handAt(time()).buttons;
    out.connected = true;
    return true;
}

void SimulatedStylus::write(const glm::dvec3& force) noexcept {
    const bool finite = std::isfinite(force.x) && std::isfinite(force.y) && std::isfinite(force.z);
    mForce = finite ? force : glm::dvec3(0.0);
}

void SimulatedStylus::step(double dt) noexcept {
    if (!(dt > 0.0) || !std::isfinite(dt)) return;
    const int n = std::max(1, mSettings.substeps);
    const double h = dt / double(n);
    const double m = mSettings.mass, b = mSettings.damping, kh = mSettings.handStiffness, bh = mSettings.handDamping;
    const bool forced = mForce != glm::dvec3(0.0);
    const double t0 = time();
    for (int i = 0; i < n; ++i) {
        const HandPose hand = handAt(t0 + double(i + 1) * h);
        // m (v' - v) / h = kh (xh - x) + bh (vh - v') - b v' + f
        const glm::dvec3 springH = kh * (hand.position - mPosition);
        const glm::dvec3 v = (m * mVelocity + h * (springH + bh * hand.velocity + mForce)) / (m + h * (bh + b));
        const glm::dvec3 dx = (0.5 * h) * (mVelocity + v);  // exact for the force held over the substep
        mEnergy.rendered += glm::dot(mForce, dx);
        mEnergy.hand += glm::dot(springH + bh * (hand.velocity - v), dx);
        const double loss = b * glm::dot(v, dx);
        mEnergy.damped += loss;
        if (forced) mEnergy.dampedUnderForce += loss;
        mVelocity = v;
        mPosition += dx;
    }
    mTimeNs += int64_t(std::llround(dt * 1e9));
}

}  // namespace kizamu::sim
