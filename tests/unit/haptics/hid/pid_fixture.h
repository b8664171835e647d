// SPDX-License-Identifier: Apache-2.0
/// @file pid_fixture.h
/// @brief A two-axis HID PID joystick report descriptor, written out byte by byte, for the
/// haptics/hid tests.
///
/// How it was derived: the report structure (Set Effect 0x21 with Effect Block Index, an Effect
/// Type array, Duration, Gain, Axes Enable, Direction Enable and two Direction ordinals; Set
/// Constant Force 0x73; Effect Operation 0x77; PID Device Control 0x95/0x96 as a one-byte array
/// of DC commands; Create New Effect 0xAB and PID Block Load 0x89 features; PID State 0x92
/// input) follows the PID 1.0 specification's example joystick (usb.org, pid1_01.pdf), and the
/// report IDs (1, 2, 5, 10, 12, 0x11, 0x12) and logical ranges (block index 1..40, magnitude
/// -32767..32767, direction 0..36000) are those OpenFFBoard publishes
/// (github.com/Ultrawipf/OpenFFBoard, Firmware/FFBoard/Inc/ffb_defs.h and
/// UserExtensions/Src/usb_hid_1ffb_desc.c). It is trimmed to what a constant force needs (two
/// effect types instead of eleven) so the expected bytes can be worked by hand. The input
/// report is 16 buttons then X and Y as 16-bit values in -32767..32767.
///
/// Bit layouts (after the report ID byte), used by the hand-worked expectations:
///  input 1 (7 bytes):  buttons 0..15, X 16..31, Y 32..47
///  output 1 Set Effect (11 bytes): block 0..7, type 8..15 (1 = Constant, 2 = Ramp), duration
///    16..31, gain 32..39, axes enable X 40 Y 41, direction enable 42, pad 43..47, direction 1
///    48..63, direction 2 64..79
///  output 5 Set Constant Force (4 bytes): block 0..7, magnitude 8..23
///  output 10 Effect Operation (4 bytes): block 0..7, op 8..15 (1 start, 2 solo, 3 stop), loop
///    count 16..23
///  output 12 Device Control (2 bytes): command 0..7 (1 enable, 2 disable, 3 stop all,
///    4 reset, 5 pause, 6 continue)
///  feature 0x11 Create New Effect (2 bytes): type 0..7
///  feature 0x12 Block Load (3 bytes): block 0..7, status 8..15 (1 success, 2 full, 3 error)
#pragma once

#include <cstdint>
#include <initializer_list>
#include <vector>

