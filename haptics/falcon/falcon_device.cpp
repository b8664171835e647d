// SPDX-License-Identifier: Apache-2.0
/// @file falcon_device.cpp
/// @brief FalconDevice: the constructor's cold work (firmware, homing) and the device thread's
/// packet exchange (threading and design in falcon_device.h).
#include "haptics/falcon/falcon_device.h"

#include "haptics/falcon/falcon_kinematics.h"
#include "haptics/servo_loop.h"

#include <glm/geometric.hpp>

#include <cmath>
#include <fstream>
#include <iterator>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

namespace kizamu::haptics::falcon {

namespace {

bool finite(const glm::dvec3& v) noexcept {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

[[noreturn]] void fail(const std::string& message) {
    throw std::runtime_error("Novint Falcon: " + message);
}

}  // namespace

// ---- VelocityEstimator ----

VelocityEstimator::VelocityEstimator(double cutoffHz) noexcept
    : mTau(cutoffHz > 0.0 ? 1.0 / (2.0 * std::numbers::pi * cutoffHz) : 0.0) {}

glm::dvec3 VelocityEstimator::update(const glm::dvec3& pos, double dt) noexcept {
    if (!finite(pos)) return mVelocity;
    if (!mHave || !(dt <= kMaxGap)) {  // first sample, a long gap, or NaN dt: restart at rest
        mHave = true;
        mPrev = pos;
        mVelocity = glm::dvec3(0.0);
        return mVelocity;
    }
    if (!(dt > 0.0)) return mVelocity;
    const glm::dvec3 raw = (pos - mPrev) / dt;
    const double alpha = dt / (dt + mTau);
    mVelocity += alpha * (raw - mVelocity);
    mPrev = pos;
    return mVelocity;
}

// ---- FalconDevice ----

DeviceSpec FalconDevice::falconSpec() {
    DeviceSpec spec;
    spec.name = "Novint Falcon";
    spec.maxForce = 8.9;  // Novint: "2+ lbs" of force
    spec.damping = 0.5;   // N·s/m, the passivity lower bound of the 1000 N/m demo wall (header)
    spec.maxStiffness = 1000.0;
    spec.rate = 1000.0;
    const double half = 0.5 * 4.0 * 0.0254;  // Novint: 4 x 4 x 4 in workspace
    spec.workspaceMin = glm::dvec3(-half);
    spec.workspaceMax = glm::dvec3(half);
    spec.orientation = false;
    return spec;
}

FalconDevice::FalconDevice(std::unique_ptr<FalconTransport> transport,
                           std::filesystem::path firmwareFile, const FalconSettings& settings)
    : mTransport(std::move(transport)),
      mFirmwareFile(std::move(firmwareFile)),
      mSettings(settings),
      mSpec(falconSpec()),
      mVelocity(settings.velocityCutoffHz) {
    if (!mTransport) throw std::invalid_argument("FalconDevice: the transport is null");
    if (settings.probeTries < 1 || settings.replyTimeoutMs < 1 ||
        !(settings.velocityCutoffHz > 0.0) || settings.homingTimeout.count() <= 0 ||
        settings.silenceTimeout.count() <= 0) {
        throw std::invalid_argument("FalconDevice: settings out of range");
    }
    if (!mTransport->isOpen()) mTransport->open(settings.deviceIndex);
    if (!probeFirmware()) {
        if (mFirmwareFile.empty()) {
            fail(
                "the device runs no firmware (it does not answer packets) and no firmware file was "
                "given. Kizamu cannot "
                "ship Novint's firmware: pass the path to the firmware file from Novint's Falcon "
                "driver package.");
        }
        loadFirmwareFile();
        mLoadedFirmware = true;
        if (!probeFirmware())
            fail("the firmware from '" + mFirmwareFile.string() +
                 "' loaded but the device does not answer with it");
    }
    home();
    mThread = std::thread([this] { deviceMain(); });
}

FalconDevice::~FalconDevice() {
    mStop.store(true, std::memory_order_release);
    if (mThread.joinable()) mThread.join();
    mTransport->close();
}

int FalconDevice::exchange(const HostPacket& packet, DevicePacket& reply, int timeoutMs) noexcept {
    const PacketBytes bytes = encodeHostPacket(packet);
    if (!mTransport->write(bytes)) return -1;
    mExchanges.fetch_add(1, std::memory_order_relaxed);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeoutMs);
    std::array<uint8_t, 64> buffer{};
    for (;;) {
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
                              deadline - std::chrono::steady_clock::now())
                              .count();
        const std::ptrdiff_t n = mTransport->read(buffer, int(std::max<int64_t>(0, left)));
        if (n < 0) return -1;
        const ParserCounts before = mParser.counts();
        const int got =
            mParser.feed(std::span<const uint8_t>(buffer.data(), std::size_t(n)), reply);
        const ParserCounts& after = mParser.counts();
        mPackets.fetch_add(after.packets - before.packets, std::memory_order_relaxed);
        mSkippedBytes.fetch_add(after.skippedBytes - before.skippedBytes,
                                std::memory_order_relaxed);
        mBadFrames.fetch_add(after.badFrames - before.badFrames, std::memory_order_relaxed);
        if (got > 0) return 1;
        if (left <= 0) return 0;
    }
}

bool FalconDevice::probeFirmware() {
    // libnifalcon's FalconFirmware::isFirmwareLoaded: the firmware answers a packet with a
    // packet; the boot loader does not. Zero motor commands, homing off.
    DevicePacket reply;
    for (int i = 0; i < mSettings.probeTries; ++i) {
        const int rc = exchange(HostPacket{}, reply, mSettings.replyTimeoutMs);
        if (rc < 0) fail("the transport failed while detecting the firmware");
        if (rc > 0) return true;
    }
    return false;
}

