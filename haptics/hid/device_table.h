// SPDX-License-Identifier: Apache-2.0
/// @file device_table.h
/// @brief Known HID force-feedback devices by USB vendor and product ID, with the force
/// figures Kizamu keeps them within, and the fallback rule for devices not in the table.
///
/// Where it sits: pure data under haptics/hid/, read by device_list.h (`kizamu devices`) and
/// by whoever opens a HidPidDevice (its DeviceSpec's force). Threading: immutable, any thread.
///
/// Sources of the facts:
///  - OpenFFBoard: vendor 0x1209 (pid.codes, the open-hardware vendor ID), product 0xFFB0, from
///    its firmware's device descriptor (github.com/Ultrawipf/OpenFFBoard,
///    Firmware/FFBoard/UserExtensions/Src/usb_descriptors.cpp, USBD_VID / USBD_PID). Its HID
///    descriptor has one axis in wheel mode (usb_hid_1ffb_desc.c) and two in joystick mode
///    (usb_hid_2ffb_desc.c); the descriptor, not the table, decides how many.
///  - OpenFFBoard drives whatever motor it is wired to, so it publishes no torque of its own:
///    the table's force is a conservative figure chosen here (5 N at the handle), not a
///    manufacturer's. Raise it in HidPidSettings after measuring the actual rig.
#pragma once

#include <cstdint>
#include <span>

namespace kizamu::haptics::hid {

/// One known device. Plain data (static storage).
struct KnownDevice {
    uint16_t vendorId = 0, productId = 0;
    const char* name = "";
    int axes = 0;              ///< force axes the device usually has (its descriptor decides)
    double maxTorque = 0.0;    ///< N·m, the manufacturer's continuous figure; 0: none published
    double maxForce = 0.0;     ///< N at the handle, what Kizamu asks of it at most
    const char* forceNote = "";  ///< where maxForce comes from
};

/// The table. Complexity: O(1). Any thread.
std::span<const KnownDevice> knownDevices() noexcept;
/// The entry for (vendor, product), or nullptr. Complexity: O(table). Any thread.
const KnownDevice* findKnownDevice(uint16_t vendorId, uint16_t productId) noexcept;

/// The fallback rule: a device whose top-level collection is on the PID usage page (0x0F) is
/// a force-feedback device even when not in the table. (Many, OpenFFBoard included, put the PID
/// collections inside a Generic Desktop Joystick collection; for those, check the report
/// descriptor with HidReportDescriptor::hasPidUsages().)
constexpr bool isPidUsagePage(uint16_t usagePage) noexcept { return usagePage == 0x0F; }

/// The force figure for a PID device not in the table (N): conservative, as for OpenFFBoard.
constexpr double kGenericPidMaxForce = 3.0;

}  // namespace kizamu::haptics::hid
