// SPDX-License-Identifier: Apache-2.0
/// @file falcon_usb_transport.h
/// @brief FalconTransport over libusb-1.0: the Falcon's FTDI FT245 (USB 0403:cb48) driven with
/// FTDI's vendor control requests directly (no libftdi), bulk endpoints 0x81 (in) and 0x02 (out).
///
/// Where it sits: the transport FalconDevice uses with real hardware. Threads: FalconDevice's
/// constructor (open, firmware), then its device thread (write, read); never the servo thread.
/// Blocking libusb calls are fine here: the device thread exists to keep them off the servo
/// thread (haptics/servo_loop.h).
///
/// Facts used (sources cited where used in the .cpp): the FTDI "SIO" request numbers and values
/// (libftdi's definitions, as libnifalcon's FalconCommLibUSB restates them); the two modem
/// status bytes at the start of every 64-byte bulk-in packet (FTDI's FT245 and libnifalcon's
/// readBlocking); the boot loader hand-shake and normal-mode settings of libnifalcon's
/// FalconCommLibUSB::setFirmwareMode / setNormalMode and FalconFirmware::loadFirmware.
///
/// Features:
///  [X] open by index, kernel driver detached, interface 0 claimed; clear errors (permissions,
///      busy, not found) naming docs/DEVICES.md
///  [X] normal mode (chip reset on open, 1 ms latency timer, the firmware's line rate, purges);
///      no bit-bang mode (libnifalcon's libusb transport sets none in either mode)
///  [X] firmware load (9600 baud hand-shake, 140 kbaud upload with echo check, back to normal)
///  [X] bulk in with the FTDI status bytes stripped, bulk out
///  [ ] asynchronous (libusb_submit_transfer) I/O; hot-plug notification
/// Changes (breaking): 2026-12-06 first version.
#pragma once

#include "haptics/falcon/falcon_transport.h"

#include <array>
#include <cstddef>
#include <cstdint>

struct libusb_context;
struct libusb_device_handle;

namespace kizamu::haptics::falcon {

inline constexpr uint16_t kFalconVendorId = 0x0403;   ///< FTDI
inline constexpr uint16_t kFalconProductId = 0xCB48;  ///< Novint Falcon

/// Owned by FalconDevice (through FalconTransport); one calling thread at a time.
class FalconUsbTransport final : public FalconTransport {
public:
    /// Starts a libusb context (no device is touched).
    /// @throw std::runtime_error when libusb cannot start (for example no /dev/bus/usb).
    FalconUsbTransport();
    ~FalconUsbTransport() override;
    FalconUsbTransport(const FalconUsbTransport&) = delete;
    FalconUsbTransport& operator=(const FalconUsbTransport&) = delete;

    /// How many Falcons are plugged in (0 when the bus cannot be listed). Cold path.
    unsigned count() const noexcept;

    void open(unsigned index) override;
    void close() noexcept override;
    bool isOpen() const noexcept override { return mHandle != nullptr; }
    void setNormalMode() override;
    void loadFirmware(const std::vector<uint8_t>& image) override;
    /// Bulk out to 0x02, 1 s timeout. Complexity O(bytes). Memory: none.
    bool write(std::span<const uint8_t> bytes) noexcept override;
    /// Bulk in from 0x81 in 64-byte packets until a payload byte arrives or `timeoutMs` passes.
    /// Complexity O(bytes). Memory: none (a fixed 64-byte buffer keeps what did not fit `out`).
    std::ptrdiff_t read(std::span<uint8_t> out, int timeoutMs) noexcept override;

private:
    /// One FTDI vendor request (bmRequestType 0x40); throws naming `what` on failure.
    void control(uint8_t request, uint16_t value, const char* what);
    /// One bulk-in packet (<= 64 bytes, status bytes stripped) into mPending; bytes, or -1.
    std::ptrdiff_t fillPending(int timeoutMs) noexcept;

    libusb_context* mContext = nullptr;
    libusb_device_handle* mHandle = nullptr;
    std::array<uint8_t, 64> mPending{};  ///< payload read but not yet returned
    std::size_t mPendingBegin = 0, mPendingEnd = 0;
};

}  // namespace kizamu::haptics::falcon