void FalconDevice::loadFirmwareFile() {
    std::ifstream in(mFirmwareFile, std::ios::binary);
    if (!in) fail("cannot read the firmware file '" + mFirmwareFile.string() + "'");
    std::vector<uint8_t> image((std::istreambuf_iterator<char>(in)),
                               std::istreambuf_iterator<char>());
    if (image.empty()) fail("the firmware file '" + mFirmwareFile.string() + "' is empty");
    mTransport->loadFirmware(image);
    mParser.reset();
}

void FalconDevice::home() {
    HostPacket packet;
    packet.homing = true;
    packet.leds = kLedRed;
    DevicePacket reply;
    const auto deadline = std::chrono::steady_clock::now() + mSettings.homingTimeout;
    for (;;) {
        const int rc = exchange(packet, reply, mSettings.replyTimeoutMs);
        if (rc < 0) fail("the transport failed while homing");
        if (rc > 0 && reply.allHomed()) break;
        if (std::chrono::steady_clock::now() >= deadline) {
            fail("homing did not finish within " + std::to_string(mSettings.homingTimeout.count()) +
                 " ms: move the grip all the way out and back in, slowly, until the LED turns "
                 "green");
        }
    }
    accept(reply, ServoLoop::clockNs());
}

void FalconDevice::accept(const DevicePacket& packet, int64_t nowNs) noexcept {
    const glm::dvec3 guess = mHavePosition ? mPosKinematic : kWorkspaceCenter;
    const ForwardResult fk = forwardKinematics(encoderAngles(packet.encoder), guess);
    if (fk.converged) {
        const double dt = mHavePosition ? double(nowNs - mLastPacketNs) * 1e-9 : 0.0;
        mPosKinematic = fk.position;
        if (!mHavePosition) mVelocity.reset();
        mVelocity.update(mPosKinematic, dt);
        mHavePosition = true;
    } else {
        mKinematicFailures.fetch_add(1, std::memory_order_relaxed);
    }
    mLastPacketNs = nowNs;
    detail::PublishedState state;
    const glm::dvec3 posDevice = mPosKinematic - kWorkspaceCenter;
    for (int i = 0; i < 3; ++i) {
        state.position[i] = posDevice[i];
        state.velocity[i] = mVelocity.velocity()[i];
    }
    state.timeNs = nowNs;
    state.buttons = packet.buttons;
    state.connected = mHavePosition ? 1U : 0U;
    mPublished = state;
    mState.write(state);
}

void FalconDevice::publishDisconnected() noexcept {
    detail::PublishedState state = mPublished;
    state.connected = 0;
    for (double& v : state.velocity) v = 0.0;
    mPublished = state;
    mState.write(state);
}

void FalconDevice::deviceMain() noexcept {
    const int64_t silenceNs = int64_t(
        std::chrono::duration_cast<std::chrono::nanoseconds>(mSettings.silenceTimeout).count());
    bool silent = false;
    DevicePacket reply;
    while (!mStop.load(std::memory_order_acquire)) {
        HostPacket packet;
        packet.leds = kLedGreen;
        mForce.take();
        const detail::PublishedForce& held = mForce.read();
        if (!silent && mHavePosition) {
            const glm::dvec3 force(held.force[0], held.force[1], held.force[2]);
            glm::dvec3 torque;
            // The device frame is the kinematic frame translated: forces are the same vectors.
            if (jointTorques(mPosKinematic, force, torque))
                packet.motor = firmwareMotorUnits(torque);
        }
        const int rc = exchange(packet, reply, mSettings.replyTimeoutMs);
        const int64_t now = ServoLoop::clockNs();
        if (rc < 0) {
            mTransportFailed.store(true, std::memory_order_release);
            publishDisconnected();
            return;  // the transport is gone: nothing more can be sent
        }
        if (rc > 0) {
            if (silent) {
                silent = false;
                mVelocity.reset();
            }
            accept(reply, now);
        } else if (!silent && now - mLastPacketNs > silenceNs) {
            // Stale position: stop commanding torque until the Falcon answers again.
            silent = true;
            publishDisconnected();
        }
    }
    // Leave the motors unpowered (best effort: the transport may be gone).
    DevicePacket ignored;
    exchange(HostPacket{}, ignored, mSettings.replyTimeoutMs);
}

bool FalconDevice::read(DeviceState& out) noexcept {
    mState.take();
    const detail::PublishedState& s = mState.read();
    out.timeNs = s.timeNs;
    out.position = glm::dvec3(s.position[0], s.position[1], s.position[2]);
    out.orientation = glm::dquat(1.0, 0.0, 0.0, 0.0);
    out.velocity = glm::dvec3(s.velocity[0], s.velocity[1], s.velocity[2]);
    out.buttons = s.buttons;
    out.connected = s.connected != 0;
    return out.connected;
}

void FalconDevice::write(const glm::dvec3& force) noexcept {
    glm::dvec3 f = finite(force) ? force : glm::dvec3(0.0);
    const double magnitude = glm::length(f);
    if (magnitude > mSpec.maxForce) f *= mSpec.maxForce / magnitude;
    detail::PublishedForce held;
    for (int i = 0; i < 3; ++i) held.force[i] = f[i];
    mForce.write(held);
}

FalconCounts FalconDevice::counts() const noexcept {
    FalconCounts c;
    c.exchanges = mExchanges.load(std::memory_order_relaxed);
    c.packets = mPackets.load(std::memory_order_relaxed);
    c.skippedBytes = mSkippedBytes.load(std::memory_order_relaxed);
    c.badFrames = mBadFrames.load(std::memory_order_relaxed);
    c.kinematicFailures = mKinematicFailures.load(std::memory_order_relaxed);
    return c;
}

}  // namespace kizamu::haptics::falcon
