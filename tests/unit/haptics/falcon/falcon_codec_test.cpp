// SPDX-License-Identifier: Apache-2.0
/// @file falcon_codec_test.cpp
/// @brief The Falcon packet codec against hand-worked byte fixtures, round trips, streams cut
/// at every position, and garbage the parser must skip and count.
#include "haptics/falcon/falcon_codec.h"

#include <gtest/gtest.h>

#include <random>
#include <vector>

namespace {

using namespace kizamu::haptics::falcon;

// Fixture 1, host -> device, worked by hand from the layout in falcon_codec.h (libnifalcon's
// Novint SDK firmware driver): motor 0x1234 -> nibbles 4,3,2,1 -> 'E','D','C','B';
// motor -1 = 0xFFFF -> 'P' x4; motor 0 -> 'A' x4; flags green LED 0x02 | homing 0x01 = 0x03 ->
// 0x41 + 3 = 'D'; byte 14 'A'; framed by '<' and '>'.
constexpr PacketBytes kHostFixture{'<', 'E', 'D', 'C', 'B', 'P', 'P', 'P',
                                   'P', 'A', 'A', 'A', 'A', 'D', 'A', '>'};

// Fixture 2, device -> host: encoder -2 = 0xFFFE -> nibbles E,F,F,F -> 'O','P','P','P';
// encoder 256 = 0x0100 -> 0,0,1,0 -> 'A','A','B','A'; encoder 0x7FFF -> F,F,F,7 ->
// 'P','P','P','H'; flags homed axes 0b111 << 4 | buttons 0b0101 = 0x75 -> 0x41 + 0x75 = 0xB6.
constexpr PacketBytes kDeviceFixture{'<', 'O', 'P', 'P', 'P', 'A',  'A', 'B',
                                     'A', 'P', 'P', 'P', 'H', 0xB6, 'A', '>'};

// Fixture 3: the all-zero host packet (zero motors, no LEDs, homing off): 14 'A' between '<' and
// '>'.
constexpr PacketBytes kZeroHostFixture{'<', 'A', 'A', 'A', 'A', 'A', 'A', 'A',
                                       'A', 'A', 'A', 'A', 'A', 'A', 'A', '>'};

DevicePacket fixtureDevicePacket() {
    DevicePacket p;
    p.encoder = {-2, 256, 0x7FFF};
    p.buttons = 0x5;
    p.homedAxes = 0x7;
    return p;
}

/// Appends bytes one by one (GCC 12 reports a false -Wstringop-overflow on vector::insert here).
void append(std::vector<uint8_t>& out, const uint8_t* bytes, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) out.push_back(bytes[i]);
}

void expectSame(const DevicePacket& a, const DevicePacket& b) {
    EXPECT_EQ(a.encoder, b.encoder);
    EXPECT_EQ(a.buttons, b.buttons);
    EXPECT_EQ(a.homedAxes, b.homedAxes);
}

TEST(FalconCodec, EncodesTheHostFixture) {
    HostPacket p;
    p.motor = {0x1234, -1, 0};
    p.leds = kLedGreen;
    p.homing = true;
    EXPECT_EQ(encodeHostPacket(p), kHostFixture);
    EXPECT_EQ(encodeHostPacket(HostPacket{}), kZeroHostFixture);
}

TEST(FalconCodec, DecodesTheHostFixture) {
    HostPacket p;
    ASSERT_TRUE(decodeHostPacket(kHostFixture, p));
    EXPECT_EQ(p.motor, (std::array<int16_t, 3>{0x1234, -1, 0}));
    EXPECT_EQ(p.leds, kLedGreen);
    EXPECT_TRUE(p.homing);
}

TEST(FalconCodec, DecodesAndEncodesTheDeviceFixture) {
    DevicePacket p;
    ASSERT_TRUE(decodeDevicePacket(kDeviceFixture, p));
    expectSame(p, fixtureDevicePacket());
    EXPECT_TRUE(p.allHomed());
    EXPECT_EQ(encodeDevicePacket(fixtureDevicePacket()), kDeviceFixture);
}

TEST(FalconCodec, RoundTripsExtremesAndRandomValues) {
    std::mt19937 rng(20261206);
    std::uniform_int_distribution<int> value(-32768, 32767), nibble(0, 15), axes(0, 7);
    std::vector<std::array<int16_t, 3>> cases{{-32768, 32767, 0}, {-1, 1, -2}, {0, 0, 0}};
    for (int i = 0; i < 500; ++i)
        cases.push_back({int16_t(value(rng)), int16_t(value(rng)), int16_t(value(rng))});
    for (const auto& c : cases) {
        HostPacket h;
        h.motor = c;
        h.leds = uint8_t(nibble(rng)) & kLedMask;
        h.homing = (nibble(rng) & 1) != 0;
        HostPacket h2;
        ASSERT_TRUE(decodeHostPacket(encodeHostPacket(h), h2));
        EXPECT_EQ(h2.motor, h.motor);
        EXPECT_EQ(h2.leds, h.leds);
        EXPECT_EQ(h2.homing, h.homing);

        DevicePacket d;
        d.encoder = c;
        d.buttons = uint8_t(nibble(rng));
        d.homedAxes = uint8_t(axes(rng));
        DevicePacket d2;
        ASSERT_TRUE(decodeDevicePacket(encodeDevicePacket(d), d2));
        expectSame(d2, d);
    }
}

