// SPDX-License-Identifier: Apache-2.0
/// @file falcon_device_test.cpp
/// @brief FalconDevice against a scripted firmware emulator: firmware detection and load, homing,
/// the pose read back, forces arriving as motor units, NaN forces, silence and unplugging.
#include "haptics/falcon/falcon_device.h"
#include "haptics/falcon/falcon_kinematics.h"
#include "haptics/servo_loop.h"
#include "tests/util/counting_allocator.h"

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <deque>
#include <filesystem>
#include <fstream>
#include <functional>
#include <mutex>
#include <numbers>
#include <stdexcept>
#include <string>
#include <thread>

namespace {

using namespace kizamu::haptics;
using namespace kizamu::haptics::falcon;
using namespace std::chrono_literals;

/// What the emulated firmware does and what it saw; shared between the test and the emulator
/// the device owns, behind one mutex (test code: the device thread may block on it briefly).
struct EmulatorState {
    std::mutex mutex;
    // Script.
    bool firmware = true;  ///< false: the boot loader, which does not answer packets
    int homeAfter = 3;     ///< homing packets before the firmware reports all axes homed
    glm::dvec3 poseKinematic = kWorkspaceCenter;  ///< where the grip is (m)
    uint8_t buttons = 0;
    bool unplugged = false;      ///< every call fails, as libusb does after a disconnect
    bool mute = false;           ///< packets are accepted, nothing is answered
    std::size_t chunk = 5;       ///< read() returns at most this many bytes (split packets)
    std::vector<uint8_t> noise;  ///< sent before every answer (garbage the parser must skip)
    // Record.
    std::vector<uint8_t> loadedImage;
    uint64_t hostPackets = 0, homingPackets = 0, badHostPackets = 0;
    HostPacket last;
    std::deque<uint8_t> outbox;

