// SPDX-License-Identifier: Apache-2.0
/// @file falcon_codec.h
/// @brief The Novint Falcon's packet format (Novint SDK-compatible firmware): host packets
/// (three motor commands, LEDs, homing mode) to bytes, and device packets (three encoder counts,
/// grip buttons, homing status) from a byte stream that arrives in arbitrary pieces.
///
/// Where it sits: FalconDevice's device thread encodes one host packet per exchange and feeds
/// what the transport read into a DevicePacketParser. Pure: no I/O, no allocation, no clock;
/// every function is noexcept and safe on any thread (a parser is owned by one thread).
///
/// Wire format (the packet layout libnifalcon's Novint SDK firmware driver,
/// FalconFirmwareNovintSDK::formatInput/formatOutput, uses; both directions are 16 bytes):
///   byte 0        '<' (0x3C)
///   bytes 1..12   three signed 16-bit values, four bytes each, least significant nibble
///                 first; each byte is 0x41 ('A') + nibble, so payload bytes are 'A'..'P'
///                 host -> device: motor commands; device -> host: encoder counts
///   byte 13       0x41 + flags
///                 host -> device: bit 0 homing mode, bits 1..3 LEDs (green 0x2, blue 0x4, red 0x8)
///                 device -> host: low nibble grip buttons, bits 4..6 axes homed (axis i: 1 << i)
///   byte 14       0x41 on the host side; not interpreted on the device side
///   byte 15       '>' (0x3E)
/// The host->device homing bit, LED bits and homed-axis bits are those of libnifalcon's
/// FalconFirmware.h (GREEN_LED, BLUE_LED, RED_LED, ENCODER_n_HOMED); the four button bits are
/// those of its FalconGripFourButton.h.
///
/// Features:
///  [X] encode and decode both directions (the device side for emulators and round trips)
///  [X] a fixed-capacity stream parser: split reads, garbage skipped and counted, resync on '<'
///  [ ] the firmware's other grips (only the four-button grip's bits are named)
/// Changes (breaking): 2026-12-06 first version.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

namespace kizamu::haptics::falcon {

inline constexpr std::size_t kPacketSize = 16;
inline constexpr uint8_t kPacketStart = 0x3C;  ///< '<'
inline constexpr uint8_t kPacketEnd = 0x3E;    ///< '>'
inline constexpr uint8_t kNibbleBias = 0x41;   ///< 'A': every payload byte is 0x41 + its value

/// Host -> device flag bits of byte 13 (before the bias).
inline constexpr uint8_t kHomingModeBit = 0x01;
inline constexpr uint8_t kLedGreen = 0x02;
inline constexpr uint8_t kLedBlue = 0x04;
inline constexpr uint8_t kLedRed = 0x08;
inline constexpr uint8_t kLedMask = kLedGreen | kLedBlue | kLedRed;

/// Device -> host: grip buttons of the four-button grip (low nibble of byte 13).
inline constexpr uint8_t kButtonMask = 0x0F;
/// Device -> host: all three axes homed (bits 4..6 of byte 13, shifted down).
inline constexpr uint8_t kAllAxesHomed = 0x07;

using PacketBytes = std::array<uint8_t, kPacketSize>;

/// What the host sends: three motor commands in the firmware's integer units (see
/// falcon_kinematics.h for the N·m -> units scale and sign), the LEDs and the homing mode.
struct HostPacket {
    std::array<int16_t, 3> motor{0, 0, 0};
    uint8_t leds = 0;     ///< kLed* bits; other bits are ignored
    bool homing = false;  ///< ask the firmware to run its homing mode
};

/// What the device answers: three raw encoder counts, grip buttons, which axes are homed.
struct DevicePacket {
    std::array<int16_t, 3> encoder{0, 0, 0};
    uint8_t buttons = 0;    ///< kButtonMask bits
    uint8_t homedAxes = 0;  ///< bit i: axis i homed (0..7)
    bool allHomed() const noexcept { return (homedAxes & kAllAxesHomed) == kAllAxesHomed; }
};

/// The 16 bytes of `packet`. Complexity O(1). Threading: pure. Memory: none.
PacketBytes encodeHostPacket(const HostPacket& packet) noexcept;
/// The 16 bytes a firmware sends for `packet` (emulators and tests; buttons and homedAxes are
/// masked to their fields). Complexity O(1). Threading: pure. Memory: none.
PacketBytes encodeDevicePacket(const DevicePacket& packet) noexcept;

/// Decodes one complete device packet; false (and `out` untouched) when `bytes` is not a valid
/// frame: wrong delimiters, or a count byte outside 'A'..'P', or a flag byte outside its range.
/// Complexity O(1). Threading: pure. Memory: none.
bool decodeDevicePacket(std::span<const uint8_t, kPacketSize> bytes, DevicePacket& out) noexcept;
/// Decodes one complete host packet (emulators and tests), with the same validation.
bool decodeHostPacket(std::span<const uint8_t, kPacketSize> bytes, HostPacket& out) noexcept;

/// Counts a parser keeps since construction (or reset()).
struct ParserCounts {
    uint64_t packets = 0;       ///< valid packets decoded
    uint64_t skippedBytes = 0;  ///< bytes dropped: outside a frame, or in a frame found invalid
    uint64_t badFrames = 0;     ///< frames that started with '<' and turned out invalid
};

/// Reassembles device packets from a byte stream cut anywhere (USB reads end where they end).
/// A frame starts at '<'; a byte that cannot be at its position drops the frame (its bytes
/// are counted as skipped) and, if that byte is '<', a new frame starts at it, so one garbled
/// byte costs at most the packet it hit. Fixed capacity (one frame), no allocation.
/// Owned by one thread (the device thread); not thread-safe.
class DevicePacketParser {
public:
    /// Feeds `bytes`; every complete valid packet is written to `latest` (so it holds the
    /// newest one). Returns how many packets completed in this call.
    /// Complexity O(bytes.size()). Threading: the owning thread. Memory: none.
    int feed(std::span<const uint8_t> bytes, DevicePacket& latest) noexcept;
    /// Forgets a partial frame and the counts.
    void reset() noexcept;
    const ParserCounts& counts() const noexcept { return mCounts; }
    /// Bytes of the frame in progress (0..15).
    std::size_t pending() const noexcept { return mSize; }

private:
    void drop() noexcept;

    PacketBytes mFrame{};
    std::size_t mSize = 0;
    ParserCounts mCounts;
};

}  // namespace kizamu::haptics::falcon
