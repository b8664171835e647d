// SPDX-License-Identifier: Apache-2.0
/// @file hid_pid_codec.h
/// @brief The bytes of the HID PID reports that stream one constant force per axis, and the
/// decoding of a joystick input report into normalised axes and buttons.
///
/// Where it sits: pure code between hid_report_descriptor.h (which finds the fields) and
/// hid_pid_device.h (whose device thread sends the bytes). Every encoder fills a caller-owned
/// ReportBuffer of fixed capacity: nothing allocates per report, so the device thread's
/// per-tick path (encodeConstantForce, decodeInput) allocates nothing.
/// Threading: a PidCodec is immutable after construction; its const members may run on any
/// number of threads at once.
///
/// Report bytes follow hidapi's conventions. Output and feature buffers always start with the
/// report ID byte, 0 for a descriptor without report IDs (hid_write, hid_send_feature_report,
/// hid_get_feature_report); an input report starts with its ID only when the descriptor numbers
/// its reports (hid_read). Fields are packed little-endian from bit 0 of the byte after the ID
/// (HID 1.11 §5.8 and §6.2.2.7: values are packed LSB first in the order of the main items).
///
/// Conventions used (sources in hid_report_descriptor.h; and for Duration):
///  - Duration = the field's all-ones bit pattern ("null", outside the logical range) means an
///    infinite effect: the PID spec's convention, as Linux's hid-pidff driver sends it for a
///    length of 0 (the hid-pidff duration patch on linux-input, "Convert infinite length from
///    Linux API (0) to PID standard (NULL)", PID_INFINITE 0xffff).
///  - Magnitude of a constant force is signed: fraction -1..1 of full scale maps to
///    -logicalMax..logicalMax, rounded, clamped to the logical range (PID 1.0: Magnitude of the
///    Set Constant Force report; OpenFFBoard declares -32767..32767).
///  - A force on one axis is its own effect: Axes Enable has only that axis' bit, Direction
///    Enable is 0, Direction instance 1 is CodecSettings::directionDeg of that axis (degrees
///    scaled onto the field's logical range, 0..360°) and instance 2 its minimum. Whether a given firmware reads
///    Direction with one axis enabled is firmware specific; the defaults follow the DirectInput
///    polar convention the PID spec adopts (0° = north, 90° = east), so axis 1 (X) gets 90°
///    and axis 2 (Y) 0°.
///
/// Features:
///  [X] Device Control (enable/disable actuators, stop all, reset), array or one bit per command
///  [X] Create New Effect / Block Load (device-managed pools), host-chosen indices otherwise
///  [X] Set Effect (constant force, infinite, full gain, one axis), Set Constant Force, Effect
///      Operation start/stop, Device Gain
///  [X] input decoding: up to 8 axes normalised to -1..1, up to 32 buttons
///  [ ] envelopes, conditions, periodic effects (not needed for a rendered force)
#pragma once

#include "haptics/hid/hid_report_descriptor.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>

namespace kizamu::haptics::hid {

/// The capacity of a ReportBuffer: a full-speed USB interrupt packet (64 bytes) and the ID byte
/// hidapi puts before an unnumbered report. findPidLayout() rejects descriptors whose reports
/// are longer than 64 bytes.
constexpr std::size_t kMaxReportBytes = 65;

/// One report, ready to send or to receive into (byte 0 the report ID). Plain data, fixed
/// capacity.
struct ReportBuffer {
    std::array<uint8_t, kMaxReportBytes> bytes{};
    std::size_t size = 0;
    std::span<const uint8_t> view() const noexcept { return {bytes.data(), size}; }
};

/// Writes `value` into `field` of `data` (the bytes after the report ID), clamped to the
/// field's logical range, little-endian. Bits outside the field are kept. A field reaching
/// past `data` writes nothing. Complexity: O(field bits / 8). Any thread; no allocation.
void packField(std::span<uint8_t> data, const FieldLocation& field, int64_t value) noexcept;
/// Writes the low `field.bitSize` bits of `raw` without clamping (the null value, e.g.).
void packRaw(std::span<uint8_t> data, const FieldLocation& field, uint64_t raw) noexcept;
/// Reads `field` from `data` (bytes after the report ID); sign-extended when the logical
/// minimum is negative. 0 for a field reaching past `data`.
int64_t unpackField(std::span<const uint8_t> data, const FieldLocation& field) noexcept;

enum class DeviceCommand : uint8_t { EnableActuators, DisableActuators, StopAllEffects, Reset };
enum class EffectOp : uint8_t { Start, Stop };

/// A decoded input report. Plain data.
struct InputSample {
    std::array<double, PidLayout::kMaxAxes> axes{};  ///< -1..1 over each axis' logical range
    std::size_t axisCount = 0;
    uint32_t buttons = 0;                            ///< bit i: button i + 1 pressed
};

/// Choices for the effects the codec writes.
struct CodecSettings {
    /// Direction written for the effect of axis 1 and axis 2, degrees (see the file comment).
    std::array<double, 2> directionDeg{90.0, 0.0};
};

/// Encodes and decodes the reports of one device. Owned by the device (one per device);
/// immutable once built, so its const members are safe from any thread.
class PidCodec {
public:
    explicit PidCodec(const PidLayout& layout, const CodecSettings& settings = {});