    std::array<int16_t, 3> encoders() const {
        glm::dvec3 angles;
        if (!inverseKinematics(poseKinematic, angles)) return {0, 0, 0};
        return {angleToEncoder(angles[0]), angleToEncoder(angles[1]), angleToEncoder(angles[2])};
    }
};

/// A FalconTransport that behaves like the Novint SDK firmware: answers each host packet with
/// one device packet carrying the encoder counts of the scripted pose.
class FirmwareEmulator final : public FalconTransport {
public:
    explicit FirmwareEmulator(std::shared_ptr<EmulatorState> state) : mState(std::move(state)) {}
    void open(unsigned) override { mOpen = true; }
    void close() noexcept override { mOpen = false; }
    bool isOpen() const noexcept override { return mOpen; }
    void setNormalMode() override {}
    void loadFirmware(const std::vector<uint8_t>& image) override {
        std::lock_guard lock(mState->mutex);
        mState->loadedImage = image;
        mState->firmware = true;
    }
    bool write(std::span<const uint8_t> bytes) noexcept override {
        std::this_thread::sleep_for(100us);  // about the Falcon's own pace
        std::lock_guard lock(mState->mutex);
        EmulatorState& s = *mState;
        if (s.unplugged) return false;
        if (!s.firmware) return true;
        HostPacket packet;
        if (bytes.size() != kPacketSize || !decodeHostPacket(bytes.first<kPacketSize>(), packet)) {
            ++s.badHostPackets;
            return true;
        }
        ++s.hostPackets;
        if (packet.homing) ++s.homingPackets;
        s.last = packet;
        if (s.mute) return true;
        DevicePacket reply;
        reply.encoder = s.encoders();
        reply.buttons = s.buttons;
        reply.homedAxes = s.homingPackets >= uint64_t(s.homeAfter) ? kAllAxesHomed : 0;
        for (uint8_t b : s.noise) s.outbox.push_back(b);
        for (uint8_t b : encodeDevicePacket(reply)) s.outbox.push_back(b);
        return true;
    }
    std::ptrdiff_t read(std::span<uint8_t> out, int timeoutMs) noexcept override {
        {
            std::lock_guard lock(mState->mutex);
            EmulatorState& s = *mState;
            if (s.unplugged) return -1;
            if (!s.outbox.empty()) {
                const std::size_t n = std::min({out.size(), s.chunk, s.outbox.size()});
                for (std::size_t i = 0; i < n; ++i) {
                    out[i] = s.outbox.front();
                    s.outbox.pop_front();
                }
                return std::ptrdiff_t(n);
            }
        }
        std::this_thread::sleep_for(
            std::min(std::chrono::microseconds(200), std::chrono::microseconds(1000 * timeoutMs)));
        return 0;
    }

private:
    std::shared_ptr<EmulatorState> mState;
    bool mOpen = false;
};

FalconSettings fastSettings() {
    FalconSettings s;
    s.probeTries = 3;
    s.replyTimeoutMs = 5;
    s.homingTimeout = 5s;
    s.silenceTimeout = 50ms;
    return s;
}

/// Polls `done` every millisecond for up to `limit`; whether it became true.
bool waitFor(const std::function<bool()>& done, std::chrono::milliseconds limit = 3000ms) {
    const auto end = std::chrono::steady_clock::now() + limit;
    while (std::chrono::steady_clock::now() < end) {
        if (done()) return true;
        std::this_thread::sleep_for(1ms);
    }
    return done();
}

std::unique_ptr<FalconDevice> makeDevice(const std::shared_ptr<EmulatorState>& state,
                                         std::filesystem::path firmware = {},
                                         FalconSettings settings = fastSettings()) {
    return std::make_unique<FalconDevice>(std::make_unique<FirmwareEmulator>(state),
                                          std::move(firmware), settings);
}

/// The motor units the device should send for `forceDevice` with the grip at the emulator's pose.
std::array<int16_t, 3> expectedUnits(EmulatorState& s, const glm::dvec3& forceDevice) {
    std::array<int16_t, 3> counts;
    {
        std::lock_guard lock(s.mutex);
        counts = s.encoders();
    }
    const ForwardResult fk = forwardKinematics(encoderAngles(counts), kWorkspaceCenter);
    glm::dvec3 torque;
    EXPECT_TRUE(fk.converged && jointTorques(fk.position, forceDevice, torque));
    return firmwareMotorUnits(torque);
}

std::array<int16_t, 3> lastMotor(EmulatorState& s) {
    std::lock_guard lock(s.mutex);
    return s.last.motor;
}

bool near(const std::array<int16_t, 3>& a, const std::array<int16_t, 3>& b, int tolerance = 1) {
    for (int i = 0; i < 3; ++i) {
        if (std::abs(int(a[i]) - int(b[i])) > tolerance) return false;
    }
    return true;
}

TEST(FalconDevice, HomesThenReadsThePose) {
    auto state = std::make_shared<EmulatorState>();
    const glm::dvec3 offset(0.01, -0.02, 0.015);
    state->poseKinematic = kWorkspaceCenter + offset;
    state->homeAfter = 5;
    state->buttons = 0x5;
    auto device = makeDevice(state);
    EXPECT_FALSE(device->loadedFirmware());
    {
        std::lock_guard lock(state->mutex);
        EXPECT_GE(state->homingPackets, 5U);
    }
    // Running: homing off, green LED.
    ASSERT_TRUE(waitFor([&] {
        std::lock_guard lock(state->mutex);
        return !state->last.homing && state->last.leds == kLedGreen;
    }));
    DeviceState out;
    ASSERT_TRUE(device->read(out));
    EXPECT_TRUE(out.connected);
    // One encoder count moves the grip by well under 0.1 mm.
    EXPECT_LT(glm::length(out.position - offset), 1e-4);
    EXPECT_EQ(out.buttons, 0x5U);
    EXPECT_EQ(out.orientation, glm::dquat(1.0, 0.0, 0.0, 0.0));
    // Standing still: the estimate stays at zero (up to the forward solve's last digits).
    ASSERT_TRUE(waitFor([&] { return device->read(out) && glm::length(out.velocity) < 1e-6; }));

    // Move the grip: the new pose arrives, later in time.
    const int64_t before = out.timeNs;
    {
        std::lock_guard lock(state->mutex);
        state->poseKinematic = kWorkspaceCenter;
    }
    ASSERT_TRUE(waitFor([&] { return device->read(out) && glm::length(out.position) < 1e-4; }));
    EXPECT_GT(out.timeNs, before);
    EXPECT_GT(device->counts().packets, 5U);
    EXPECT_EQ(device->counts().kinematicFailures, 0U);
}

TEST(FalconDevice, ForceArrivesAsMotorUnits) {
    auto state = std::make_shared<EmulatorState>();
    state->poseKinematic = kWorkspaceCenter + glm::dvec3(-0.01, 0.005, 0.02);
    auto device = makeDevice(state);
    const glm::dvec3 force(1.0, -2.0, 3.0);
    const std::array<int16_t, 3> expected = expectedUnits(*state, force);
    EXPECT_NE(expected, (std::array<int16_t, 3>{0, 0, 0}));
    device->write(force);
    EXPECT_TRUE(waitFor([&] { return near(lastMotor(*state), expected); }))
        << lastMotor(*state)[0] << " " << lastMotor(*state)[1] << " " << lastMotor(*state)[2];

    // Above maxForce the force is scaled to it, direction kept.
    const glm::dvec3 big(100.0, 0.0, 0.0);
    const std::array<int16_t, 3> capped =
        expectedUnits(*state, glm::dvec3(device->spec().maxForce, 0.0, 0.0));
    device->write(big);
    EXPECT_TRUE(waitFor([&] { return near(lastMotor(*state), capped); }));
}

TEST(FalconDevice, NonFiniteForceSendsZero) {
    auto state = std::make_shared<EmulatorState>();
    auto device = makeDevice(state);
    device->write({2.0, 0.0, 0.0});
    ASSERT_TRUE(waitFor([&] { return lastMotor(*state) != std::array<int16_t, 3>{0, 0, 0}; }));
    device->write({std::nan(""), 1.0, 1.0});
    EXPECT_TRUE(waitFor([&] { return lastMotor(*state) == std::array<int16_t, 3>{0, 0, 0}; }));
    device->write({2.0, 0.0, 0.0});
    ASSERT_TRUE(waitFor([&] { return lastMotor(*state) != std::array<int16_t, 3>{0, 0, 0}; }));
    device->write({0.0, INFINITY, 0.0});
    EXPECT_TRUE(waitFor([&] { return lastMotor(*state) == std::array<int16_t, 3>{0, 0, 0}; }));
}

TEST(FalconDevice, UnplugDisconnects) {
    auto state = std::make_shared<EmulatorState>();
    auto device = makeDevice(state);
    device->write({2.0, 0.0, 0.0});
    ASSERT_TRUE(waitFor([&] { return lastMotor(*state) != std::array<int16_t, 3>{0, 0, 0}; }));
    {
        std::lock_guard lock(state->mutex);
        state->unplugged = true;
    }
    DeviceState out;
    EXPECT_TRUE(waitFor([&] { return !device->read(out); }));
    EXPECT_FALSE(out.connected);
    EXPECT_EQ(out.velocity, glm::dvec3(0.0));
    EXPECT_TRUE(device->transportFailed());
    // The servo thread may keep writing; nothing reaches the (gone) transport, nothing crashes.
    device->write({1.0, 1.0, 1.0});
    EXPECT_FALSE(device->read(out));
}

TEST(FalconDevice, SilenceDisconnectsWithZeroForceUntilPacketsReturn) {
    auto state = std::make_shared<EmulatorState>();
    auto device = makeDevice(state);
    device->write({0.0, 3.0, 0.0});
    ASSERT_TRUE(waitFor([&] { return lastMotor(*state) != std::array<int16_t, 3>{0, 0, 0}; }));
    {
        std::lock_guard lock(state->mutex);
        state->mute = true;
    }
    DeviceState out;
    EXPECT_TRUE(waitFor([&] { return !device->read(out); }));
    EXPECT_FALSE(out.connected);
    // The device keeps talking, with the motors off: the position it would push from is stale.
    EXPECT_TRUE(waitFor([&] { return lastMotor(*state) == std::array<int16_t, 3>{0, 0, 0}; }));
    EXPECT_FALSE(device->transportFailed());
    {
        std::lock_guard lock(state->mutex);
        state->mute = false;
    }
    EXPECT_TRUE(waitFor([&] { return device->read(out); }));
    EXPECT_TRUE(waitFor([&] { return lastMotor(*state) != std::array<int16_t, 3>{0, 0, 0}; }));
}

TEST(FalconDevice, GarbageOnTheLineIsSkipped) {
    auto state = std::make_shared<EmulatorState>();
    state->noise = {0x00, '>', 'A', 0x7F, '<', 'B'};  // includes a false start
    state->chunk = 7;
    state->poseKinematic = kWorkspaceCenter + glm::dvec3(0.0, 0.01, 0.0);
    auto device = makeDevice(state);
    DeviceState out;
    ASSERT_TRUE(device->read(out));
    EXPECT_LT(glm::length(out.position - glm::dvec3(0.0, 0.01, 0.0)), 1e-4);
    EXPECT_TRUE(waitFor([&] { return device->counts().packets > 20; }));
    const FalconCounts c = device->counts();
    EXPECT_GT(c.skippedBytes, 0U);
    EXPECT_GT(c.badFrames, 0U);
}

TEST(FalconDevice, NoFirmwareAndNoFileIsAClearError) {
    auto state = std::make_shared<EmulatorState>();
    state->firmware = false;
    try {
        makeDevice(state);
        FAIL() << "expected an error";
    } catch (const std::runtime_error& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("no firmware file was given"), std::string::npos) << what;
        EXPECT_NE(what.find("Novint"), std::string::npos) << what;
    }
}

