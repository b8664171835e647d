// SPDX-License-Identifier: Apache-2.0
/// @file falcon_usb_transport.cpp
/// @brief libusb implementation of FalconTransport: FTDI control requests, the boot loader
/// hand-shake, the firmware upload and the bulk pipes (overview in falcon_usb_transport.h).
#include "haptics/falcon/falcon_usb_transport.h"

#include <libusb.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <stdexcept>
#include <string>

namespace kizamu::haptics::falcon {

namespace {

// FTDI vendor requests ("SIO" requests, libftdi's numbering, as libnifalcon's FalconCommLibUSB
// restates it). All are host-to-device vendor requests (bmRequestType 0x40) with no data stage.
constexpr uint8_t kRequestTypeOut = 0x40;
constexpr uint8_t kSioReset = 0;        ///< value: 0 reset, 1 purge RX, 2 purge TX
constexpr uint8_t kSioModemCtrl = 1;    ///< value: line levels in the low byte, mask in the high
constexpr uint8_t kSioSetFlowCtrl = 2;  ///< value 0: no flow control
constexpr uint8_t kSioSetBaudRate = 3;  ///< value: the FTDI baud divisor encoding
constexpr uint8_t kSioSetData = 4;      ///< value: bits | parity << 8 | stop bits << 11
constexpr uint8_t kSioSetLatencyTimer = 9;  ///< value: ms
constexpr uint16_t kResetSio = 0, kPurgeRx = 1, kPurgeTx = 2;
constexpr uint16_t kDtrHigh = 0x0101, kDtrLow = 0x0100, kRtsLow = 0x0200;
constexpr uint16_t kData8N1 = 8;
/// The interface index libnifalcon passes (INTERFACE_ANY); the FT245 has one interface.
constexpr uint16_t kFtdiIndex = 0;

// Line settings (libnifalcon FalconCommLibUSB::setFirmwareMode and setNormalMode).
constexpr uint16_t kBaud9600 = 0x4138;          ///< boot loader hand-shake
constexpr uint16_t kBaudFirmwareLoad = 0x0015;  ///< about 140 kbaud, the upload
constexpr uint16_t kBaudNormal = 0x0002;        ///< the firmware's packet exchange
constexpr uint16_t kLatencyFirmwareMs = 16;     ///< shorter timers make the hand-shake fail
constexpr uint16_t kLatencyNormalMs = 1;

constexpr unsigned char kEndpointIn = 0x81;
constexpr unsigned char kEndpointOut = 0x02;
constexpr std::size_t kUsbPacket = 64;        ///< full-speed bulk packet
constexpr std::size_t kModemStatusBytes = 2;  ///< FTDI status at the start of every packet in
constexpr unsigned kControlTimeoutMs = 1000;
constexpr unsigned kBulkTimeoutMs = 1000;
/// Firmware upload chunk: a 64-byte packet less FTDI's 2 status bytes, so each chunk's echo
/// comes back in one packet (libnifalcon FalconFirmware::loadFirmware uses 62).
constexpr std::size_t kFirmwareChunk = 62;
constexpr int kHandshakeTries = 100;

std::string usbError(int code) {
    return std::string(libusb_error_name(code)) + ": " +
           libusb_strerror(static_cast<libusb_error>(code));
}

[[noreturn]] void fail(const std::string& message) {
    throw std::runtime_error("Novint Falcon (USB 0403:cb48): " + message);
}

std::string accessHint() {
    return " Permission denied: install the udev rule in docs/DEVICES.md (then unplug and "
           "re-plug the Falcon), or run as a user with write access to /dev/bus/usb.";
}

}  // namespace

FalconUsbTransport::FalconUsbTransport() {
    const int rc = libusb_init(&mContext);
    if (rc < 0) {
        mContext = nullptr;
        fail("libusb could not start (" + usbError(rc) +
             "); is /dev/bus/usb available to this process?");
    }
}

FalconUsbTransport::~FalconUsbTransport() {
    close();
    if (mContext) libusb_exit(mContext);
}

unsigned FalconUsbTransport::count() const noexcept {
    libusb_device** list = nullptr;
    const ssize_t n = libusb_get_device_list(mContext, &list);
    if (n < 0) return 0;
    unsigned found = 0;
    for (ssize_t i = 0; i < n; ++i) {
        libusb_device_descriptor desc{};
        if (libusb_get_device_descriptor(list[i], &desc) == 0 && desc.idVendor == kFalconVendorId &&
            desc.idProduct == kFalconProductId) {
            ++found;
        }
    }
    libusb_free_device_list(list, 1);
    return found;
}

void FalconUsbTransport::open(unsigned index) {
    close();
    libusb_device** list = nullptr;
    const ssize_t n = libusb_get_device_list(mContext, &list);
    if (n < 0) fail("cannot list USB devices (" + usbError(int(n)) + ")");
    libusb_device* chosen = nullptr;
    unsigned found = 0;
    for (ssize_t i = 0; i < n; ++i) {
        libusb_device_descriptor desc{};
        if (libusb_get_device_descriptor(list[i], &desc) != 0) continue;
        if (desc.idVendor != kFalconVendorId || desc.idProduct != kFalconProductId) continue;
        if (found == index) chosen = list[i];
        ++found;
    }
    int rc = chosen ? libusb_open(chosen, &mHandle) : 0;
    libusb_free_device_list(list, 1);
    if (!chosen) {
        fail("no Falcon at index " + std::to_string(index) + " (" + std::to_string(found) +
             " found). Is it plugged in and is its power supply connected?");
    }
    if (rc < 0) {
        mHandle = nullptr;
        fail("cannot open the device (" + usbError(rc) + ")." +
             (rc == LIBUSB_ERROR_ACCESS ? accessHint() : std::string()));
    }
    // The kernel's ftdi_sio driver binds to FTDI chips; let libusb detach it while we hold the
    // interface (unsupported on some platforms, where there is nothing to detach).
    libusb_set_auto_detach_kernel_driver(mHandle, 1);
    rc = libusb_claim_interface(mHandle, 0);
    if (rc < 0) {
        libusb_close(mHandle);
        mHandle = nullptr;
        std::string hint;
        if (rc == LIBUSB_ERROR_BUSY)
            hint = " Another program (or driver) holds it; close it and try again.";
        if (rc == LIBUSB_ERROR_ACCESS) hint = accessHint();
        fail("cannot claim interface 0 (" + usbError(rc) + ")." + hint);
    }
    try {
        // Reset the chip's serial engine before setting it up, as libftdi's ftdi_usb_open does.
        control(kSioReset, kResetSio, "resetting the FTDI chip");
        setNormalMode();
    } catch (...) {
        close();
        throw;
    }
}

void FalconUsbTransport::close() noexcept {
    if (!mHandle) return;
    libusb_release_interface(mHandle, 0);
    libusb_close(mHandle);
    mHandle = nullptr;
    mPendingBegin = mPendingEnd = 0;
}

void FalconUsbTransport::control(uint8_t request, uint16_t value, const char* what) {
    if (!mHandle) fail(std::string(what) + ": the device is not open");
    const int rc = libusb_control_transfer(mHandle, kRequestTypeOut, request, value, kFtdiIndex,
                                           nullptr, 0, kControlTimeoutMs);
    if (rc < 0) fail(std::string(what) + " failed (" + usbError(rc) + ")");
}

void FalconUsbTransport::setNormalMode() {
    control(kSioSetLatencyTimer, kLatencyNormalMs, "setting the latency timer");
    control(kSioSetBaudRate, kBaudNormal, "setting the line rate");
    control(kSioReset, kPurgeRx, "purging the receive buffer");
    control(kSioReset, kPurgeTx, "purging the transmit buffer");
    mPendingBegin = mPendingEnd = 0;
}

void FalconUsbTransport::loadFirmware(const std::vector<uint8_t>& image) {
    if (image.empty()) fail("the firmware image is empty");
    // Boot loader hand-shake (libnifalcon FalconCommLibUSB::setFirmwareMode).
    control(kSioReset, kPurgeRx, "purging the receive buffer");
    control(kSioReset, kPurgeTx, "purging the transmit buffer");
    control(kSioSetLatencyTimer, kLatencyFirmwareMs, "setting the latency timer");
    control(kSioSetBaudRate, kBaud9600, "setting 9600 baud");
    control(kSioSetData, kData8N1, "setting 8N1");
    control(kSioSetFlowCtrl, 0, "disabling flow control");
    control(kSioModemCtrl, kRtsLow, "lowering RTS");
    control(kSioModemCtrl, kDtrLow, "lowering DTR");
    control(kSioModemCtrl, kDtrHigh, "raising DTR");

    std::array<unsigned char, 512> in{};
    int got = 0;
    // The boot loader answers "\n C \r" with "\n D , \r" (sometimes after a 0x00), behind the
    // two status bytes.
    unsigned char query[3] = {0x0A, 0x43, 0x0D};
    const unsigned char answer[4] = {0x0A, 0x44, 0x2C, 0x0D};
    bool answered = false;
    for (int i = 0; i < kHandshakeTries && !answered; ++i) {
        int sent = 0;
        int rc =
            libusb_bulk_transfer(mHandle, kEndpointOut, query, sizeof query, &sent, kBulkTimeoutMs);
        if (rc < 0) fail("boot loader hand-shake: write failed (" + usbError(rc) + ")");
        rc = libusb_bulk_transfer(mHandle, kEndpointIn, in.data(), int(in.size()), &got,
                                  kBulkTimeoutMs);
        if (rc < 0 && rc != LIBUSB_ERROR_TIMEOUT)
            fail("boot loader hand-shake: read failed (" + usbError(rc) + ")");
        const unsigned char* payload = in.data() + kModemStatusBytes;
        if (got == 6 && std::memcmp(payload, answer, 4) == 0) answered = true;
        if (got == 7 && payload[0] == 0x00 && std::memcmp(payload + 1, answer, 4) == 0)
            answered = true;
    }
    if (!answered)
        fail(
            "the boot loader did not answer; unplug the Falcon's USB and power, plug them back, "
            "and try again");

    control(kSioModemCtrl, kDtrLow, "lowering DTR");
    control(kSioSetBaudRate, kBaudFirmwareLoad, "setting the upload rate");
    unsigned char ping = 0x41;
    int sent = 0;
    int rc = libusb_bulk_transfer(mHandle, kEndpointOut, &ping, 1, &sent, kBulkTimeoutMs);
    if (rc < 0) fail("boot loader check: write failed (" + usbError(rc) + ")");
    rc = libusb_bulk_transfer(mHandle, kEndpointIn, in.data(), 3, &got, kBulkTimeoutMs);
    if (rc < 0 || got != 3 || in[2] != 0x41) fail("the boot loader did not echo its check byte");

    // Upload, chunk by chunk, each echoed back byte for byte (libnifalcon
    // FalconFirmware::loadFirmware).
    std::array<unsigned char, kFirmwareChunk> chunk{};
    for (std::size_t offset = 0; offset < image.size();) {
        const std::size_t size = std::min(kFirmwareChunk, image.size() - offset);
        std::memcpy(chunk.data(), image.data() + offset, size);
        rc = libusb_bulk_transfer(mHandle, kEndpointOut, chunk.data(), int(size), &sent,
                                  kBulkTimeoutMs);
        if (rc < 0 || std::size_t(sent) != size)
            fail("firmware upload: write failed at byte " + std::to_string(offset));
        std::size_t echoed = 0;
        while (echoed < size) {
            rc = libusb_bulk_transfer(mHandle, kEndpointIn, in.data(), int(kUsbPacket), &got,
                                      kBulkTimeoutMs);
            if (rc < 0 && !(rc == LIBUSB_ERROR_TIMEOUT && got > 0)) {
                fail("firmware upload: no echo at byte " + std::to_string(offset + echoed) + " (" +
                     usbError(rc) + ")");
            }
            const std::size_t payload =
                got > int(kModemStatusBytes) ? std::size_t(got) - kModemStatusBytes : 0;
            if (echoed + payload > size)
                fail("firmware upload: more echo than sent at byte " + std::to_string(offset));
            if (std::memcmp(in.data() + kModemStatusBytes, image.data() + offset + echoed,
                            payload) != 0) {
                fail("firmware upload: echo mismatch at byte " + std::to_string(offset + echoed) +
                     "; is this Novint's firmware file?");
            }
            echoed += payload;
        }
        offset += size;
    }
    setNormalMode();
}

bool FalconUsbTransport::write(std::span<const uint8_t> bytes) noexcept {
    if (!mHandle) return false;
    std::size_t done = 0;
    while (done < bytes.size()) {
        int sent = 0;
        // libusb takes a non-const buffer for both directions; an OUT transfer only reads it.
        auto* data = const_cast<unsigned char*>(bytes.data() + done);
        const int rc = libusb_bulk_transfer(mHandle, kEndpointOut, data, int(bytes.size() - done),
                                            &sent, kBulkTimeoutMs);
        if (rc < 0 || sent <= 0) return false;
        done += std::size_t(sent);
    }
    return true;
}

std::ptrdiff_t FalconUsbTransport::fillPending(int timeoutMs) noexcept {
    std::array<unsigned char, kUsbPacket> packet{};
    int got = 0;
    const int rc = libusb_bulk_transfer(mHandle, kEndpointIn, packet.data(), int(packet.size()),
                                        &got, unsigned(std::max(1, timeoutMs)));
    if (rc < 0 && rc != LIBUSB_ERROR_TIMEOUT) return -1;
    mPendingBegin = mPendingEnd = 0;
    if (got > int(kModemStatusBytes)) {
        const std::size_t payload = std::size_t(got) - kModemStatusBytes;
        std::memcpy(mPending.data(), packet.data() + kModemStatusBytes, payload);
        mPendingEnd = payload;
    }
    return std::ptrdiff_t(mPendingEnd);
}

std::ptrdiff_t FalconUsbTransport::read(std::span<uint8_t> out, int timeoutMs) noexcept {
    if (!mHandle) return -1;
    if (out.empty()) return 0;
    const auto deadline =
        std::chrono::steady_clock::now() + std::chrono::milliseconds(std::max(0, timeoutMs));
    // The FTDI chip sends a status-only packet every latency period, so an empty read returns
    // after about 1 ms; keep asking until payload arrives or the time is up.
    while (mPendingBegin == mPendingEnd) {
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
                              deadline - std::chrono::steady_clock::now())
                              .count();
        if (fillPending(int(std::max<int64_t>(1, left))) < 0) return -1;
        if (mPendingBegin == mPendingEnd && std::chrono::steady_clock::now() >= deadline) return 0;
    }
    const std::size_t n = std::min(out.size(), mPendingEnd - mPendingBegin);
    std::memcpy(out.data(), mPending.data() + mPendingBegin, n);
    mPendingBegin += n;
    return std::ptrdiff_t(n);
}

}  // namespace kizamu::haptics::falcon
