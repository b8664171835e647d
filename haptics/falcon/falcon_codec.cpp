// SPDX-License-Identifier: Apache-2.0
/// @file falcon_codec.cpp
/// @brief Packet encoding, validation and stream reassembly (format in falcon_codec.h).
#include "haptics/falcon/falcon_codec.h"

namespace kizamu::haptics::falcon {

namespace {

constexpr std::size_t kFlagsByte = 13;
constexpr std::size_t kSpareByte = 14;
/// Largest flag value a device sends in byte 13: buttons (4 bits) and homed axes (3 bits).
constexpr uint8_t kDeviceFlagsMax = 0x7F;
/// Largest flag value a host sends in byte 13: homing bit and three LEDs.
constexpr uint8_t kHostFlagsMax = 0x0F;

/// Writes the three 16-bit values as biased nibbles, least significant first, into bytes 1..12.
void putValues(const std::array<int16_t, 3>& values, PacketBytes& out) noexcept {
    for (std::size_t axis = 0; axis < 3; ++axis) {
        const auto bits = static_cast<uint16_t>(values[axis]);
        for (std::size_t n = 0; n < 4; ++n) {
            out[1 + 4 * axis + n] = static_cast<uint8_t>(kNibbleBias + ((bits >> (4 * n)) & 0xF));
        }
    }
}

/// Reads bytes 1..12 back into three 16-bit values (two's complement, as the firmware sends).
std::array<int16_t, 3> getValues(std::span<const uint8_t, kPacketSize> bytes) noexcept {
    std::array<int16_t, 3> values{};
    for (std::size_t axis = 0; axis < 3; ++axis) {
        uint16_t bits = 0;
        for (std::size_t n = 0; n < 4; ++n) {
            const unsigned nibble = unsigned(bytes[1 + 4 * axis + n] - kNibbleBias) & 0xFU;
            bits = static_cast<uint16_t>(bits | (nibble << (4 * n)));
        }
        values[axis] = static_cast<int16_t>(bits);
    }
    return values;
}

bool isNibbleByte(uint8_t b) noexcept {
    return b >= kNibbleBias && b <= kNibbleBias + 0xF;
}

/// Whether `b` can stand at `position` of a frame whose byte 13 carries values up to `flagsMax`.
bool validAt(std::size_t position, uint8_t b, uint8_t flagsMax) noexcept {
    if (position == 0) return b == kPacketStart;
    if (position < kFlagsByte) return isNibbleByte(b);
    if (position == kFlagsByte) return b >= kNibbleBias && b <= kNibbleBias + flagsMax;
    if (position == kSpareByte) return b != kPacketStart && b != kPacketEnd;
    return b == kPacketEnd;
}

bool validFrame(std::span<const uint8_t, kPacketSize> bytes, uint8_t flagsMax) noexcept {
    for (std::size_t i = 0; i < kPacketSize; ++i) {
        if (!validAt(i, bytes[i], flagsMax)) return false;
    }
    return true;
}

PacketBytes frame() noexcept {
    PacketBytes out{};
    out[0] = kPacketStart;
    out[kSpareByte] = kNibbleBias;
    out[kPacketSize - 1] = kPacketEnd;
    return out;
}

}  // namespace

PacketBytes encodeHostPacket(const HostPacket& packet) noexcept {
    PacketBytes out = frame();
    putValues(packet.motor, out);
    const uint8_t flags =
        static_cast<uint8_t>((packet.leds & kLedMask) | (packet.homing ? kHomingModeBit : 0));
    out[kFlagsByte] = static_cast<uint8_t>(kNibbleBias + flags);
    return out;
}

PacketBytes encodeDevicePacket(const DevicePacket& packet) noexcept {
    PacketBytes out = frame();
    putValues(packet.encoder, out);
    const uint8_t flags = static_cast<uint8_t>(((packet.homedAxes & kAllAxesHomed) << 4) |
                                               (packet.buttons & kButtonMask));
    out[kFlagsByte] = static_cast<uint8_t>(kNibbleBias + flags);
    return out;
}

bool decodeDevicePacket(std::span<const uint8_t, kPacketSize> bytes, DevicePacket& out) noexcept {
    if (!validFrame(bytes, kDeviceFlagsMax)) return false;
    const uint8_t flags = static_cast<uint8_t>(bytes[kFlagsByte] - kNibbleBias);
    out.encoder = getValues(bytes);
    out.buttons = flags & kButtonMask;
    out.homedAxes = (flags >> 4) & kAllAxesHomed;
    return true;
}

bool decodeHostPacket(std::span<const uint8_t, kPacketSize> bytes, HostPacket& out) noexcept {
    if (!validFrame(bytes, kHostFlagsMax)) return false;
    const uint8_t flags = static_cast<uint8_t>(bytes[kFlagsByte] - kNibbleBias);
    out.motor = getValues(bytes);
    out.leds = flags & kLedMask;
    out.homing = (flags & kHomingModeBit) != 0;
    return true;
}

int DevicePacketParser::feed(std::span<const uint8_t> bytes, DevicePacket& latest) noexcept {
    int completed = 0;
    for (const uint8_t b : bytes) {
        if (mSize > 0 && !validAt(mSize, b, kDeviceFlagsMax)) drop();
        if (mSize == 0) {
            if (b == kPacketStart) {
                mFrame[0] = b;
                mSize = 1;
            } else {
                ++mCounts.skippedBytes;
            }
            continue;
        }
        mFrame[mSize++] = b;
        if (mSize == kPacketSize) {
            mSize = 0;
            // Every byte was validated on arrival, so the frame decodes.
            if (decodeDevicePacket(mFrame, latest)) {
                ++mCounts.packets;
                ++completed;
            } else {
                ++mCounts.badFrames;
                mCounts.skippedBytes += kPacketSize;
            }
        }
    }
    return completed;
}

void DevicePacketParser::drop() noexcept {
    ++mCounts.badFrames;
    mCounts.skippedBytes += mSize;
    mSize = 0;
}

void DevicePacketParser::reset() noexcept {
    mSize = 0;
    mCounts = {};
}

}  // namespace kizamu::haptics::falcon