TEST(FalconDevice, LoadsTheFirmwareFileWhenNeeded) {
    auto state = std::make_shared<EmulatorState>();
    state->firmware = false;
    const std::filesystem::path file =
        std::filesystem::temp_directory_path() / "kizamu_falcon_test_firmware.bin";
    const std::vector<uint8_t> image{0x02, 0x00, 0xFF, 0x41, '<', '>', 0x10};
    {
        std::ofstream outFile(file, std::ios::binary);
        outFile.write(reinterpret_cast<const char*>(image.data()), std::streamsize(image.size()));
    }
    auto device = makeDevice(state, file);
    EXPECT_TRUE(device->loadedFirmware());
    {
        std::lock_guard lock(state->mutex);
        EXPECT_EQ(state->loadedImage, image);
    }
    DeviceState out;
    EXPECT_TRUE(device->read(out));
    device.reset();
    std::filesystem::remove(file);

    auto missing = std::make_shared<EmulatorState>();
    missing->firmware = false;
    EXPECT_THROW(makeDevice(missing, "/nonexistent/falcon_firmware.bin"), std::runtime_error);
}

TEST(FalconDevice, HomingTimeoutIsAnError) {
    auto state = std::make_shared<EmulatorState>();
    state->homeAfter = 1'000'000;
    FalconSettings settings = fastSettings();
    settings.homingTimeout = 100ms;
    try {
        makeDevice(state, {}, settings);
        FAIL() << "expected an error";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("homing"), std::string::npos) << e.what();
    }
    std::lock_guard lock(state->mutex);
    EXPECT_EQ(state->last.leds, kLedRed);
    EXPECT_TRUE(state->last.homing);
}

