// SPDX-License-Identifier: Apache-2.0
/// @file hid_pid_codec_test.cpp
/// @brief Report bytes against hand-worked expectations (bit layouts: pid_fixture.h), input
/// decoding, and the device table.
#include "haptics/hid/device_table.h"
#include "haptics/hid/hid_pid_codec.h"
#include "unit/haptics/hid/pid_fixture.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace kizamu::haptics::hid {
namespace {

std::vector<uint8_t> bytesOf(const ReportBuffer& r) { return {r.bytes.begin(), r.bytes.begin() + long(r.size)}; }

PidCodec fixtureCodec() { return PidCodec(findPidLayout(parseReportDescriptor(fixture::joystick()))); }

TEST(HidPidCodec, DeviceControl) {
    const PidCodec c = fixtureCodec();
    ReportBuffer r;
    ASSERT_TRUE(c.encodeDeviceControl(DeviceCommand::EnableActuators, r));
    EXPECT_EQ(bytesOf(r), (std::vector<uint8_t>{0x0C, 0x01}));
    ASSERT_TRUE(c.encodeDeviceControl(DeviceCommand::DisableActuators, r));
    EXPECT_EQ(bytesOf(r), (std::vector<uint8_t>{0x0C, 0x02}));
    ASSERT_TRUE(c.encodeDeviceControl(DeviceCommand::StopAllEffects, r));
    EXPECT_EQ(bytesOf(r), (std::vector<uint8_t>{0x0C, 0x03}));
    ASSERT_TRUE(c.encodeDeviceControl(DeviceCommand::Reset, r));
    EXPECT_EQ(bytesOf(r), (std::vector<uint8_t>{0x0C, 0x04}));
}

TEST(HidPidCodec, DeviceControlBits) {
    const PidCodec c(findPidLayout(parseReportDescriptor(fixture::joystickDeviceControlBits())));
    ReportBuffer r;
    ASSERT_TRUE(c.encodeDeviceControl(DeviceCommand::EnableActuators, r));
    EXPECT_EQ(bytesOf(r), (std::vector<uint8_t>{0x0C, 0x01}));
    ASSERT_TRUE(c.encodeDeviceControl(DeviceCommand::Reset, r));
    EXPECT_EQ(bytesOf(r), (std::vector<uint8_t>{0x0C, 0x08}));
    ASSERT_TRUE(c.encodeDeviceControl(DeviceCommand::DisableActuators, r));
    EXPECT_EQ(bytesOf(r), (std::vector<uint8_t>{0x0C, 0x02}));
}

TEST(HidPidCodec, CreateNewEffectAndBlockLoad) {
    const PidCodec c = fixtureCodec();
    EXPECT_TRUE(c.createsEffects());
    ReportBuffer r;
    ASSERT_TRUE(c.encodeCreateNewEffect(r));
    EXPECT_EQ(bytesOf(r), (std::vector<uint8_t>{0x11, 0x01}));
    ASSERT_TRUE(c.prepareBlockLoad(r));
    EXPECT_EQ(bytesOf(r), (std::vector<uint8_t>{0x12, 0x00, 0x00}));
    const std::vector<uint8_t> ok = {0x12, 0x03, 0x01};
    ASSERT_TRUE(c.decodeBlockLoad(ok).has_value());
    EXPECT_EQ(*c.decodeBlockLoad(ok), 3);
    const std::vector<uint8_t> full = {0x12, 0x03, 0x02};
    EXPECT_FALSE(c.decodeBlockLoad(full).has_value());
    const std::vector<uint8_t> shortReport = {0x12, 0x03};
    EXPECT_FALSE(c.decodeBlockLoad(shortReport).has_value());
    const std::vector<uint8_t> otherId = {0x13, 0x03, 0x01};
    EXPECT_FALSE(c.decodeBlockLoad(otherId).has_value());
}

TEST(HidPidCodec, SetEffectPerAxis) {
    const PidCodec c = fixtureCodec();
    ReportBuffer r;
    // Axis X, block 1: constant (1), duration null (infinite), gain 255, X enabled, direction
    // 90° = 9000 = 0x2328 on 0..36000, instance 2 zero.
    c.encodeSetEffect(1, 0, r);
    EXPECT_EQ(bytesOf(r), (std::vector<uint8_t>{0x01, 0x01, 0x01, 0xFF, 0xFF, 0xFF, 0x01, 0x28, 0x23, 0x00, 0x00}));
    // Axis Y, block 2: Y enabled (bit 41), direction 0°.
    c.encodeSetEffect(2, 1, r);
    EXPECT_EQ(bytesOf(r), (std::vector<uint8_t>{0x01, 0x02, 0x01, 0xFF, 0xFF, 0xFF, 0x02, 0x00, 0x00, 0x00, 0x00}));
}

TEST(HidPidCodec, ConstantForceMagnitude) {
    const PidCodec c = fixtureCodec();
    ReportBuffer r;
    c.encodeConstantForce(1, 0.5, r);  // round(0.5 * 32767) = 16384 = 0x4000
    EXPECT_EQ(bytesOf(r), (std::vector<uint8_t>{0x05, 0x01, 0x00, 0x40}));
    c.encodeConstantForce(2, -1.0, r);  // -32767 = 0x8001
    EXPECT_EQ(bytesOf(r), (std::vector<uint8_t>{0x05, 0x02, 0x01, 0x80}));
    c.encodeConstantForce(1, 7.0, r);  // clamped to 32767
    EXPECT_EQ(bytesOf(r), (std::vector<uint8_t>{0x05, 0x01, 0xFF, 0x7F}));
    c.encodeConstantForce(1, std::numeric_limits<double>::quiet_NaN(), r);
    EXPECT_EQ(bytesOf(r), (std::vector<uint8_t>{0x05, 0x01, 0x00, 0x00}));
    c.encodeConstantForce(1, -std::numeric_limits<double>::infinity(), r);
    EXPECT_EQ(bytesOf(r), (std::vector<uint8_t>{0x05, 0x01, 0x00, 0x00}));
    EXPECT_EQ(c.magnitudeValue(0.0), 0);
    EXPECT_EQ(c.magnitudeValue(-0.25), -8192);  // round(-8191.75)
}

TEST(HidPidCodec, EffectOperation) {
    const PidCodec c = fixtureCodec();
    ReportBuffer r;
    c.encodeEffectOperation(1, EffectOp::Start, r);
    EXPECT_EQ(bytesOf(r), (std::vector<uint8_t>{0x0A, 0x01, 0x01, 0x01}));
    c.encodeEffectOperation(2, EffectOp::Stop, r);
    EXPECT_EQ(bytesOf(r), (std::vector<uint8_t>{0x0A, 0x02, 0x03, 0x01}));
}

TEST(HidPidCodec, DecodeInput) {
    const PidCodec c = fixtureCodec();
    InputSample s;
    // Buttons 1, 3 and 16; X = 32767 (+1), Y = -32767 (0x8001, -1).
    const std::vector<uint8_t> report = {0x01, 0x05, 0x80, 0xFF, 0x7F, 0x01, 0x80};
    ASSERT_TRUE(c.decodeInput(report, s));
    EXPECT_EQ(s.axisCount, 2u);
    EXPECT_DOUBLE_EQ(s.axes[0], 1.0);
    EXPECT_DOUBLE_EQ(s.axes[1], -1.0);
    EXPECT_EQ(s.buttons, 0x8005u);
    // X = 0 (centre), Y = 16384: 16384 / 32767.
    const std::vector<uint8_t> centre = {0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x40};
    ASSERT_TRUE(c.decodeInput(centre, s));
    EXPECT_DOUBLE_EQ(s.axes[0], 0.0);
    EXPECT_NEAR(s.axes[1], 16384.0 / 32767.0, 1e-12);
    EXPECT_EQ(s.buttons, 0u);
    // Another report ID, or too short: rejected, sample unchanged.
    const std::vector<uint8_t> state = {0x02, 0x03};
    EXPECT_FALSE(c.decodeInput(state, s));
    const std::vector<uint8_t> truncated = {0x01, 0x00, 0x00};
    EXPECT_FALSE(c.decodeInput(truncated, s));
    EXPECT_NEAR(s.axes[1], 16384.0 / 32767.0, 1e-12);
}

TEST(HidPidCodec, PackAndUnpackFields) {
    std::vector<uint8_t> data(4, 0xAA);
    const FieldLocation f{4, 12, -2048, 2047};
    packField(data, f, -1);  // 12 bits of ones at bits 4..15
    EXPECT_EQ(data[0], 0xFA);
    EXPECT_EQ(data[1], 0xFF);
    EXPECT_EQ(data[2], 0xAA);
    EXPECT_EQ(unpackField(data, f), -1);
    packField(data, f, 5000);  // clamped to 2047
    EXPECT_EQ(unpackField(data, f), 2047);
    const FieldLocation past{30, 8, 0, 255};  // reaches past the buffer: ignored
    packField(data, past, 1);
    EXPECT_EQ(unpackField(data, past), 0);
}

TEST(DeviceTable, OpenFfboard) {
    const KnownDevice* d = findKnownDevice(0x1209, 0xFFB0);
    ASSERT_NE(d, nullptr);
    EXPECT_STREQ(d->name, "OpenFFBoard");
    EXPECT_GT(d->maxForce, 0.0);
    EXPECT_EQ(findKnownDevice(0x1209, 0x0001), nullptr);
    EXPECT_TRUE(isPidUsagePage(0x0F));
    EXPECT_FALSE(isPidUsagePage(0x01));
    EXPECT_FALSE(knownDevices().empty());
}

}  // namespace
}  // namespace kizamu::haptics::hid

