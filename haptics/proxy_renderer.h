// SPDX-License-Identifier: Apache-2.0
/// @file proxy_renderer.h
/// @brief Force rendering on the clay: a proxy (god-object) that follows the device in free
/// space and stays on the tool's contact surface when the device penetrates, coupled to the
/// device by a spring-damper kept inside the device's passivity bound.
///
/// Where it sits: the servo thread (one tick per device read, 1 kHz) reads the device, calls
/// update() with the published snapshot (adf::GuardedAccessor), writes the force back, and when
/// carving sends the proxy's pose, not the device's, to the engine. Papers: the god-object of
/// Zilles and Salisbury 1995 (here on a distance field: contact where the distance equals the
/// tool radius plus the depth-constraint offset, Kizamu 4.x); the passivity bound of Colgate and
/// Schenkel 1997 (b > K·T/2 + |B|, device.h). Units SI (m, s, N, kg). Frame: the clay's world
/// frame; the caller maps the device into it (workspace.h) and builds the renderer on the mapped
/// spec, so "device" below means the device's state in the world.
///
/// Features:
///  [X] proxy in free space = device; stops on the contact surface (march, then regula falsi on the gap; bounded)
///  [X] slides along the surface (tangent-plane move + re-projection, bounded), static and
///      kinetic friction (Coulomb cone on the spring force)
///  [X] tool radius and offset surface (contact where distance = toolRadius + offset)
///  [X] stiffness clamped to kPassivitySafety x the passivity bound and to the device's maximum
///  [X] force clamped to the device's maximum, force scale, haptics-off switch, soft start
///  [X] a snapshot that moves the surface under the proxy: the proxy settles at a bounded rate
///  [X] carving: the proxy advances into the material at the removal rate
///  [X] non-finite or disconnected device: zero force, proxy held
///  [ ] 6-DOF tools (orientation, torque), tool shapes other than the sphere
///  [X] workspace mapping (scale, rotation) between device and clay: the renderer runs in the
///      world on WorkspaceMapping::worldSpec() (workspace.h), which keeps it passive on the device
/// Changes: none yet (first version, issue 32).
#pragma once

#include "adf/adf.h"
#include "adf/guarded_accessor.h"
#include "haptics/device.h"

#include <glm/vec3.hpp>

#include <cstdint>