TEST(FalconDevice, ZeroMotorsOnDestruction) {
    auto state = std::make_shared<EmulatorState>();
    auto device = makeDevice(state);
    device->write({0.0, 0.0, 4.0});
    ASSERT_TRUE(waitFor([&] { return lastMotor(*state) != std::array<int16_t, 3>{0, 0, 0}; }));
    device.reset();
    EXPECT_EQ(lastMotor(*state), (std::array<int16_t, 3>{0, 0, 0}));
}

TEST(FalconDevice, SpecIsNovintsPublishedFigures) {
    const DeviceSpec spec = FalconDevice::falconSpec();
    EXPECT_EQ(spec.name, "Novint Falcon");
    EXPECT_DOUBLE_EQ(spec.maxForce, 8.9);
    EXPECT_FALSE(spec.orientation);
    EXPECT_DOUBLE_EQ(spec.rate, 1000.0);
    EXPECT_NEAR(spec.workspaceMax.x - spec.workspaceMin.x, 0.1016, 1e-12);
    EXPECT_EQ(spec.workspaceMin, -spec.workspaceMax);
    // The stiffness it advertises is passive with its damping at its rate.
    EXPECT_LE(spec.maxStiffness, passiveStiffnessBound(spec.damping, 0.0, 1.0 / spec.rate) + 1e-9);
}