TEST(FalconCodec, RejectsInvalidFrames) {
    DevicePacket untouched = fixtureDevicePacket(), p = untouched;
    PacketBytes bad = kDeviceFixture;
    bad[0] = 'x';
    EXPECT_FALSE(decodeDevicePacket(bad, p));
    bad = kDeviceFixture;
    bad[15] = 'x';
    EXPECT_FALSE(decodeDevicePacket(bad, p));
    bad = kDeviceFixture;
    bad[5] = 'Q';  // one past 'P': not a nibble
    EXPECT_FALSE(decodeDevicePacket(bad, p));
    bad = kDeviceFixture;
    bad[13] = 0x40;  // below the bias
    EXPECT_FALSE(decodeDevicePacket(bad, p));
    expectSame(p, untouched);
    HostPacket h;
    PacketBytes badHost = kHostFixture;
    badHost[13] = 0x41 + 0x10;  // host flags are four bits
    EXPECT_FALSE(decodeHostPacket(badHost, h));
}

TEST(FalconCodec, ParserReassemblesStreamsCutAnywhere) {
    // Three packets back to back, fed in every split of sizes 1..17.
    std::vector<uint8_t> stream;
    std::vector<DevicePacket> sent;
    for (int i = 0; i < 3; ++i) {
        DevicePacket p;
        p.encoder = {int16_t(100 * i - 7), int16_t(-300 * i), int16_t(i)};
        p.buttons = uint8_t(i);
        p.homedAxes = uint8_t(i + 1);
        sent.push_back(p);
        const PacketBytes b = encodeDevicePacket(p);
        append(stream, b.data(), b.size());
    }
    for (std::size_t piece = 1; piece <= 17; ++piece) {
        DevicePacketParser parser;
        DevicePacket latest;
        int total = 0;
        for (std::size_t at = 0; at < stream.size(); at += piece) {
            const std::size_t n = std::min(piece, stream.size() - at);
            const int got = parser.feed(std::span<const uint8_t>(stream.data() + at, n), latest);
            total += got;
            if (got > 0) {
                // Completed packets arrive in order: the newest is the one whose end was fed.
                expectSame(latest, sent[std::size_t(total - 1)]);
            }
        }
        EXPECT_EQ(total, 3) << "piece " << piece;
        EXPECT_EQ(parser.counts().packets, 3U);
        EXPECT_EQ(parser.counts().skippedBytes, 0U);
        EXPECT_EQ(parser.pending(), 0U);
    }
}

TEST(FalconCodec, ParserSkipsAndCountsGarbageAndResyncs) {
    DevicePacketParser parser;
    DevicePacket latest;
    const DevicePacket good = fixtureDevicePacket();
    std::vector<uint8_t> stream{0x00, 0xFF, 'A', '>'};  // 4 bytes of noise before any frame
    // A truncated frame: '<' and 5 payload bytes, then a new frame starts (resync on '<').
    append(stream, kDeviceFixture.data(), 6);
    append(stream, kDeviceFixture.data(), kPacketSize);
    // A frame with one garbled payload byte (a control byte), then a good frame.
    PacketBytes garbled = kDeviceFixture;
    garbled[7] = 0x01;
    append(stream, garbled.data(), kPacketSize);
    append(stream, kDeviceFixture.data(), kPacketSize);
    // A frame whose end byte is wrong.
    PacketBytes unterminated = kDeviceFixture;
    unterminated[15] = 'A';
    append(stream, unterminated.data(), kPacketSize);

    const int got = parser.feed(stream, latest);
    EXPECT_EQ(got, 2);
    expectSame(latest, good);
    const ParserCounts& c = parser.counts();
    EXPECT_EQ(c.packets, 2U);
    EXPECT_EQ(c.badFrames, 3U);
    // 4 noise + 6 truncated + (7 of the garbled frame + the bad byte + 8 after it, outside a
    // frame) + 16 of the unterminated frame (15 in the frame + its bad last byte).
    EXPECT_EQ(c.skippedBytes, 4U + 6U + 16U + 16U);
    EXPECT_EQ(parser.pending(), 0U);

    // Random noise never crashes.
    std::mt19937 rng(7);
    std::uniform_int_distribution<int> byte(0, 255);
    std::vector<uint8_t> noise(20000);
    for (auto& b : noise) b = uint8_t(byte(rng));
    DevicePacketParser noisy;
    noisy.feed(noise, latest);
    // Every byte is accounted for: skipped, in a packet, or in the frame still open.
    EXPECT_EQ(noisy.counts().skippedBytes + 16 * noisy.counts().packets + noisy.pending(),
              noise.size());
}

}  // namespace