namespace kizamu::haptics {

/// What the renderer is asked for. Plain values; each field documented with its unit.
struct ProxySettings {
    double toolRadius = 0.0;  ///< m, the tool sphere: it touches where the distance is this
    double offset = 0.0;      ///< m, depth-constraint offset: contact where distance = toolRadius + offset
    double stiffness = 0.0;   ///< N/m, asked for; 0: the stiffest allowed (the constructor clamps)
    double damping = 0.0;     ///< N·s/m, virtual, on the proxy-device relative velocity (spends the bound)
    double staticFriction = 0.0;   ///< static Coulomb coefficient (>= kineticFriction)
    double kineticFriction = 0.0;  ///< kinetic Coulomb coefficient
    double maxForce = 0.0;    ///< N; 0 or above the device's: the device's maximum
    double forceScale = 1.0;  ///< 0..1, multiplies the force before the clamp
    bool enabled = true;      ///< false: haptics off (zero force; the proxy is still tracked)
    double softStartForce = 0.5;  ///< N: after a (re)start no force until the computed one is below this
    double softStartTime = 0.25;  ///< s: then the force ramps from 0 to full over this time
    double removalRate = 0.03;    ///< m/s: how fast the carving proxy advances into the material (a loop tool through soft clay)
    /// m/s: how fast a proxy the surface moved under (a new snapshot) is moved back to it:
    /// K settleSpeed T per tick bounds the force step it causes (0.16 N at 3200 N/m, 1 kHz;
    /// docs/decisions/0032-haptic-proxy-gains.md).
    double settleSpeed = 0.05;
};

/// One tick's result.
struct ProxyOutput {
    glm::dvec3 force{0.0};  ///< N, device frame: finite, |force| <= maxForce()
    glm::dvec3 proxy{0.0};  ///< m: the proxy (tool centre); what the engine carves when carving
    bool contact = false;   ///< the clay holds the proxy off the device
    bool settling = false;  ///< the proxy is being moved back to a surface that moved
    bool fault = false;     ///< the device state (or dt) was unusable: zero force, proxy held
};

/// Which limit set the stiffness the renderer uses.
enum class StiffnessLimit : uint8_t { Requested, Passivity, DeviceMaximum, Unchecked };

/// The proxy renderer of one device. Owned by the servo loop; one per device; not thread-safe
/// (the servo thread only). update() is noexcept, allocates nothing and takes no lock.
class ProxyRenderer {
public:
    /// Fraction of the passivity bound the constructor allows: the bound holds for an ideal
    /// zero-order hold at exactly `period`; the servo loop's period error (up to 0.1 ms p99.9 at
    /// 1 kHz, design brief: the bound shrinks by 1/1.1), the device's velocity estimate and the
    /// ADF's gradient error eat into it, and exactly at the bound the contact's entry and exit
    /// still put a little energy in; 0.8 keeps about 10 % beyond the jitter
    /// (docs/decisions/0032-haptic-proxy-gains.md).
    static constexpr double kPassivitySafety = 0.8;
    /// Bounded work per tick (what keeps update() real-time).
    static constexpr int kMarchSteps = 32;     ///< sphere-tracing steps along the proxy's path
    static constexpr int kBisectSteps = 16;    ///< most root-finding steps to the contact point (regula falsi: a few)
    static constexpr int kSlideIterations = 4; ///< tangent-plane moves (edges and grooves need > 1)
    static constexpr int kProjectSteps = 3;    ///< Newton steps back onto the surface per move

    /// @param spec    the device's limits (maxForce, maxStiffness, damping b)
    /// @param period  s, the servo period T the stiffness must be passive at (> 0)
    /// @param settings what is asked; the stiffness is clamped to
    ///        min(asked or unlimited, kPassivitySafety x passiveStiffnessBound(b, B, T), spec.maxStiffness)
    ///        and the damping B to [0, b] (gains() says what was chosen and why).
    ProxyRenderer(const DeviceSpec& spec, double period, const ProxySettings& settings);

    /// One servo tick: moves the proxy toward `device` under the clay's constraint and returns
    /// the force to render.
    /// @param device   the state read this tick (device frame = world, m, m/s)
    /// @param clay     an accessor bound to the snapshot this tick reads
    /// @param clayId   identifies that snapshot (the SnapshotStore sequence number): when it
    ///                 changes the surface may have moved, and the proxy settles at settleSpeed
    /// @param dt       s, time since the last tick (the servo period)
    /// @param carving  the carve button is held: the proxy advances into the material at
    ///                 removalRate, and the caller carves at ProxyOutput::proxy
    /// @return force finite and within maxForce(); zero with `fault` for a non-finite device
    ///         state or dt, zero while disconnected, off or in the soft start's wait.
    /// Complexity: O(kMarchSteps + kBisectSteps + kSlideIterations x (kMarchSteps + kBisectSteps
    ///             + kProjectSteps)) accessor samples at worst, a few in free space.
    /// Threading: the servo thread. Memory: none; never blocks, never throws.
    ProxyOutput update(const DeviceState& device, adf::AdfAccessor& clay, uint64_t clayId, double dt,
                       bool carving) noexcept;
    /// The same on the published snapshot `guard` holds (binds `clay` to it).
    ProxyOutput update(const DeviceState& device, adf::GuardedAccessor& clay, const adf::GuardedAccessor::Guard& guard,
                       double dt, bool carving) noexcept {
        return update(device, clay.bound(guard), guard.sequence(), dt, carving);
    }

    /// Forgets the proxy (it starts again at the device) and restarts the soft start.
    void reset() noexcept;