namespace kizamu::haptics::hid::fixture {

inline std::vector<uint8_t> cat(std::initializer_list<std::vector<uint8_t>> parts) {
    std::vector<uint8_t> out;
    for (const auto& p : parts) out.insert(out.end(), p.begin(), p.end());
    return out;
}

/// The joystick's input report (inside the application collection opened by kOpen).
inline const std::vector<uint8_t> kOpen = {
    0x05, 0x01,              // Usage Page (Generic Desktop)
    0x09, 0x04,              // Usage (Joystick)
    0xA1, 0x01,              // Collection (Application)
};
inline const std::vector<uint8_t> kInput = {
    0x85, 0x01,              //   Report ID 1
    0x05, 0x09,              //   Usage Page (Button)
    0x19, 0x01, 0x29, 0x10,  //   Usage Minimum 1, Usage Maximum 16
    0x15, 0x00, 0x25, 0x01,  //   Logical 0..1
    0x75, 0x01, 0x95, 0x10,  //   Report Size 1, Report Count 16
    0x81, 0x02,              //   Input (Data, Variable, Absolute)
    0x05, 0x01,              //   Usage Page (Generic Desktop)
    0x09, 0x30, 0x09, 0x31,  //   Usage X, Usage Y
    0x16, 0x01, 0x80,        //   Logical Minimum -32767
    0x26, 0xFF, 0x7F,        //   Logical Maximum 32767
    0x75, 0x10, 0x95, 0x02,  //   Report Size 16, Report Count 2
    0x81, 0x02,              //   Input (Data, Variable, Absolute)
};
inline const std::vector<uint8_t> kClose = {0xC0};

inline const std::vector<uint8_t> kSetEffect = {
    0x05, 0x0F,              //   Usage Page (PID)
    0x09, 0x21,              //   Usage Set Effect Report
    0xA1, 0x02,              //   Collection (Logical)
    0x85, 0x01,              //     Report ID 1
    0x09, 0x22,              //     Effect Block Index
    0x15, 0x01, 0x25, 0x28,  //     Logical 1..40
    0x75, 0x08, 0x95, 0x01,  //     8 bits x 1
    0x91, 0x02,              //     Output (Variable)
    0x09, 0x25,              //     Effect Type
    0xA1, 0x02,              //     Collection (Logical)
    0x09, 0x26, 0x09, 0x27,  //       ET Constant Force, ET Ramp
    0x15, 0x01, 0x25, 0x02,  //       Logical 1..2
    0x75, 0x08, 0x95, 0x01,  //       8 bits x 1
    0x91, 0x00,              //       Output (Array)
    0xC0,                    //     End Collection
    0x09, 0x50,              //     Duration
    0x15, 0x00, 0x26, 0xFF, 0x7F,  // Logical 0..32767
    0x75, 0x10, 0x95, 0x01,  //     16 bits x 1
    0x91, 0x02,              //     Output (Variable)
    0x09, 0x52,              //     Gain
    0x15, 0x00, 0x26, 0xFF, 0x00,  // Logical 0..255
    0x75, 0x08, 0x95, 0x01,  //     8 bits x 1
    0x91, 0x02,              //     Output (Variable)
    0x09, 0x55,              //     Axes Enable
    0xA1, 0x02,              //     Collection (Logical)
    0x05, 0x01,              //       Usage Page (Generic Desktop)
    0x09, 0x30, 0x09, 0x31,  //       X, Y
    0x15, 0x00, 0x25, 0x01,  //       Logical 0..1
    0x75, 0x01, 0x95, 0x02,  //       1 bit x 2
    0x91, 0x02,              //       Output (Variable)
    0xC0,                    //     End Collection
    0x05, 0x0F,              //     Usage Page (PID)
    0x09, 0x56,              //     Direction Enable
    0x95, 0x01, 0x91, 0x02,  //     1 bit x 1, Output (Variable)
    0x95, 0x05, 0x91, 0x03,  //     5 bits padding, Output (Constant)
    0x09, 0x57,              //     Direction
    0xA1, 0x02,              //     Collection (Logical)
    0x0B, 0x01, 0x00, 0x0A, 0x00,  // Usage Ordinal 1 (extended usage 0x000A0001)
    0x0B, 0x02, 0x00, 0x0A, 0x00,  // Usage Ordinal 2
    0x66, 0x14, 0x00,        //       Unit (degrees)
    0x15, 0x00, 0x27, 0xA0, 0x8C, 0x00, 0x00,  // Logical 0..36000
    0x75, 0x10, 0x95, 0x02,  //       16 bits x 2
    0x91, 0x02,              //       Output (Variable)
    0x66, 0x00, 0x00,        //       Unit (none)
    0xC0,                    //     End Collection
    0xC0,                    //   End Collection
};

inline const std::vector<uint8_t> kConstantForce = {
    0x09, 0x73,              //   Usage Set Constant Force Report
    0xA1, 0x02,              //   Collection (Logical)
    0x85, 0x05,              //     Report ID 5
    0x09, 0x22,              //     Effect Block Index
    0x15, 0x01, 0x25, 0x28, 0x75, 0x08, 0x95, 0x01, 0x91, 0x02,
    0x09, 0x70,              //     Magnitude
    0x16, 0x01, 0x80, 0x26, 0xFF, 0x7F,  // Logical -32767..32767
    0x75, 0x10, 0x95, 0x01, 0x91, 0x02,
    0xC0,
};

inline const std::vector<uint8_t> kEffectOperation = {
    0x09, 0x77,              //   Usage Effect Operation Report
    0xA1, 0x02,
    0x85, 0x0A,              //     Report ID 10
    0x09, 0x22, 0x15, 0x01, 0x25, 0x28, 0x75, 0x08, 0x95, 0x01, 0x91, 0x02,
    0x09, 0x78,              //     Effect Operation
    0xA1, 0x02,
    0x09, 0x79, 0x09, 0x7A, 0x09, 0x7B,  // Start, Start Solo, Stop
    0x15, 0x01, 0x25, 0x03, 0x75, 0x08, 0x95, 0x01,
    0x91, 0x00,              //       Output (Array)
    0xC0,
    0x09, 0x7C,              //     Loop Count
    0x15, 0x00, 0x26, 0xFF, 0x00, 0x75, 0x08, 0x95, 0x01, 0x91, 0x02,
    0xC0,
};

/// Device Control as the PID spec's example has it: one byte selecting a DC command.
inline const std::vector<uint8_t> kDeviceControlArray = {
    0x09, 0x95,              //   Usage PID Device Control Report
    0xA1, 0x02,
    0x85, 0x0C,              //     Report ID 12
    0x09, 0x96,              //     PID Device Control
    0xA1, 0x02,
    0x09, 0x97, 0x09, 0x98, 0x09, 0x99, 0x09, 0x9A, 0x09, 0x9B, 0x09, 0x9C,
    0x15, 0x01, 0x25, 0x06, 0x75, 0x08, 0x95, 0x01,
    0x91, 0x00,              //       Output (Array)
    0xC0,
    0xC0,
};

/// Device Control as OpenFFBoard has it: one bit per DC command (6 bits, 2 padding).
inline const std::vector<uint8_t> kDeviceControlBits = {
    0x09, 0x95, 0xA1, 0x02, 0x85, 0x0C, 0x09, 0x96, 0xA1, 0x02,
    0x09, 0x97, 0x09, 0x98, 0x09, 0x99, 0x09, 0x9A, 0x09, 0x9B, 0x09, 0x9C,
    0x15, 0x00, 0x25, 0x01, 0x75, 0x01, 0x95, 0x06,
    0x91, 0x02,              //       Output (Variable): bit per command
    0x95, 0x02, 0x91, 0x03,  //       2 bits padding
    0xC0, 0xC0,
};

inline const std::vector<uint8_t> kCreateAndLoad = {
    0x09, 0xAB,              //   Usage Create New Effect Report
    0xA1, 0x02,
    0x85, 0x11,              //     Report ID 0x11
    0x09, 0x25,              //     Effect Type
    0xA1, 0x02,
    0x09, 0x26, 0x09, 0x27,
    0x15, 0x01, 0x25, 0x02, 0x75, 0x08, 0x95, 0x01,
    0xB1, 0x00,              //       Feature (Array)
    0xC0,
    0xC0,
    0x09, 0x89,              //   Usage PID Block Load Report
    0xA1, 0x02,
    0x85, 0x12,              //     Report ID 0x12
    0x09, 0x22, 0x15, 0x01, 0x25, 0x28, 0x75, 0x08, 0x95, 0x01,
    0xB1, 0x02,              //     Feature (Variable)
    0x09, 0x8B,              //     Block Load Status
    0xA1, 0x02,
    0x09, 0x8C, 0x09, 0x8D, 0x09, 0x8E,  // Success, Full, Error
    0x15, 0x01, 0x25, 0x03, 0x75, 0x08, 0x95, 0x01,
    0xB1, 0x00,              //       Feature (Array)
    0xC0,
    0xC0,
};

inline const std::vector<uint8_t> kPidState = {
    0x09, 0x92,              //   Usage PID State Report
    0xA1, 0x02,
    0x85, 0x02,              //     Report ID 2
    0x09, 0x9F, 0x09, 0xA0,  //     Device Paused, Actuators Enabled
    0x15, 0x00, 0x25, 0x01, 0x75, 0x01, 0x95, 0x02,
    0x81, 0x02,              //     Input (Variable)
    0x95, 0x06, 0x81, 0x03,  //     6 bits padding
    0xC0,
};

/// The whole joystick with the array form of Device Control.
inline std::vector<uint8_t> joystick() {
    return cat({kOpen, kInput, kSetEffect, kConstantForce, kEffectOperation, kDeviceControlArray, kCreateAndLoad,
                kPidState, kClose});
}

/// The same with OpenFFBoard's bit-per-command Device Control.
inline std::vector<uint8_t> joystickDeviceControlBits() {
    return cat({kOpen, kInput, kSetEffect, kConstantForce, kEffectOperation, kDeviceControlBits, kCreateAndLoad,
                kPidState, kClose});
}

/// A plain joystick with no PID reports.
inline std::vector<uint8_t> plainJoystick() { return cat({kOpen, kInput, kClose}); }

}  // namespace kizamu::haptics::hid::fixture
