// SPDX-License-Identifier: Apache-2.0
/// @file hid_pid_codec.cpp
/// @brief Report encoding and decoding for HID PID devices (conventions: the header).
#include "haptics/hid/hid_pid_codec.h"

#include <algorithm>
#include <cmath>

namespace kizamu::haptics::hid {

namespace {

bool fits(std::size_t bytes, const FieldLocation& f) {
    return f.present() && f.bitSize <= 64 && uint64_t(f.bitOffset) + f.bitSize <= uint64_t(bytes) * 8;
}

/// Rounds `fraction` (clamped to 0..1) of the logical range up from its minimum.
int64_t scaleUnsigned(const FieldLocation& f, double fraction) {
    fraction = std::isfinite(fraction) ? std::clamp(fraction, 0.0, 1.0) : 0.0;
    return f.logicalMin + int64_t(std::llround(fraction * double(f.logicalMax - f.logicalMin)));
}

}  // namespace

void packRaw(std::span<uint8_t> data, const FieldLocation& f, uint64_t raw) noexcept {
    if (!fits(data.size(), f)) return;
    for (uint32_t b = 0; b < f.bitSize; ++b) {
        const uint32_t bit = f.bitOffset + b;
        const uint8_t mask = uint8_t(1u << (bit % 8));
        if ((raw >> b) & 1u)
            data[bit / 8] |= mask;
        else
            data[bit / 8] &= uint8_t(~mask);
    }
}

void packField(std::span<uint8_t> data, const FieldLocation& f, int64_t value) noexcept {
    if (f.logicalMin <= f.logicalMax) value = std::clamp(value, f.logicalMin, f.logicalMax);
    packRaw(data, f, uint64_t(value));
}

int64_t unpackField(std::span<const uint8_t> data, const FieldLocation& f) noexcept {
    if (!fits(data.size(), f)) return 0;
    uint64_t raw = 0;
    for (uint32_t b = 0; b < f.bitSize; ++b) {
        const uint32_t bit = f.bitOffset + b;
        raw |= uint64_t((data[bit / 8] >> (bit % 8)) & 1u) << b;
    }
    if (f.logicalMin < 0 && f.bitSize < 64 && ((raw >> (f.bitSize - 1)) & 1u))
        raw |= ~uint64_t(0) << f.bitSize;  // sign-extend
    return int64_t(raw);
}

PidCodec::PidCodec(const PidLayout& layout, const CodecSettings& settings)
    : mLayout(layout), mSettings(settings) {}

int PidCodec::forceAxes() const noexcept {
    const auto& enable = mLayout.setEffect.axisEnable;
    const int enabled = int(enable[0].present()) + int(enable[1].present());
    if (enabled > 0) return enabled;
    return int(std::min<std::size_t>(mLayout.axisCount, 2));
}

std::span<uint8_t> PidCodec::begin(const ReportLocation& report, ReportBuffer& out) const noexcept {
    out.bytes.fill(0);
    // An unnumbered report's size has no ID byte; the buffer gets one (0) all the same.
    out.size = std::min<std::size_t>(report.id != 0 ? report.bytes : report.bytes + 1, kMaxReportBytes);
    out.bytes[0] = report.id;
    return {out.bytes.data() + 1, out.size - 1};
}

bool PidCodec::encodeDeviceControl(DeviceCommand command, ReportBuffer& out) const noexcept {
    const auto& dc = mLayout.deviceControl;
    const FieldChoice& c = command == DeviceCommand::EnableActuators    ? dc.enableActuators
                           : command == DeviceCommand::DisableActuators ? dc.disableActuators
                           : command == DeviceCommand::StopAllEffects   ? dc.stopAllEffects
                                                                        : dc.reset;
    if (!c.present()) {
        out.size = 0;
        return false;
    }
    packField(begin(dc.report, out), c.field, c.value);
    return true;
}

bool PidCodec::encodeCreateNewEffect(ReportBuffer& out) const noexcept {
    const auto& n = mLayout.createNewEffect;
    if (!n.report.present()) {
        out.size = 0;
        return false;
    }
    packField(begin(n.report, out), n.typeConstant.field, n.typeConstant.value);
    return true;
}

bool PidCodec::prepareBlockLoad(ReportBuffer& out) const noexcept {
    if (!mLayout.blockLoad.report.present()) {
        out.size = 0;
        return false;
    }
    begin(mLayout.blockLoad.report, out);
    return true;
}

std::optional<uint8_t> PidCodec::decodeBlockLoad(std::span<const uint8_t> report) const noexcept {
    const auto& b = mLayout.blockLoad;
    const std::size_t bytes = b.report.id != 0 ? b.report.bytes : b.report.bytes + 1;
    if (!b.report.present() || report.size() < bytes || report[0] != b.report.id) return std::nullopt;
    const auto data = report.subspan(1);
    if (unpackField(data, b.success.field) != b.success.value) return std::nullopt;
    const int64_t index = unpackField(data, b.blockIndex);
    if (index < 1 || index > 255) return std::nullopt;
    return uint8_t(index);
}

void PidCodec::encodeSetEffect(uint8_t blockIndex, int axis, ReportBuffer& out) const noexcept {
    const auto& s = mLayout.setEffect;
    const auto data = begin(s.report, out);
    packField(data, s.blockIndex, blockIndex);
    packField(data, s.typeConstant.field, s.typeConstant.value);
    if (s.duration.present()) packRaw(data, s.duration, ~uint64_t(0));  // null: infinite
    packField(data, s.triggerRepeatInterval, 0);
    packField(data, s.samplePeriod, 0);
    packField(data, s.startDelay, 0);
    if (s.gain.present()) packField(data, s.gain, s.gain.logicalMax);
    // Trigger button: the null value (no trigger) where the range excludes 0.
    if (s.triggerButton.present()) {
        if (s.triggerButton.logicalMin > 0)
            packRaw(data, s.triggerButton, ~uint64_t(0));
        else
            packField(data, s.triggerButton, 0);
    }
    for (int a = 0; a < 2; ++a)
        if (s.axisEnable[a].present()) packRaw(data, s.axisEnable[a], a == axis ? 1u : 0u);
    if (s.directionEnable.present()) packRaw(data, s.directionEnable, 0u);
    // Direction instance 1 carries the axis' angle, instance 2 stays 0.
    if (s.direction[0].present()) {
        const double deg = mSettings.directionDeg[axis == 1 ? 1 : 0];
        const double wrapped = std::fmod(std::fmod(deg, 360.0) + 360.0, 360.0);
        // 0..360° over the logical range (OpenFFBoard: 0..36000, hundredths of a degree).
        const FieldLocation& f = s.direction[0];
        const double span = double(f.logicalMax - f.logicalMin);
        packField(data, f, f.logicalMin + int64_t(std::llround(wrapped / 360.0 * span)));
    }
    if (s.direction[1].present()) packField(data, s.direction[1], s.direction[1].logicalMin);
}

int64_t PidCodec::magnitudeValue(double fraction) const noexcept {
    const FieldLocation& m = mLayout.constantForce.magnitude;
    if (!std::isfinite(fraction)) fraction = 0.0;
    fraction = std::clamp(fraction, -1.0, 1.0);
    const int64_t full = m.logicalMax;
    const int64_t v = int64_t(std::llround(fraction * double(full)));
    return std::clamp(v, m.logicalMin, m.logicalMax);
}

void PidCodec::encodeConstantForce(uint8_t blockIndex, double fraction, ReportBuffer& out) const noexcept {
    const auto& c = mLayout.constantForce;
    const auto data = begin(c.report, out);
    packField(data, c.blockIndex, blockIndex);
    packField(data, c.magnitude, magnitudeValue(fraction));
}

void PidCodec::encodeEffectOperation(uint8_t blockIndex, EffectOp op, ReportBuffer& out) const noexcept {
    const auto& e = mLayout.effectOperation;
    const auto data = begin(e.report, out);
    packField(data, e.blockIndex, blockIndex);
    const FieldChoice& c = op == EffectOp::Start ? e.start : e.stop;
    packField(data, c.field, c.value);
    packField(data, e.loopCount, 1);
}

bool PidCodec::encodeDeviceGain(double fraction, ReportBuffer& out) const noexcept {
    const auto& g = mLayout.deviceGain;
    if (!g.report.present()) {
        out.size = 0;
        return false;
    }
    packField(begin(g.report, out), g.gain, scaleUnsigned(g.gain, fraction));
    return true;
}

bool PidCodec::decodeInput(std::span<const uint8_t> report, InputSample& out) const noexcept {
    const auto& in = mLayout.input;
    if (report.size() < in.bytes) return false;
    if (in.id != 0 && report[0] != in.id) return false;
    const auto data = in.id != 0 ? report.subspan(1) : report;
    out.axisCount = mLayout.axisCount;
    for (std::size_t a = 0; a < mLayout.axisCount; ++a) {
        const FieldLocation& f = mLayout.axes[a].field;
        const double span = double(f.logicalMax - f.logicalMin);
        const double v = double(unpackField(data, f));
        out.axes[a] = span > 0.0 ? std::clamp(2.0 * (v - double(f.logicalMin)) / span - 1.0, -1.0, 1.0) : 0.0;
    }
    uint32_t buttons = 0;
    for (uint32_t b = 0; b < mLayout.buttonCount; ++b) {
        const uint32_t bit = mLayout.buttonsBitOffset + b;
        if (bit / 8 < data.size() && ((data[bit / 8] >> (bit % 8)) & 1u)) buttons |= 1u << b;
    }
    out.buttons = buttons;
    return true;
}

}  // namespace kizamu::haptics::hid
