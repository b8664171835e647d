// SPDX-License-Identifier: Apache-2.0
/// @file workspace.cpp
/// @brief WorkspaceMapping: the device-to-world similarity and the spec it implies.
#include "haptics/workspace.h"

#include <glm/common.hpp>

#include <algorithm>
#include <cmath>

namespace kizamu::haptics {

WorkspaceMapping WorkspaceMapping::fit(const DeviceSpec& spec, const glm::dvec3& lo, const glm::dvec3& hi) noexcept {
    WorkspaceMapping m;
    const glm::dvec3 device = spec.workspaceMax - spec.workspaceMin;
    const glm::dvec3 world = hi - lo;
    double s = 0.0;
    for (int a = 0; a < 3; ++a)
        if (device[a] > 0.0) s = s == 0.0 ? world[a] / device[a] : std::min(s, world[a] / device[a]);
    m.scale = s > 0.0 ? s : 1.0;
    m.deviceAnchor = (spec.workspaceMin + spec.workspaceMax) * 0.5;
    m.worldAnchor = (lo + hi) * 0.5;
    return m;
}

glm::dvec3 WorkspaceMapping::toWorld(const glm::dvec3& devicePoint) const noexcept {
    return worldAnchor + vectorToWorld(devicePoint - deviceAnchor);
}

glm::dvec3 WorkspaceMapping::toDevice(const glm::dvec3& worldPoint) const noexcept {
    return deviceAnchor + (glm::inverse(rotation) * (worldPoint - worldAnchor)) / scale;
}

glm::dvec3 WorkspaceMapping::vectorToWorld(const glm::dvec3& v) const noexcept { return scale * (rotation * v); }

glm::dvec3 WorkspaceMapping::forceToDevice(const glm::dvec3& worldForce) const noexcept {
    return glm::inverse(rotation) * worldForce;
}

DeviceState WorkspaceMapping::toWorld(const DeviceState& device) const noexcept {
    DeviceState w = device;
    w.position = toWorld(device.position);
    w.velocity = vectorToWorld(device.velocity);
    w.orientation = rotation * device.orientation;
    return w;
}

DeviceSpec WorkspaceMapping::worldSpec(const DeviceSpec& device) const {
    DeviceSpec w = device;
    w.maxStiffness = device.maxStiffness / scale;
    w.damping = device.damping / scale;
    // The box of the eight mapped corners (a rotation turns the box).
    w.workspaceMin = glm::dvec3(HUGE_VAL);
    w.workspaceMax = glm::dvec3(-HUGE_VAL);
    for (int c = 0; c < 8; ++c) {
        const glm::dvec3 corner((c & 1) ? device.workspaceMax.x : device.workspaceMin.x,
                                (c & 2) ? device.workspaceMax.y : device.workspaceMin.y,
                                (c & 4) ? device.workspaceMax.z : device.workspaceMin.z);
        w.workspaceMin = glm::min(w.workspaceMin, toWorld(corner));
        w.workspaceMax = glm::max(w.workspaceMax, toWorld(corner));
    }
    return w;
}

void WorkspaceMapping::anchor(const glm::dvec3& devicePoint, const glm::dvec3& worldPoint) noexcept {
    deviceAnchor = devicePoint;
    worldAnchor = worldPoint;
}

}  // namespace kizamu::haptics
