// SPDX-License-Identifier: Apache-2.0
/// @file hid_pid_device.h
/// @brief A HID force-feedback (PID) wheel or joystick as a haptics::Device: its one or two axes
/// move the tool in a plane of the clay, and the force's components in that plane become one
/// constant-force effect per axis.
///
/// Where it sits: haptics/hid/, beside sim/simulated_stylus.h (the same Device interface). The
/// servo thread (servo_loop.h) calls read() and write(); a device thread owned by HidPidDevice
/// exchanges the HID reports through a HidTransport (hidapi_transport.h on Linux hidraw, a
/// scripted one in tests). Threads and why: USB transfers block for up to a frame, so they
/// never run on the servo thread. The device thread publishes each decoded input report through
/// a wait-free mailbox (util::TripleBuffer: read() takes the newest whole state, never waits)
/// and takes the newest force from a single atomic word (two floats), so the servo thread
/// neither blocks, allocates nor does I/O.
///
/// Mapping (1-2 axis devices; the device frame of DeviceState, m and N):
///  - axis 1 -> tool x, axis 2 -> tool y; position = axisSign × (normalised axis value, -1..1)
///    × workspaceHalfWidth. The axes used are the force axes (PidCodec::forceAxes(): the
///    Set Effect report's Axes Enable bits), so a one-axis device (a wheel) keeps y = 0.
///  - z = HidPidSettings::depth, fixed: the plane sits at a fixed depth in the clay and depth is
///    left to the application's surface following (the device has no third axis to render it).
///  - force x, y (N) -> each axis' constant-force magnitude = axisSign × F / maxForce of full
///    scale, clamped to the logical range; force z is not rendered. maxForce is the device's
///    (device_table.h) or the settings'.
///  - velocity: finite differences of successive input reports' positions, low-pass filtered
///    (first order, velocityCutoffHz).
///  - non-finite forces become zero before they reach the mailbox; a transport error (unplugged)
///    stops the device thread, read() then returns false with connected = false, and no force
///    is sent again; stop() and the destructor send zero force, stop the effects and disable
///    the actuators.
///
/// Backend checklist:
///  [X] setup: reset, enable actuators, Create New Effect / Block Load or host block indices,
///      Set Effect, zero magnitude, start, per force axis
///  [X] per-report force streaming (only when a quantised magnitude changes)
///  [X] input decoding to position, filtered velocity, buttons (engine::ToolButton bits = the
///      device's first buttons, bit i = button i + 1)
///  [X] disconnect -> connected false, zero force; non-finite -> zero; stop -> zero and stop
///  [ ] reconnection (open a new HidPidDevice), PID State input (safety switch) not read
///  [ ] measured damping and stiffness per device (HidPidSettings carries assumed figures)
/// Changes (breaking):
///  2026-12-06 first version (issue 32).
#pragma once

#include "haptics/device.h"
#include "util/triple_buffer.h"
#include "haptics/hid/hid_pid_codec.h"

#include <glm/vec3.hpp>

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <thread>

namespace kizamu::haptics::hid {

/// A device that refuses its setup or cannot be opened (cold paths only).
class HidDeviceError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// The byte pipe to one HID device. Requirements:
///  - calls come from one thread at a time (HidPidDevice's device thread, or its controlling
///    thread in start() and stop() while the device thread is not running);
///  - output and feature buffers start with the report ID (0 for unnumbered reports), input
///    reports are returned as hidapi's hid_read returns them (the ID first when numbered);
///  - a negative or false return means the device is gone or broken (HidPidDevice stops using it).
/// Owned by the HidPidDevice it is given to.
class HidTransport {
public:
    virtual ~HidTransport() = default;
    /// Sends an output report. False on error.
    virtual bool writeReport(std::span<const uint8_t> report) = 0;
    /// Waits up to `timeoutMs` for one input report and copies it into `buffer`. Returns its
    /// bytes, 0 on timeout, -1 on error.
    virtual int readReport(std::span<uint8_t> buffer, int timeoutMs) = 0;
    /// Sends a feature report. False on error.
    virtual bool sendFeature(std::span<const uint8_t> report) = 0;
    /// Gets the feature report whose ID is `buffer[0]` into `buffer`. Returns its bytes (ID
    /// included), -1 on error.
    virtual int getFeature(std::span<uint8_t> buffer) = 0;
};

/// What a HidPidDevice is configured with. SI units.
struct HidPidSettings {
    std::string name = "HID PID device";
    double workspaceHalfWidth = 0.05;  ///< m: axis value ±1 maps to ±this
    double depth = 0.0;                ///< m: z of the tool plane in the device frame
    double maxForce = 3.0;             ///< N at full-scale magnitude (device_table.h's figure)
    /// N·s/m: the physical damping the renderer's passivity bound uses. Assumed (a motor's
    /// back-EMF damping at the handle is of this order), not measured: measure per rig.
    double damping = 0.5;
    double maxStiffness = 0.0;         ///< N/m; 0: the renderer's passivity bound decides
    double velocityCutoffHz = 30.0;    ///< Hz, the velocity filter's cutoff
    /// ms the device thread waits for an input report (1..1000): the longest a posted force
    /// waits to be sent when the device reports nothing.
    int readTimeoutMs = 2;
    std::array<double, 2> axisSign{1.0, 1.0};  ///< ±1: flips an axis (position and force)
    CodecSettings codec;
};

/// Device-thread counters, for tests and diagnostics. Any thread (relaxed atomics).
struct HidPidCounters {
    uint64_t inputReports = 0;   ///< decoded joystick reports
    uint64_t forceReports = 0;   ///< Set Constant Force reports sent while streaming
};

/// Owned by the application (one per device). start() and stop() from one controlling thread;
/// read() and write() from the servo thread (Device's contract); counters() from any thread.
class HidPidDevice final : public Device {
public:
    /// Takes the transport; sends nothing until start().
    /// @throw std::invalid_argument for a layout without axes or settings out of range
    ///        (workspaceHalfWidth or maxForce <= 0, non-finite depth, velocityCutoffHz <= 0,
    ///        readTimeoutMs outside 1..1000).
    HidPidDevice(std::unique_ptr<HidTransport> transport, const PidLayout& layout,
                 const HidPidSettings& settings = {});
    /// stop().
    ~HidPidDevice() override;
    HidPidDevice(const HidPidDevice&) = delete;
    HidPidDevice& operator=(const HidPidDevice&) = delete;

