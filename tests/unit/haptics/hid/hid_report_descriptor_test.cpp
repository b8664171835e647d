// SPDX-License-Identifier: Apache-2.0
/// @file hid_report_descriptor_test.cpp
/// @brief The descriptor parser and findPidLayout on the fixture joystick (pid_fixture.h).
#include "haptics/hid/hid_report_descriptor.h"
#include "unit/haptics/hid/pid_fixture.h"

#include <gtest/gtest.h>

#include <string>

namespace kizamu::haptics::hid {
namespace {

TEST(HidReportDescriptor, ParsesFieldsReportsAndOffsets) {
    const HidReportDescriptor d = parseReportDescriptor(fixture::joystick());
    EXPECT_TRUE(d.usesReportIds);
    ASSERT_EQ(d.topLevelUsages.size(), 1u);
    EXPECT_EQ(d.topLevelUsages[0], extendedUsage(page::kGenericDesktop, desktop::kJoystick));
    EXPECT_TRUE(d.hasPidUsages());
    EXPECT_EQ(d.reportBytes(ReportType::Input, 1), 7u);
    EXPECT_EQ(d.reportBytes(ReportType::Output, 1), 11u);
    EXPECT_EQ(d.reportBytes(ReportType::Output, 5), 4u);
    EXPECT_EQ(d.reportBytes(ReportType::Output, 10), 4u);
    EXPECT_EQ(d.reportBytes(ReportType::Output, 12), 2u);
    EXPECT_EQ(d.reportBytes(ReportType::Feature, 0x11), 2u);
    EXPECT_EQ(d.reportBytes(ReportType::Feature, 0x12), 3u);
    EXPECT_EQ(d.reportBytes(ReportType::Input, 2), 2u);
    EXPECT_EQ(d.reportBytes(ReportType::Output, 99), 0u);

    // The buttons: 16 one-bit values, usages Button 1..16.
    const HidField& buttons = d.fields[0];
    EXPECT_EQ(buttons.type, ReportType::Input);
    EXPECT_EQ(buttons.bitOffset, 0u);
    EXPECT_EQ(buttons.count, 16u);
    ASSERT_EQ(buttons.usages.size(), 16u);
    EXPECT_EQ(buttons.usages.front(), extendedUsage(page::kButton, 1));
    EXPECT_EQ(buttons.usages.back(), extendedUsage(page::kButton, 16));
    const HidField& axes = d.fields[1];
    EXPECT_EQ(axes.bitOffset, 16u);
    EXPECT_EQ(axes.bitSize, 16u);
    EXPECT_EQ(axes.logicalMin, -32767);
    EXPECT_EQ(axes.logicalMax, 32767);
    EXPECT_EQ(axes.collections.size(), 1u);
}

TEST(HidReportDescriptor, LayoutOfThePidJoystick) {
    const PidLayout L = findPidLayout(parseReportDescriptor(fixture::joystick()));
    EXPECT_EQ(L.input.id, 1);
    EXPECT_EQ(L.input.bytes, 7u);
    ASSERT_EQ(L.axisCount, 2u);
    EXPECT_EQ(L.axes[0].usage, desktop::kX);
    EXPECT_EQ(L.axes[0].field.bitOffset, 16u);
    EXPECT_EQ(L.axes[1].usage, desktop::kY);
    EXPECT_EQ(L.axes[1].field.bitOffset, 32u);
    EXPECT_EQ(L.buttonCount, 16u);
    EXPECT_EQ(L.buttonsBitOffset, 0u);

    EXPECT_EQ(L.setEffect.report.id, 1);
    EXPECT_EQ(L.setEffect.blockIndex.bitOffset, 0u);
    EXPECT_EQ(L.setEffect.typeConstant.field.bitOffset, 8u);
    EXPECT_EQ(L.setEffect.typeConstant.value, 1);  // array: logical min + index 0
    EXPECT_EQ(L.setEffect.duration.bitOffset, 16u);
    EXPECT_EQ(L.setEffect.duration.bitSize, 16u);
    EXPECT_EQ(L.setEffect.gain.bitOffset, 32u);
    EXPECT_EQ(L.setEffect.gain.logicalMax, 255);
    EXPECT_EQ(L.setEffect.axisEnable[0].bitOffset, 40u);
    EXPECT_EQ(L.setEffect.axisEnable[1].bitOffset, 41u);
    EXPECT_EQ(L.setEffect.directionEnable.bitOffset, 42u);
    EXPECT_EQ(L.setEffect.direction[0].bitOffset, 48u);
    EXPECT_EQ(L.setEffect.direction[1].bitOffset, 64u);
    EXPECT_EQ(L.setEffect.direction[0].logicalMax, 36000);
    EXPECT_FALSE(L.setEffect.startDelay.present());

    EXPECT_EQ(L.constantForce.report.id, 5);
    EXPECT_EQ(L.constantForce.magnitude.bitOffset, 8u);
    EXPECT_EQ(L.constantForce.magnitude.logicalMin, -32767);

    EXPECT_EQ(L.effectOperation.report.id, 10);
    EXPECT_EQ(L.effectOperation.start.value, 1);
    EXPECT_EQ(L.effectOperation.stop.value, 3);
    EXPECT_EQ(L.effectOperation.loopCount.bitOffset, 16u);

    EXPECT_EQ(L.deviceControl.report.id, 12);
    EXPECT_EQ(L.deviceControl.enableActuators.value, 1);
    EXPECT_EQ(L.deviceControl.disableActuators.value, 2);
    EXPECT_EQ(L.deviceControl.stopAllEffects.value, 3);
    EXPECT_EQ(L.deviceControl.reset.value, 4);

    EXPECT_EQ(L.createNewEffect.report.id, 0x11);
    EXPECT_EQ(L.createNewEffect.typeConstant.value, 1);
    EXPECT_EQ(L.blockLoad.report.id, 0x12);
    EXPECT_EQ(L.blockLoad.success.field.bitOffset, 8u);
    EXPECT_EQ(L.blockLoad.success.value, 1);
    EXPECT_FALSE(L.deviceGain.report.present());
}

TEST(HidReportDescriptor, DeviceControlAsOneBitPerCommand) {
    const PidLayout L = findPidLayout(parseReportDescriptor(fixture::joystickDeviceControlBits()));
    EXPECT_EQ(L.deviceControl.enableActuators.field.bitOffset, 0u);
    EXPECT_EQ(L.deviceControl.enableActuators.field.bitSize, 1u);
    EXPECT_EQ(L.deviceControl.enableActuators.value, 1);
    EXPECT_EQ(L.deviceControl.reset.field.bitOffset, 3u);
    EXPECT_EQ(L.deviceControl.reset.value, 1);
}

TEST(HidReportDescriptor, NoPidIsAClearError) {
    const HidReportDescriptor d = parseReportDescriptor(fixture::plainJoystick());
    EXPECT_FALSE(d.hasPidUsages());
    try {
        findPidLayout(d);
        FAIL() << "expected HidDescriptorError";
    } catch (const HidDescriptorError& e) {
        EXPECT_NE(std::string(e.what()).find("not a force-feedback device"), std::string::npos) << e.what();
    }
}

TEST(HidReportDescriptor, MissingConstantForceIsNamed) {
    const auto bytes = fixture::cat({fixture::kOpen, fixture::kInput, fixture::kSetEffect, fixture::kEffectOperation,
                                     fixture::kDeviceControlArray, fixture::kClose});
    try {
        findPidLayout(parseReportDescriptor(bytes));
        FAIL() << "expected HidDescriptorError";
    } catch (const HidDescriptorError& e) {
        EXPECT_NE(std::string(e.what()).find("Set Constant Force"), std::string::npos) << e.what();
    }
}

TEST(HidReportDescriptor, MalformedDescriptorsThrow) {
    auto bytes = fixture::joystick();
    bytes.pop_back();  // the last End Collection
    EXPECT_THROW(parseReportDescriptor(bytes), HidDescriptorError);
    const std::vector<uint8_t> truncated = {0x05, 0x01, 0x26, 0xFF};  // 2-byte item with 1 byte
    EXPECT_THROW(parseReportDescriptor(truncated), HidDescriptorError);
    const std::vector<uint8_t> pop = {0xB4};  // Pop without Push
    EXPECT_THROW(parseReportDescriptor(pop), HidDescriptorError);
    const std::vector<uint8_t> endFirst = {0xC0};
    EXPECT_THROW(parseReportDescriptor(endFirst), HidDescriptorError);
    EXPECT_NO_THROW(parseReportDescriptor(std::vector<uint8_t>{}));
}

TEST(HidReportDescriptor, UnsignedMaximumInShortForm) {
    // Logical 0..65535 written as 0x26 0xFF 0xFF (signed -1) reads as 65535.
    const std::vector<uint8_t> bytes = {0x05, 0x01, 0x09, 0x30, 0x15, 0x00, 0x26, 0xFF, 0xFF,
                                        0x75, 0x10, 0x95, 0x01, 0x81, 0x02};
    const HidReportDescriptor d = parseReportDescriptor(bytes);
    ASSERT_EQ(d.fields.size(), 1u);
    EXPECT_EQ(d.fields[0].logicalMax, 65535);
    EXPECT_FALSE(d.usesReportIds);
    EXPECT_EQ(d.reportBytes(ReportType::Input, 0), 2u);
}

}  // namespace
}  // namespace kizamu::haptics::hid