    const PidLayout& layout() const noexcept { return mLayout; }
    /// Force axes the device can take a constant force on (1 or 2): the X and Y bits its Set
    /// Effect report's Axes Enable has (a wheel's input report may list more axes than it
    /// drives: OpenFFBoard's has eight, its wheel mode one force axis); without Axes Enable,
    /// min(input axes, 2).
    int forceAxes() const noexcept;
    /// Whether effects are created through Create New Effect / Block Load (device-managed
    /// block indices) rather than picked by the host (1, 2, ...).
    bool createsEffects() const noexcept { return mLayout.createNewEffect.report.present(); }

    /// PID Device Control. False (and `out` empty) when the device lacks the command.
    bool encodeDeviceControl(DeviceCommand command, ReportBuffer& out) const noexcept;
    /// Create New Effect (feature) for a constant force. False when the device has none.
    bool encodeCreateNewEffect(ReportBuffer& out) const noexcept;
    /// A Block Load feature buffer to pass to a get-feature call (report ID set, zeroed).
    /// False when the device has none.
    bool prepareBlockLoad(ReportBuffer& out) const noexcept;
    /// The block index a Block Load report (as got, report ID first) assigned, or nothing when
    /// its status is not success or the report is too short or has another ID.
    std::optional<uint8_t> decodeBlockLoad(std::span<const uint8_t> report) const noexcept;
    /// Set Effect: a constant force on axis `axis` (0: X, 1: Y), infinite, full gain.
    void encodeSetEffect(uint8_t blockIndex, int axis, ReportBuffer& out) const noexcept;
    /// Set Constant Force with magnitude `fraction` of full scale (-1..1; clamped; NaN -> 0).
    /// The per-tick report. Complexity: O(report bytes). No allocation.
    void encodeConstantForce(uint8_t blockIndex, double fraction, ReportBuffer& out) const noexcept;
    /// Effect Operation: start (loop count 1) or stop.
    void encodeEffectOperation(uint8_t blockIndex, EffectOp op, ReportBuffer& out) const noexcept;
    /// Device Gain at `fraction` (0..1) of its range. False when the device has none.
    bool encodeDeviceGain(double fraction, ReportBuffer& out) const noexcept;

    /// The logical Magnitude value for `fraction` (see the file comment).
    int64_t magnitudeValue(double fraction) const noexcept;

    /// Decodes an input report (report ID first when numbered). False when it is not the
    /// joystick report (another ID) or is shorter than it; `out` is then unchanged.
    /// Complexity: O(axes + buttons). No allocation.
    bool decodeInput(std::span<const uint8_t> report, InputSample& out) const noexcept;

private:
    /// Zeroes `out`, sets the ID byte (0 when unnumbered) and the size; returns the bytes after
    /// the ID.
    std::span<uint8_t> begin(const ReportLocation& report, ReportBuffer& out) const noexcept;

    PidLayout mLayout;
    CodecSettings mSettings;
};

}  // namespace kizamu::haptics::hid
