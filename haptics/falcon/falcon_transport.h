// SPDX-License-Identifier: Apache-2.0
/// @file falcon_transport.h
/// @brief The byte pipe to a Novint Falcon: open, load firmware, then exchange bytes.
///
/// Where it sits: FalconDevice owns one and drives it from two places: its constructor (open,
/// firmware check and load, on the caller's thread) and its device thread (write and read in
/// normal mode). Never from the servo thread. Implementations: FalconUsbTransport (libusb,
/// falcon_usb_transport.h) and the tests' scripted firmware emulator.
///
/// Requirements on an implementation:
///  - open(), setNormalMode() and loadFirmware() are cold: they may block for seconds and throw
///    std::runtime_error with a message that says what to do;
///  - write() and read() are noexcept and report a lost device as a failure (false, -1), not an
///    exception, because the device thread must not let one escape;
///  - read() returns the firmware's payload bytes only (a USB transport strips the FTDI status
///    bytes), in order, possibly cut anywhere; it waits at most `timeoutMs`;
///  - one thread at a time calls it (FalconDevice's constructor, then its device thread).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace kizamu::haptics::falcon {

/// Owned by FalconDevice (one per device); not thread-safe (one calling thread at a time).
class FalconTransport {
public:
    virtual ~FalconTransport() = default;

    /// Opens the `index`-th Falcon (0: the first found) and puts it in normal mode.
    /// @throw std::runtime_error when there is none, it cannot be opened (permissions: see
    /// docs/DEVICES.md) or it does not answer its set-up requests.
    virtual void open(unsigned index) = 0;
    /// Releases the device. Idempotent.
    virtual void close() noexcept = 0;
    virtual bool isOpen() const noexcept = 0;

    /// Normal mode: the line settings the firmware's packet exchange runs at; clears pending
    /// bytes. @throw std::runtime_error when the device refuses.
    virtual void setNormalMode() = 0;
    /// Switches to the boot loader's mode, sends `image` (the firmware file's bytes) checking
    /// its echo, and returns to normal mode. @throw std::runtime_error on any failure (the
    /// device then needs a power cycle or another try).
    virtual void loadFirmware(const std::vector<uint8_t>& image) = 0;

    /// Sends all of `bytes`; false when the device is gone or the transfer failed.
    virtual bool write(std::span<const uint8_t> bytes) noexcept = 0;
    /// Reads what arrives within `timeoutMs` (ms, >= 0) into `out`: the number of bytes read
    /// (0 when none came), or -1 when the device is gone or the transfer failed.
    virtual std::ptrdiff_t read(std::span<uint8_t> out, int timeoutMs) noexcept = 0;
};

}  // namespace kizamu::haptics::falcon