namespace kizamu::haptics::hid {
namespace {

TEST(HidPidCodec, ForceAxesFollowAxesEnable) {
    EXPECT_EQ(fixtureCodec().forceAxes(), 2);
    // The same joystick whose Axes Enable lists X only (a wheel's single force axis): the
    // two-bit X, Y run becomes one X bit.
    const std::vector<uint8_t> twoAxes = {0x09, 0x30, 0x09, 0x31, 0x15, 0x00, 0x25, 0x01, 0x75, 0x01, 0x95, 0x02};
    const std::vector<uint8_t> oneAxis = {0x09, 0x30, 0x15, 0x00, 0x25, 0x01, 0x75, 0x01, 0x95, 0x01};
    std::vector<uint8_t> bytes = fixture::joystick();
    const auto at = std::search(bytes.begin(), bytes.end(), twoAxes.begin(), twoAxes.end());
    ASSERT_NE(at, bytes.end());
    bytes.erase(at, at + long(twoAxes.size()));
    bytes.insert(bytes.begin() + (at - bytes.begin()), oneAxis.begin(), oneAxis.end());
    const PidCodec c(findPidLayout(parseReportDescriptor(bytes)));
    EXPECT_EQ(c.layout().axisCount, 2u);  // the input report still has X and Y
    EXPECT_EQ(c.forceAxes(), 1);
    EXPECT_TRUE(c.layout().setEffect.axisEnable[0].present());
    EXPECT_FALSE(c.layout().setEffect.axisEnable[1].present());
}

}  // namespace
}  // namespace kizamu::haptics::hid