    /// The fraction t in [0, 1] of the segment from `from` to `to` the tool travels before it
    /// touches the clay (1: the whole segment is free; 0: `from` is already inside). Used to
    /// project a 2-DOF tool onto the surface (engine_client.h). Same bounded march as the proxy's
    /// own moves: material thinner than |to − from| / kMarchSteps may be stepped over.
    /// Complexity: O(kMarchSteps + kBisectSteps) samples. Memory: none. Servo thread.
    double contactFraction(adf::AdfAccessor& clay, const glm::dvec3& from, const glm::dvec3& to) const noexcept {
        return freeFraction(clay, from, to);
    }

    // ---- what was chosen ----
    struct Gains {
        double stiffness = 0.0;       ///< N/m, what the force uses
        double damping = 0.0;         ///< N·s/m, virtual
        double passiveBound = 0.0;    ///< N/m, passiveStiffnessBound(b, B, T) (before the safety factor)
        double maxForce = 0.0;        ///< N
        StiffnessLimit limitedBy = StiffnessLimit::Requested;
    };
    const Gains& gains() const noexcept { return mGains; }
    double maxForce() const noexcept { return mGains.maxForce; }
    const ProxySettings& settings() const noexcept { return mSettings; }

    // ---- live controls (servo thread, between ticks) ----
    /// 0..1 (clamped). Takes effect on the next tick.
    void setForceScale(double scale) noexcept;
    /// Haptics on/off; turning on restarts the soft start.
    void setEnabled(bool on) noexcept;
    /// TESTS ONLY: sets the stiffness with no passivity or device check (to show that the bound
    /// matters). Never call it in the application.
    void setStiffnessUnchecked(double stiffness) noexcept;

private:
    /// Contact level: the distance (m) at which the tool touches.
    double level() const noexcept { return mSettings.toolRadius + mSettings.offset; }
    /// Distance minus level at `p` and the unit gradient there (a zero vector where it vanishes).
    double gap(adf::AdfAccessor& clay, const glm::dvec3& p, glm::dvec3* normal = nullptr) const noexcept;
    /// Fraction t in [0, 1] of the segment from `from` (free) to `to` reachable before the tool
    /// touches: 1 when the whole segment is free.
    double freeFraction(adf::AdfAccessor& clay, const glm::dvec3& from, const glm::dvec3& to) const noexcept;
    /// Moves `p` back onto the contact surface along the gradient (kProjectSteps Newton steps).
    glm::dvec3 project(adf::AdfAccessor& clay, glm::dvec3 p) const noexcept;
    /// The god-object step: the proxy from `from` toward `target`, stopped and slid by the clay.
    glm::dvec3 constrainedMove(adf::AdfAccessor& clay, const glm::dvec3& from, const glm::dvec3& target,
                               bool& contact) noexcept;
    /// The carving step: free motion unlimited, motion inside the material <= `budget` (m).
    glm::dvec3 carveMove(adf::AdfAccessor& clay, const glm::dvec3& from, const glm::dvec3& target, double budget,
                         bool& contact) const noexcept;
    /// The settling step after the surface moved; true while still settling.
    bool settle(adf::AdfAccessor& clay, const glm::dvec3& target, double step, bool& contact) noexcept;
    /// Zero output with the proxy held; restarts the soft start.
    ProxyOutput hold(bool fault) noexcept;

    ProxySettings mSettings;
    Gains mGains;
    glm::dvec3 mProxy{0.0};
    glm::dvec3 mProxyVelocity{0.0};
    glm::dvec3 mLastDevice{0.0};   ///< the device position of the last good tick
    bool mHasProxy = false;    ///< false until the first good tick (then the proxy starts at the device)
    bool mContact = false;     ///< the last tick ended in contact
    bool mSticking = false;    ///< in contact and held by static friction
    bool mSettling = false;    ///< moving the proxy back to a surface that moved
    uint64_t mClayId = 0;
    bool mWaiting = true;      ///< soft start: waiting for the computed force to be small
    double mRamp = 0.0;        ///< soft start: 0..1
};

}  // namespace kizamu::haptics
