// SPDX-License-Identifier: Apache-2.0
/// @file hidapi_transport.h
/// @brief HidTransport over hidapi's hidraw backend (Linux), and the report descriptor read
/// from sysfs.
///
/// Where it sits: the platform edge of haptics/hid/ (STYLE.md §1): the only file that includes
/// hidapi. hidapi 0.13 (Debian's libhidapi-dev) has no hid_get_report_descriptor, so the
/// descriptor comes from sysfs: /sys/class/hidraw/hidrawN/device/report_descriptor (the Linux
/// hidraw documentation, Documentation/hid/hidraw.rst, and the HID core's sysfs attribute).
/// Report buffers go to hidraw as they are: its write() takes the report ID as the first byte,
/// 0 for a device without numbered reports, and read() returns a numbered report with its ID
/// first (Documentation/hid/hidraw.rst), which hidapi's hidraw backend passes through.
/// Threading: one HidapiTransport per device, used by one thread at a time (HidTransport's
/// contract). hid_init() runs once per process (std::call_once); hid_exit() is never called.
///
/// Checklist:
///  [X] open by hidraw path, write, read with timeout, send/get feature
///  [X] report descriptor from sysfs (Linux)
///  [ ] other platforms (hidapi's other backends lack the sysfs descriptor)
#pragma once

#include "haptics/hid/hid_pid_device.h"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

struct hid_device_;

namespace kizamu::haptics::hid {

/// Owned by the HidPidDevice it is given to; see HidTransport for the threading contract.
class HidapiTransport final : public HidTransport {
public:
    /// Opens `path` (e.g. "/dev/hidraw3").
    /// @throw HidDeviceError when hidapi cannot open it (the message says so, with a pointer to
    ///        docs/DEVICES.md when the node is not readable and writable).
    static std::unique_ptr<HidapiTransport> open(const std::string& path);
    ~HidapiTransport() override;
    HidapiTransport(const HidapiTransport&) = delete;
    HidapiTransport& operator=(const HidapiTransport&) = delete;

    bool writeReport(std::span<const uint8_t> report) override;
    int readReport(std::span<uint8_t> buffer, int timeoutMs) override;
    bool sendFeature(std::span<const uint8_t> report) override;
    int getFeature(std::span<uint8_t> buffer) override;
    /// The USB vendor and product ID of the open device. False when hidapi cannot tell.
    bool ids(uint16_t& vendorId, uint16_t& productId) const;

private:
    explicit HidapiTransport(hid_device_* device) : mDevice(device) {}
    hid_device_* mDevice;
};

/// Initialises hidapi once per process. False when hid_init fails. Any thread.
bool ensureHidapi() noexcept;

/// The report descriptor of hidraw node `devicePath` ("/dev/hidrawN") read from sysfs.
/// @throw HidDeviceError when the sysfs file cannot be read (not Linux, or no such node).
/// Complexity: one small file read. Cold path.
std::vector<uint8_t> readSysfsReportDescriptor(const std::string& devicePath);

/// Opens hidraw node `devicePath`, parses its descriptor and builds a HidPidDevice (not
/// started). With `useTable`, a device in device_table.h gets the table's name and maxForce in
/// place of the settings'.
/// @throw HidDeviceError, HidDescriptorError. Cold path.
std::unique_ptr<HidPidDevice> openHidPidDevice(const std::string& devicePath, HidPidSettings settings = {},
                                               bool useTable = true);

}  // namespace kizamu::haptics::hid
