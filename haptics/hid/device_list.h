// SPDX-License-Identifier: Apache-2.0
/// @file device_list.h
/// @brief The haptic devices this machine has: Novint Falcons (libusb), HID force-feedback
/// devices (hidapi), and the simulated stylus, which is always there. What `kizamu devices`
/// prints.
///
/// Where it sits: haptics/hid/, the platform edge (libusb and hidapi). Cold path: enumeration
/// only; it opens a Falcon for a moment to tell whether it can be opened, and checks a hidraw
/// node's permissions without opening it. Threading: any thread; libusb gets its own context
/// per call, hidapi is initialised once (hidapi_transport.h).
///
/// Sources of the facts: the Novint Falcon enumerates as USB 0403:cb48 (vendor FTDI, whose
/// FT232 it uses): libnifalcon (github.com/libnifalcon/libnifalcon), its C driver header,
/// NOVINT_FALCON_VENDOR_ID 0x0403 / NOVINT_FALCON_PRODUCT_ID 0xCB48. HID PID devices:
/// device_table.h.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace kizamu::haptics::hid {

enum class FoundKind : uint8_t { Simulated, Falcon, HidPid };

/// One device found. Plain data.
struct FoundDevice {
    FoundKind kind = FoundKind::Simulated;
    std::string id;            ///< what to pass to select it: "sim", "falcon:BUS:ADDR", "/dev/hidrawN"
    std::string name;
    uint16_t vendorId = 0, productId = 0;
    bool available = false;    ///< can be opened now
    std::string status;        ///< "ok", or why it cannot be opened and what to do
    int axes = 0;              ///< force axes; 0: unknown (descriptor unreadable)
    double maxForce = 0.0;     ///< N, the figure Kizamu keeps the device within; 0: unknown
};

/// What listDevices() found, and notes on what it could not look at (libusb or hidapi
/// unavailable). Plain data.
struct DeviceListing {
    std::vector<FoundDevice> devices;  ///< the simulated stylus first, then real devices
    std::vector<std::string> notes;
    /// Whether any real (non-simulated) device was found.
    bool anyReal() const noexcept;
};

struct ListOptions {
    bool usb = true;  ///< look for Falcons through libusb
    bool hid = true;  ///< look for HID PID devices through hidapi
};

/// Enumerates. Never throws for a missing library or device: those become notes.
/// Complexity: one libusb device list and one hidapi enumeration. Cold path (allocates).
DeviceListing listDevices(const ListOptions& options = {});

/// The Falcon's USB IDs.
constexpr uint16_t kFalconVendorId = 0x0403, kFalconProductId = 0xCB48;

}  // namespace kizamu::haptics::hid
