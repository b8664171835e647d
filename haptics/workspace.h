// SPDX-License-Identifier: Apache-2.0
/// @file workspace.h
/// @brief Where the device's workspace sits in the clay: a similarity (scale, rotation,
/// translation) from the device frame to the clay's world frame, the device spec as the
/// renderer sees it through that map (stiffness and damping scaled so the wall stays passive on
/// the device), and re-anchoring for the clutch and the fine (relative) mode.
///
/// The map: world = worldAnchor + scale · R (device − deviceAnchor). Forces are not scaled: the
/// hand feels, in newtons, the force the renderer computed in the world, turned by Rᵀ. A world
/// spring K_w then acts on the device as K_w · scale (a device displacement d moves the world
/// point by scale · d), and a world damper B_w as B_w · scale. So the renderer runs in the world
/// on worldSpec(): maxStiffness / scale and damping b / scale, which makes its passivity bound
/// 2 (b / scale − |B_w|) / T exactly the device's 2 (b − |B_w| scale) / T divided by scale
/// (Colgate and Schenkel's b > K·T/2 + |B| on the device side). A renderer built for one scale
/// stays passive at every smaller scale (the device-side stiffness K_w · scale only drops),
/// which is why the fine mode may only scale down.
///
/// Galyean and Hughes 2.2.2: a relative mode re-anchors the device's workspace to a small region
/// of the clay for fine work; here anchor() places any device point on any world point without
/// moving the tool, so switching scale or releasing the clutch never jumps.
/// A plain value; every function is noexcept, allocates nothing and is safe on the servo thread.
#pragma once

#include "haptics/device.h"

#include <glm/gtc/quaternion.hpp>
#include <glm/vec3.hpp>

namespace kizamu::haptics {

struct WorkspaceMapping {
    double scale = 1.0;                           ///< world m per device m, > 0
    glm::dquat rotation{1.0, 0.0, 0.0, 0.0};      ///< device axes to world axes (unit)
    glm::dvec3 deviceAnchor{0.0};                 ///< m, device frame
    glm::dvec3 worldAnchor{0.0};                  ///< m, world frame: where deviceAnchor lands

    /// The device's workspace box (spec.workspaceMin/Max) centred on the world box [lo, hi] and
    /// scaled so it fits inside it (the smallest of the three axis ratios), no rotation.
    static WorkspaceMapping fit(const DeviceSpec& spec, const glm::dvec3& lo, const glm::dvec3& hi) noexcept;

    glm::dvec3 toWorld(const glm::dvec3& devicePoint) const noexcept;
    /// The device point that maps to `worldPoint` (the inverse of toWorld).
    glm::dvec3 toDevice(const glm::dvec3& worldPoint) const noexcept;
    /// A device-frame vector (a velocity) in the world: scale · R v.
    glm::dvec3 vectorToWorld(const glm::dvec3& v) const noexcept;
    /// A world force (N) as the device renders it: Rᵀ f, not scaled (see the file comment).
    glm::dvec3 forceToDevice(const glm::dvec3& worldForce) const noexcept;
    /// The device's state in the world: position and velocity mapped, orientation R q; the rest
    /// (time, buttons, connected) unchanged.
    DeviceState toWorld(const DeviceState& device) const noexcept;
    /// The spec the world-frame renderer must use (see the file comment): maxStiffness and
    /// damping divided by scale, the workspace box mapped, the rest unchanged.
    DeviceSpec worldSpec(const DeviceSpec& device) const;
    /// Keeps scale and rotation and moves the anchors so `devicePoint` maps to `worldPoint`.
    void anchor(const glm::dvec3& devicePoint, const glm::dvec3& worldPoint) noexcept;
};

}  // namespace kizamu::haptics