TEST(FalconVelocityEstimator, FilteredDifference) {
    VelocityEstimator v(40.0);
    EXPECT_EQ(v.update({1.0, 2.0, 3.0}, 0.0), glm::dvec3(0.0));  // first sample: at rest
    for (int i = 0; i < 50; ++i) EXPECT_EQ(v.update({1.0, 2.0, 3.0}, 1e-3), glm::dvec3(0.0));
    // Constant 0.1 m/s along x at 1 kHz: the first-order filter converges geometrically.
    glm::dvec3 p(1.0, 2.0, 3.0), est(0.0);
    for (int i = 0; i < 300; ++i) {
        p.x += 1e-4;
        est = v.update(p, 1e-3);
    }
    EXPECT_NEAR(est.x, 0.1, 1e-6);
    EXPECT_NEAR(est.y, 0.0, 1e-15);
    // One step: alpha = dt / (dt + 1 / (2 pi fc)).
    VelocityEstimator w(40.0);
    w.update(glm::dvec3(0.0), 0.0);
    const double alpha = 1e-3 / (1e-3 + 1.0 / (2.0 * std::numbers::pi * 40.0));
    EXPECT_NEAR(w.update({1e-3, 0.0, 0.0}, 1e-3).x, alpha * 1.0, 1e-12);
    // A gap restarts at rest; NaN and non-positive dt keep the estimate.
    EXPECT_EQ(w.update({5.0, 0.0, 0.0}, 1.0), glm::dvec3(0.0));
    EXPECT_EQ(w.update({6.0, 0.0, 0.0}, std::nan("")), glm::dvec3(0.0));
}

TEST(FalconDevice, ServoSideAllocatesNothing) {
    auto state = std::make_shared<EmulatorState>();
    auto device = makeDevice(state);
    DeviceState out;
    device->read(out);
    device->write({0.0, 0.0, 0.0});
    const kizamu::test::AllocationCounts before = kizamu::test::threadAllocationCounts();
    for (int i = 0; i < 20000; ++i) {
        device->read(out);
        device->write({0.001 * (i % 100), std::nan(""), 1.0});
        device->write({0.0, 0.0, 0.001 * (i % 50)});
    }
    const kizamu::test::AllocationCounts after = kizamu::test::threadAllocationCounts();
    EXPECT_EQ(after.allocations, before.allocations);
    EXPECT_EQ(after.frees, before.frees);
}

/// A spring to the device frame's origin: the simplest servo client.
class CentringSpring final : public ServoClient {
public:
    void tick(const DeviceState& state, double, glm::dvec3& force) noexcept override {
        force = -200.0 * state.position;
    }
};

TEST(FalconDevice, RunsUnderTheServoTicker) {
    auto state = std::make_shared<EmulatorState>();
    const glm::dvec3 offset(0.01, 0.0, -0.005);
    state->poseKinematic = kWorkspaceCenter + offset;
    auto device = makeDevice(state);
    CentringSpring client;
    ServoTicker ticker(*device, client, 1000.0);
    const int64_t start = ServoLoop::clockNs();
    ticker.begin(start + ticker.periodNs());
    for (int i = 0; i < 200; ++i) {
        std::this_thread::sleep_for(1ms);
        ticker.step(ServoLoop::clockNs());
    }
    EXPECT_TRUE(ticker.connected());
    // The spring pulls towards the centre: about -200 N/m x offset (encoder quantisation aside).
    EXPECT_NEAR(ticker.lastForce().x, -2.0, 0.05);
    EXPECT_NEAR(ticker.lastForce().z, 1.0, 0.05);
    const std::array<int16_t, 3> expected = expectedUnits(*state, ticker.lastForce());
    EXPECT_TRUE(waitFor([&] { return near(lastMotor(*state), expected, 3); }));
}

}  // namespace