    /// Runs the setup on the calling thread (see the checklist), then starts the device thread.
    /// @throw HidDeviceError when a report cannot be sent or the device refuses an effect (the
    ///        actuators are disabled again first); std::logic_error when already started.
    /// Complexity: a few USB transfers per axis. Cold path.
    void start();
    /// Ends the device thread, then (if the device still answers) sends zero force, stops the
    /// effects and disables the actuators. Idempotent. Controlling thread.
    void stop() noexcept;

    const DeviceSpec& spec() const noexcept override { return mSpec; }
    /// The newest published state (the centre of the plane until the first input report).
    /// False (out.connected false, last position kept) before start(), after stop() and once
    /// the transport failed. Servo thread; never blocks.
    bool read(DeviceState& out) noexcept override;
    /// Posts `force` (N, device frame) for the device thread; x, y are rendered, z is not;
    /// non-finite -> zero. Servo thread (or the watchdog's zero); never blocks.
    void write(const glm::dvec3& force) noexcept override;

    bool connected() const noexcept { return mConnected.load(std::memory_order_acquire); }
    /// Force axes in use (1 or 2).
    int forceAxes() const noexcept { return mForceAxes; }
    HidPidCounters counters() const noexcept;
    const PidCodec& codec() const noexcept { return mCodec; }

private:
    void deviceThread() noexcept;
    /// Device thread: encodes and sends the posted force when a magnitude changed. False on a
    /// transport error.
    bool sendForce() noexcept;
    /// Device thread: turns one decoded input report into position, velocity and buttons and
    /// publishes them through the mailbox.
    void publish(const InputSample& sample, int64_t timeNs) noexcept;
    /// Sends zero force, stops the effects, disables the actuators; ignores errors.
    void shutdownEffects() noexcept;
    void checkedWrite(const ReportBuffer& report, const char* what);

    std::unique_ptr<HidTransport> mTransport;
    PidCodec mCodec;
    HidPidSettings mSettings;
    DeviceSpec mSpec;
    int mForceAxes = 1;
    std::array<uint8_t, 2> mBlockIndex{1, 2};
    bool mStarted = false;       ///< controlling thread
    std::thread mThread;
    std::atomic<bool> mStop{false};
    std::atomic<bool> mConnected{false};  ///< started and the transport answers

    // Force mailbox: x and y as two floats in one word (written by the servo side).
    std::atomic<uint64_t> mForceWord{0};

    /// What the device thread publishes for the servo thread (its one writer and one reader).
    struct Published {
        glm::dvec3 position{0.0}, velocity{0.0};
        int64_t timeNs = 0;
        uint32_t buttons = 0;
        bool valid = false;  ///< false until the first report (or start())
    };
    util::TripleBuffer<Published> mState;
    DeviceState mLastRead;       ///< servo thread: the state read() returns

    // Device-thread state.
    ReportBuffer mIn, mOut;
    std::array<int64_t, 2> mSentMagnitude{0, 0};
    glm::dvec3 mPrevPos{0.0}, mVel{0.0};
    int64_t mPrevTimeNs = -1;
    std::atomic<uint64_t> mInputReports{0}, mForceReports{0};
};

}  // namespace kizamu::haptics::hid
