// SPDX-License-Identifier: Apache-2.0
/// @file device.h
/// @brief One interface for every haptic device (simulated stylus, Novint Falcon, HID
/// force-feedback devices): state in, force out, and the device's specification. SI units.
///
/// Where it sits: the servo thread (servo_loop.h) reads a Device once per tick and writes the
/// force the renderer (proxy_renderer.h) computed. Implementations: sim/simulated_stylus.h (and
/// sim/realtime_stylus.h on the wall clock), the Novint Falcon over libusb
/// (haptics/falcon/falcon_device.h), HID force-feedback (PID) devices over hidapi
/// (haptics/hid/hid_pid_device.h). Threading: read() and write() are called from the servo thread, and write() of a zero force also from the
/// servo loop's watchdog thread, never at the same time as another call (servo_loop.h, the
/// gate); both keep the servo thread's contract: no lock another thread holds, no allocation,
/// no I/O that can block (a real device's transfers are asynchronous and preallocated, or run on
/// a device thread behind a lock-free mailbox).
#pragma once

#include <glm/gtc/quaternion.hpp>
#include <glm/vec3.hpp>

#include <cstdint>
#include <string>

namespace kizamu::haptics {

/// What a device reports at one instant, in the device's own frame (m, m/s).
struct DeviceState {
    int64_t timeNs = 0;                              ///< when it was read (the servo clock)
    glm::dvec3 position{0.0};                        ///< m, the end effector in the device frame
    glm::dquat orientation{1.0, 0.0, 0.0, 0.0};      ///< device frame; identity on a 3-DOF device
    glm::dvec3 velocity{0.0};                        ///< m/s, as the device or its driver estimates it
    uint32_t buttons = 0;                            ///< engine::ToolButton bits
    bool connected = true;                           ///< false once the device stopped answering
};

/// A device's published limits (the manufacturer's figures), what the renderer keeps within.
struct DeviceSpec {
    std::string name;
    double maxForce = 0.0;      ///< N, the most the device may be asked for (continuous)
    double maxStiffness = 0.0;  ///< N/m, the stiffest wall the device renders stably at `rate`
    double damping = 0.0;       ///< N·s/m, the device's own physical damping (b in the passivity bound)
    double rate = 1000.0;       ///< Hz, the servo rate the figures hold at
    glm::dvec3 workspaceMin{0.0}, workspaceMax{0.0};  ///< m, the reachable box in the device frame
    bool orientation = false;   ///< whether the device measures orientation (6-DOF input)
};

/// A haptic device. Owned by the application; used by the servo thread.
class Device {
public:
    virtual ~Device() = default;
    virtual const DeviceSpec& spec() const noexcept = 0;
    /// The newest state; false (and `out.connected` false) when the device stopped answering.
    /// Servo thread only; never blocks, never allocates.
    virtual bool read(DeviceState& out) noexcept = 0;
    /// The force to render now (N, device frame). Callers never pass non-finite values and keep
    /// |force| <= spec().maxForce (the servo loop checks both). The servo thread, or the
    /// watchdog's zero (never two calls at once).
    virtual void write(const glm::dvec3& force) noexcept = 0;
};

/// The passivity bound of a spring-damper wall rendered at sample period T (s) on a device with
/// physical damping b (N·s/m), with virtual damping B (N·s/m): the wall is passive when
/// b > K·T/2 + |B| (Colgate and Schenkel), so the stiffest passive K is 2 (b − |B|) / T (0 when
/// |B| >= b).
inline double passiveStiffnessBound(double deviceDamping, double virtualDamping, double period) {
    const double margin = deviceDamping - (virtualDamping < 0.0 ? -virtualDamping : virtualDamping);
    return margin > 0.0 ? 2.0 * margin / period : 0.0;
}

}  // namespace kizamu::haptics
