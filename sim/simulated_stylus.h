// SPDX-License-Identifier: Apache-2.0
/// @file simulated_stylus.h
/// @brief A simulated haptic stylus: a point mass with physical damping, pushed by a scripted
/// hand through an impedance and by the rendered force, on a virtual clock.
///
/// Where it sits: sim/ is the project's null backend (STYLE.md §6): the same Device interface as
/// a real stylus, deterministic, so the servo loop, the renderer and CI run without hardware.
/// Lock-step use: read() → render → write() → step(T), on one thread; the same inputs give the
/// same states bit for bit (no clock, no threads, no randomness).
///
/// Model, per substep of length h (SI units):
///   m dv/dt = K_h (x_hand(t) − x) + B_h (v_hand(t) − v) − b v + f_rendered,   dx/dt = v
/// integrated with the damping terms implicit in the new velocity v', the hand spring explicit
/// in the old position, and x' = x + h (v + v') / 2. That position step makes the bookkeeping
/// exact: with every force F held over the substep, m (v' - v)·(v + v') / 2 = F·Δx, so the
/// kinetic energy equals the works of the hand, the rendered force and the damping as applied
/// (tested), and the integrator neither hides nor adds energy the passivity test would see
/// (x' = x + h v' instead would dissipate h²|F|²/2m per substep, ~8 % of b at a 3200 N/m wall).
/// The rendered force is held over the whole step (the zero-order hold of a real servo loop),
/// which is what the passivity bound is about; substeps (10 by default) make the device itself
/// close to continuous. Stability: the damping is unconditionally stable; the explicit hand
/// spring grows the state by sqrt(1 + (hω)²/2) per substep, ω = sqrt(K_h / m): at the defaults
/// (m = 0.1 kg, K_h = 500 N/m, h = 0.1 ms) 1 + 1.25e-5, a growth rate of 0.125/s against the
/// damping's decay rate (b + B_h) / 2m = 35/s.
///
/// Features:
///  [X] Device interface (spec, read, write), deterministic step()
///  [X] hand impedance following a Hand (hand.h, hand files: hand_file.h)
///  [X] energy bookkeeping: work of the rendered force, dissipation of the physical damping
///  [ ] workspace stops (the workspace is reported, not enforced)
///  [X] a live hand (the mouse: live_hand.h) instead of the script, on the servo clock
///  [ ] orientation, button bounce, sensor quantisation
/// Changes: none yet (first version, issue 32).
#pragma once

#include "haptics/device.h"
#include "sim/hand.h"
#include "sim/live_hand.h"

#include <glm/vec3.hpp>

#include <cstdint>

namespace kizamu::sim {

/// Modelled on a Falcon-class 3-DOF device: ~9 N continuous force (the Falcon's published 2 lb)
/// and a ~10 cm cube workspace (its 4 x 4 x 4 in). Its physical damping b = 2 N·s/m is a model
/// choice, far above a real linkage's: it sets the passivity bound 2b/T = 4000 N/m at 1 kHz,
/// a usable wall; the effective mass 0.1 kg is the order of a grip and linkage. The hand figures
/// are those of a relaxed human grip (stiffness a few hundred N/m, damping a few N·s/m).
struct StylusSettings {
    double mass = 0.1;             ///< kg
    double damping = 2.0;          ///< N·s/m, physical (b of the passivity bound)
    double handStiffness = 500.0;  ///< N/m, K_h
    double handDamping = 5.0;      ///< N·s/m, B_h
    double maxForce = 9.0;         ///< N
    double maxStiffness = 0.0;     ///< N/m; 0: the passivity bound 2b/T at `rate`
    double rate = 1000.0;          ///< Hz, the servo rate the spec is stated at
    int substeps = 10;             ///< integration substeps per step()
    glm::dvec3 workspaceMin{-0.05}, workspaceMax{0.05};  ///< m
};

/// Energy bookkeeping since construction, J. Each figure is the exact work of the forces the
/// integrator applied (the rendered force is constant over a step, so its work is f·Δx).
struct StylusEnergy {
    double rendered = 0.0;          ///< work of the rendered force on the device
    double damped = 0.0;            ///< >= 0, dissipated by the physical damping b
    double dampedUnderForce = 0.0;  ///< the part of `damped` during steps with a non-zero force
    double hand = 0.0;              ///< work of the hand impedance on the device
};

/// Owned by the test or the app's sim backend; one thread (not thread-safe).
class SimulatedStylus final : public haptics::Device {
public:
    /// Starts at rest at the hand's position at t = 0.
    explicit SimulatedStylus(Hand hand, const StylusSettings& settings = {});

    const haptics::DeviceSpec& spec() const noexcept override { return mSpec; }
    /// The state at the current virtual time (exact velocity, the hand's buttons). Never fails.
    bool read(haptics::DeviceState& out) noexcept override;
    /// Holds `force` (N) until the next write; a non-finite force is held as zero.
    void write(const glm::dvec3& force) noexcept override;

    /// Advances the virtual clock by `dt` (s, > 0) with the held force.
    /// Complexity: O(substeps). Memory: none.
    void step(double dt) noexcept;

    /// Drives the stylus with `live` instead of the scripted hand (null: the script again): the
    /// hand at stylus time t is live->at(clockOffsetNs + t). The servo thread, between steps.
    void setLiveHand(LiveHand* live, int64_t clockOffsetNs = 0) noexcept {
        mLive = live;
        mLiveOffsetNs = clockOffsetNs;
    }

    double time() const noexcept { return double(mTimeNs) / 1e9; }  ///< s (exact at whole ns)
    const glm::dvec3& position() const noexcept { return mPosition; }
    const glm::dvec3& velocity() const noexcept { return mVelocity; }
    const glm::dvec3& force() const noexcept { return mForce; }
    const StylusEnergy& energy() const noexcept { return mEnergy; }
    const Hand& hand() const noexcept { return mHand; }
    const StylusSettings& settings() const noexcept { return mSettings; }

private:
    /// The hand at stylus time t (s): the live hand's, or the script's.
    HandPose handAt(double t) noexcept {
        return mLive ? mLive->at(mLiveOffsetNs + int64_t(t * 1e9)) : mHand.at(t);
    }

    Hand mHand;
    LiveHand* mLive = nullptr;
    int64_t mLiveOffsetNs = 0;
    StylusSettings mSettings;
    haptics::DeviceSpec mSpec;
    int64_t mTimeNs = 0;  ///< the virtual clock, integer ns: 1000 steps of 1 ms land exactly on 1 s
    glm::dvec3 mPosition{0.0}, mVelocity{0.0}, mForce{0.0};
    StylusEnergy mEnergy;
};

}  // namespace kizamu::sim
