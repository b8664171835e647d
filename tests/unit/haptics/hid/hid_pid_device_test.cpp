// SPDX-License-Identifier: Apache-2.0
/// @file hid_pid_device_test.cpp
/// @brief HidPidDevice over a scripted in-test transport: setup reports, axes -> position,
/// force -> reports, non-finite -> zero, unplug -> disconnected, stop -> zero and stop.
#include "haptics/hid/device_list.h"
#include "haptics/hid/hid_pid_device.h"
#include "haptics/servo_loop.h"
#include "unit/haptics/hid/pid_fixture.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>
#include <functional>
#include <limits>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

namespace kizamu::haptics::hid {
namespace {

using Bytes = std::vector<uint8_t>;

/// What the scripted device saw and will answer; shared between the test and the transport.
struct Script {
    std::mutex mutex;
    std::deque<Bytes> inputs;      ///< input reports to hand out, one per read
    std::vector<Bytes> writes;     ///< output reports received
    std::vector<Bytes> features;   ///< feature reports received
    uint8_t nextBlock = 3;         ///< the block index Block Load assigns next
    bool refuse = false;           ///< Block Load answers "full"
    bool unplugged = false;        ///< every call fails

    std::vector<Bytes> writesSnapshot() {
        std::lock_guard lock(mutex);
        return writes;
    }
};

/// A HidTransport answering from a Script (the device thread is its only caller once started).
class ScriptedTransport final : public HidTransport {
public:
    explicit ScriptedTransport(std::shared_ptr<Script> s) : mS(std::move(s)) {}
    bool writeReport(std::span<const uint8_t> report) override {
        std::lock_guard lock(mS->mutex);
        if (mS->unplugged) return false;
        mS->writes.emplace_back(report.begin(), report.end());
        return true;
    }
    int readReport(std::span<uint8_t> buffer, int timeoutMs) override {
        {
            std::lock_guard lock(mS->mutex);
            if (mS->unplugged) return -1;
            if (!mS->inputs.empty()) {
                const Bytes r = mS->inputs.front();
                mS->inputs.pop_front();
                const std::size_t n = std::min(r.size(), buffer.size());
                std::copy_n(r.begin(), n, buffer.begin());
                return int(n);
            }
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(timeoutMs));
        return 0;
    }
    bool sendFeature(std::span<const uint8_t> report) override {
        std::lock_guard lock(mS->mutex);
        if (mS->unplugged) return false;
        mS->features.emplace_back(report.begin(), report.end());
        return true;
    }
    int getFeature(std::span<uint8_t> buffer) override {
        std::lock_guard lock(mS->mutex);
        if (mS->unplugged || buffer.size() < 3 || buffer[0] != 0x12) return -1;
        buffer[1] = mS->nextBlock++;
        buffer[2] = mS->refuse ? 0x02 : 0x01;
        return 3;
    }

private:
    std::shared_ptr<Script> mS;
};

/// Polls `done` for up to 2 s.
bool eventually(const std::function<bool()>& done) {
    for (int i = 0; i < 400; ++i) {
        if (done()) return true;
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return done();
}

Bytes inputReport(int16_t x, int16_t y, uint16_t buttons = 0) {
    return {0x01, uint8_t(buttons & 0xFF), uint8_t(buttons >> 8), uint8_t(uint16_t(x) & 0xFF),
            uint8_t(uint16_t(x) >> 8), uint8_t(uint16_t(y) & 0xFF), uint8_t(uint16_t(y) >> 8)};
}

bool contains(const std::vector<Bytes>& v, const Bytes& b) { return std::find(v.begin(), v.end(), b) != v.end(); }

struct Rig {
    std::shared_ptr<Script> script = std::make_shared<Script>();
    std::unique_ptr<HidPidDevice> device;
    explicit Rig(HidPidSettings settings = {}) {
        settings.maxForce = 3.0;
        settings.workspaceHalfWidth = 0.05;
        settings.depth = -0.01;
        settings.readTimeoutMs = 1;
        device = std::make_unique<HidPidDevice>(std::make_unique<ScriptedTransport>(script),
                                                findPidLayout(parseReportDescriptor(fixture::joystick())), settings);
    }
};

TEST(HidPidDevice, SetupSendsResetEnableAndOneEffectPerAxis) {
    Rig rig;
    DeviceState st;
    EXPECT_FALSE(rig.device->read(st));  // not started
    EXPECT_FALSE(st.connected);
    rig.device->start();
    EXPECT_EQ(rig.device->forceAxes(), 2);
    EXPECT_TRUE(rig.device->read(st));
    EXPECT_TRUE(st.connected);
    EXPECT_EQ(st.position, glm::dvec3(0.0, 0.0, -0.01));  // centre until the first report
    rig.device->stop();
    const auto w = rig.script->writesSnapshot();
    ASSERT_GE(w.size(), 8u);
    EXPECT_EQ(w[0], (Bytes{0x0C, 0x04}));  // reset
    EXPECT_EQ(w[1], (Bytes{0x0C, 0x01}));  // enable actuators
    // Block Load gave 3 (X) and 4 (Y).
    EXPECT_EQ(w[2], (Bytes{0x01, 0x03, 0x01, 0xFF, 0xFF, 0xFF, 0x01, 0x28, 0x23, 0x00, 0x00}));
    EXPECT_EQ(w[3], (Bytes{0x05, 0x03, 0x00, 0x00}));
    EXPECT_EQ(w[4], (Bytes{0x0A, 0x03, 0x01, 0x01}));
    EXPECT_EQ(w[5], (Bytes{0x01, 0x04, 0x01, 0xFF, 0xFF, 0xFF, 0x02, 0x00, 0x00, 0x00, 0x00}));
    EXPECT_EQ(w[6], (Bytes{0x05, 0x04, 0x00, 0x00}));
    EXPECT_EQ(w[7], (Bytes{0x0A, 0x04, 0x01, 0x01}));
    ASSERT_EQ(rig.script->features.size(), 2u);
    EXPECT_EQ(rig.script->features[0], (Bytes{0x11, 0x01}));
    // stop(): zero force and stop per effect, then disable the actuators.
    EXPECT_EQ(w.back(), (Bytes{0x0C, 0x02}));
    EXPECT_TRUE(contains(w, Bytes{0x0A, 0x03, 0x03, 0x01}));
    EXPECT_TRUE(contains(w, Bytes{0x0A, 0x04, 0x03, 0x01}));
    EXPECT_FALSE(rig.device->read(st));
}

TEST(HidPidDevice, RefusedEffectIsAnErrorAndDisablesActuators) {
    Rig rig;
    rig.script->refuse = true;
    EXPECT_THROW(rig.device->start(), HidDeviceError);
    EXPECT_EQ(rig.script->writesSnapshot().back(), (Bytes{0x0C, 0x02}));
}

TEST(HidPidDevice, AxesBecomePositionAndButtons) {
    Rig rig;
    rig.device->start();
    {
        std::lock_guard lock(rig.script->mutex);
        rig.script->inputs.push_back(inputReport(16384, -32767, 0x0005));
    }
    ASSERT_TRUE(eventually([&] { return rig.device->counters().inputReports >= 1; }));
    DeviceState st;
    ASSERT_TRUE(rig.device->read(st));
    EXPECT_NEAR(st.position.x, 16384.0 / 32767.0 * 0.05, 1e-9);
    EXPECT_NEAR(st.position.y, -0.05, 1e-9);
    EXPECT_DOUBLE_EQ(st.position.z, -0.01);
    EXPECT_EQ(st.buttons, 0x5u);
    EXPECT_EQ(rig.device->spec().maxForce, 3.0);
    EXPECT_EQ(rig.device->spec().workspaceMax.x, 0.05);
}

TEST(HidPidDevice, VelocityFollowsMotion) {
    Rig rig;
    rig.device->start();
    for (int i = 0; i <= 10; ++i) {
        {
            std::lock_guard lock(rig.script->mutex);
            rig.script->inputs.push_back(inputReport(int16_t(i * 3000), 0));
        }
        ASSERT_TRUE(eventually([&] { return rig.device->counters().inputReports >= uint64_t(i + 1); }));
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    DeviceState st;
    ASSERT_TRUE(rig.device->read(st));
    EXPECT_GT(st.velocity.x, 0.0);
    EXPECT_TRUE(std::isfinite(st.velocity.x));
    EXPECT_EQ(st.velocity.y, 0.0);
}

TEST(HidPidDevice, ForceBecomesConstantForceReports) {
    Rig rig;
    rig.device->start();
    // maxForce 3 N: x = 1.5 N is half scale (16384), y = -3 N full negative (-32767); z ignored.
    rig.device->write({1.5, -3.0, 7.0});
    ASSERT_TRUE(eventually([&] {
        const auto w = rig.script->writesSnapshot();
        return contains(w, Bytes{0x05, 0x03, 0x00, 0x40}) && contains(w, Bytes{0x05, 0x04, 0x01, 0x80});
    }));
    // Beyond maxForce: clamped to full scale.
    rig.device->write({30.0, 0.0, 0.0});
    ASSERT_TRUE(eventually([&] { return contains(rig.script->writesSnapshot(), Bytes{0x05, 0x03, 0xFF, 0x7F}); }));
    // Non-finite: zero on both axes.
    rig.device->write({std::numeric_limits<double>::quiet_NaN(), 1.0, 0.0});
    ASSERT_TRUE(eventually([&] {
        const auto w = rig.script->writesSnapshot();
        const auto lastX = std::find_if(w.rbegin(), w.rend(), [](const Bytes& b) { return b.size() == 4 && b[0] == 0x05 && b[1] == 0x03; });
        const auto lastY = std::find_if(w.rbegin(), w.rend(), [](const Bytes& b) { return b.size() == 4 && b[0] == 0x05 && b[1] == 0x04; });
        return lastX != w.rend() && lastY != w.rend() && *lastX == Bytes{0x05, 0x03, 0x00, 0x00} &&
               *lastY == Bytes{0x05, 0x04, 0x00, 0x00};
    }));
    EXPECT_GE(rig.device->counters().forceReports, 3u);
}

TEST(HidPidDevice, UnplugDisconnectsAndStopsSending) {
    Rig rig;
    rig.device->start();
    rig.device->write({1.5, 0.0, 0.0});
    ASSERT_TRUE(eventually([&] { return contains(rig.script->writesSnapshot(), Bytes{0x05, 0x03, 0x00, 0x40}); }));
    {
        std::lock_guard lock(rig.script->mutex);
        rig.script->unplugged = true;
    }
    ASSERT_TRUE(eventually([&] { return !rig.device->connected(); }));
    DeviceState st;
    EXPECT_FALSE(rig.device->read(st));
    EXPECT_FALSE(st.connected);
    const std::size_t before = rig.script->writesSnapshot().size();
    rig.device->write({2.0, 2.0, 0.0});  // harmless: nobody sends it
    rig.device->stop();
    EXPECT_EQ(rig.script->writesSnapshot().size(), before);
}

TEST(HidPidDevice, DestructorZeroesAndStops) {
    auto script = std::make_shared<Script>();
    {
        HidPidSettings s;
        s.readTimeoutMs = 1;
        HidPidDevice device(std::make_unique<ScriptedTransport>(script),
                            findPidLayout(parseReportDescriptor(fixture::joystick())), s);
        device.start();
        device.write({1.0, 1.0, 0.0});
        ASSERT_TRUE(eventually([&] { return device.counters().forceReports >= 2; }));
    }
    const auto w = script->writesSnapshot();
    ASSERT_GE(w.size(), 5u);
    EXPECT_EQ(w.back(), (Bytes{0x0C, 0x02}));
    EXPECT_EQ(w[w.size() - 5], (Bytes{0x05, 0x03, 0x00, 0x00}));
    EXPECT_EQ(w[w.size() - 4], (Bytes{0x0A, 0x03, 0x03, 0x01}));
    EXPECT_EQ(w[w.size() - 3], (Bytes{0x05, 0x04, 0x00, 0x00}));
    EXPECT_EQ(w[w.size() - 2], (Bytes{0x0A, 0x04, 0x03, 0x01}));
}

TEST(HidPidDevice, RejectsBadSettings) {
    HidPidSettings s;
    s.maxForce = 0.0;
    EXPECT_THROW(HidPidDevice(std::make_unique<ScriptedTransport>(std::make_shared<Script>()),
                              findPidLayout(parseReportDescriptor(fixture::joystick())), s),
                 std::invalid_argument);
}

/// A client pushing a fixed force, recording the state it saw.
class FixedForceClient final : public ServoClient {
public:
    glm::dvec3 force{0.0};
    DeviceState seen;
    void tick(const DeviceState& state, double, glm::dvec3& out) noexcept override {
        seen = state;
        out = force;
    }
};

TEST(HidPidDevice, DrivenByTheServoTicker) {
    Rig rig;
    rig.device->start();
    {
        std::lock_guard lock(rig.script->mutex);
        rig.script->inputs.push_back(inputReport(-32767, 0));
    }
    ASSERT_TRUE(eventually([&] { return rig.device->counters().inputReports >= 1; }));
    FixedForceClient client;
    client.force = {-1.5, 0.75, 0.0};  // -16384 on X, round(0.25 * 32767) = 8192 = 0x2000 on Y
    ServoTicker ticker(*rig.device, client, 1000.0);
    ticker.begin(1'000'000);
    for (int i = 1; i <= 5; ++i) ticker.step(int64_t(i) * 1'000'000);
    EXPECT_TRUE(ticker.connected());
    EXPECT_NEAR(client.seen.position.x, -0.05, 1e-12);
    ASSERT_TRUE(eventually([&] {
        const auto w = rig.script->writesSnapshot();
        return contains(w, Bytes{0x05, 0x03, 0x00, 0xC0}) && contains(w, Bytes{0x05, 0x04, 0x00, 0x20});
    }));
}

TEST(DeviceList, SimulatedStylusAlwaysListed) {
    const DeviceListing none = listDevices({.usb = false, .hid = false});
    ASSERT_EQ(none.devices.size(), 1u);
    EXPECT_EQ(none.devices[0].id, "sim");
    EXPECT_TRUE(none.devices[0].available);
    EXPECT_FALSE(none.anyReal());
    // The real enumeration: whatever this machine has, it does not throw and lists sim first.
    const DeviceListing all = listDevices();
    ASSERT_FALSE(all.devices.empty());
    EXPECT_EQ(all.devices[0].kind, FoundKind::Simulated);
    for (const FoundDevice& d : all.devices) EXPECT_FALSE(d.status.empty()) << d.id;
}

}  // namespace
}  // namespace kizamu::haptics::hid
