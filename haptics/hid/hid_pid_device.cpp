// SPDX-License-Identifier: Apache-2.0
/// @file hid_pid_device.cpp
/// @brief HidPidDevice: setup, the device thread, and the lock-free exchange with the servo
/// thread (design: the header).
#include "haptics/hid/hid_pid_device.h"

#include <bit>
#include <chrono>
#include <cmath>
#include <numbers>

namespace kizamu::haptics::hid {

namespace {

int64_t steadyNowNs() noexcept {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(
               std::chrono::steady_clock::now().time_since_epoch())
        .count();
}

uint64_t packForce(float x, float y) noexcept {
    return uint64_t(std::bit_cast<uint32_t>(x)) | (uint64_t(std::bit_cast<uint32_t>(y)) << 32);
}

}  // namespace

HidPidDevice::HidPidDevice(std::unique_ptr<HidTransport> transport, const PidLayout& layout,
                           const HidPidSettings& settings)
    : mTransport(std::move(transport)), mCodec(layout, settings.codec), mSettings(settings) {
    if (!mTransport) throw std::invalid_argument("HidPidDevice: no transport");
    if (layout.axisCount == 0) throw std::invalid_argument("HidPidDevice: the layout has no input axis");
    if (!(settings.workspaceHalfWidth > 0.0) || !std::isfinite(settings.workspaceHalfWidth))
        throw std::invalid_argument("HidPidDevice: workspaceHalfWidth must be > 0 m");
    if (!(settings.maxForce > 0.0) || !std::isfinite(settings.maxForce))
        throw std::invalid_argument("HidPidDevice: maxForce must be > 0 N");
    if (!std::isfinite(settings.depth)) throw std::invalid_argument("HidPidDevice: depth must be finite");
    if (!(settings.velocityCutoffHz > 0.0)) throw std::invalid_argument("HidPidDevice: velocityCutoffHz must be > 0");
    if (settings.readTimeoutMs < 1 || settings.readTimeoutMs > 1000)
        throw std::invalid_argument("HidPidDevice: readTimeoutMs must be within 1..1000");
    mForceAxes = mCodec.forceAxes();
    const double hw = settings.workspaceHalfWidth;
    mSpec.name = settings.name;
    mSpec.maxForce = settings.maxForce;
    mSpec.maxStiffness = settings.maxStiffness;
    mSpec.damping = settings.damping;
    mSpec.rate = 1000.0;
    mSpec.workspaceMin = {-hw, mForceAxes > 1 ? -hw : 0.0, settings.depth};
    mSpec.workspaceMax = {hw, mForceAxes > 1 ? hw : 0.0, settings.depth};
    mSpec.orientation = false;
    mLastRead.position = {0.0, 0.0, settings.depth};
    mLastRead.connected = false;
}

HidPidDevice::~HidPidDevice() { stop(); }

void HidPidDevice::checkedWrite(const ReportBuffer& report, const char* what) {
    if (!mTransport->writeReport(report.view()))
        throw HidDeviceError(std::string("HID PID device: sending ") + what + " failed (device gone?)");
}

void HidPidDevice::start() {
    if (mStarted) throw std::logic_error("HidPidDevice::start: already started");
    ReportBuffer r;
    if (mCodec.encodeDeviceControl(DeviceCommand::Reset, r)) checkedWrite(r, "Device Reset");
    mCodec.encodeDeviceControl(DeviceCommand::EnableActuators, r);
    checkedWrite(r, "Enable Actuators");
    try {
        for (int a = 0; a < mForceAxes; ++a) {
            uint8_t index = uint8_t(a + 1);
            if (mCodec.createsEffects()) {
                mCodec.encodeCreateNewEffect(r);
                if (!mTransport->sendFeature(r.view()))
                    throw HidDeviceError("HID PID device: sending Create New Effect failed");
                mCodec.prepareBlockLoad(r);
                const int n = mTransport->getFeature({r.bytes.data(), r.size});
                if (n < 0) throw HidDeviceError("HID PID device: reading Block Load failed");
                const auto got = mCodec.decodeBlockLoad({r.bytes.data(), std::size_t(n)});
                if (!got) throw HidDeviceError("HID PID device: the device refused a constant-force effect (Block Load status)");
                index = *got;
            }
            mBlockIndex[std::size_t(a)] = index;
            mCodec.encodeSetEffect(index, a, r);
            checkedWrite(r, "Set Effect");
            mCodec.encodeConstantForce(index, 0.0, r);
            checkedWrite(r, "Set Constant Force");
            mCodec.encodeEffectOperation(index, EffectOp::Start, r);
            checkedWrite(r, "Effect Operation (start)");
        }
    } catch (...) {
        if (mCodec.encodeDeviceControl(DeviceCommand::DisableActuators, r)) mTransport->writeReport(r.view());
        throw;
    }
    mSentMagnitude = {0, 0};
    mForceWord.store(packForce(0.0f, 0.0f), std::memory_order_relaxed);
    // Until the first input report the state is the centre of the plane, at rest.
    publish(InputSample{}, steadyNowNs());
    mPrevTimeNs = -1;
    mConnected.store(true, std::memory_order_release);
    mStop.store(false, std::memory_order_release);
    mStarted = true;
    mThread = std::thread([this] { deviceThread(); });
}

void HidPidDevice::stop() noexcept {
    if (!mStarted) return;
    mStop.store(true, std::memory_order_release);
    if (mThread.joinable()) mThread.join();
    if (mConnected.load(std::memory_order_acquire)) shutdownEffects();
    mConnected.store(false, std::memory_order_release);
    mStarted = false;
}

void HidPidDevice::shutdownEffects() noexcept {
    ReportBuffer r;
    for (int a = 0; a < mForceAxes; ++a) {
        const uint8_t index = mBlockIndex[std::size_t(a)];
        mCodec.encodeConstantForce(index, 0.0, r);
        mTransport->writeReport(r.view());
        mCodec.encodeEffectOperation(index, EffectOp::Stop, r);
        mTransport->writeReport(r.view());
    }
    if (mCodec.encodeDeviceControl(DeviceCommand::DisableActuators, r)) mTransport->writeReport(r.view());
}

void HidPidDevice::deviceThread() noexcept {
    while (!mStop.load(std::memory_order_acquire)) {
        const int n = mTransport->readReport({mIn.bytes.data(), mIn.bytes.size()}, mSettings.readTimeoutMs);
        if (n < 0) break;
        if (n > 0) {
            InputSample sample;
            if (mCodec.decodeInput({mIn.bytes.data(), std::size_t(n)}, sample)) {
                publish(sample, steadyNowNs());
                mInputReports.fetch_add(1, std::memory_order_relaxed);
            }
        }
        if (!sendForce()) break;
    }
    if (!mStop.load(std::memory_order_acquire)) {
        // The transport failed: the device is gone and can take no more reports.
        mConnected.store(false, std::memory_order_release);
        mForceWord.store(packForce(0.0f, 0.0f), std::memory_order_relaxed);
    }
}

bool HidPidDevice::sendForce() noexcept {
    const uint64_t word = mForceWord.load(std::memory_order_acquire);
    const std::array<double, 2> f{double(std::bit_cast<float>(uint32_t(word))),
                                  double(std::bit_cast<float>(uint32_t(word >> 32)))};
    for (int a = 0; a < mForceAxes; ++a) {
        const std::size_t i = std::size_t(a);
        const double fraction = mSettings.axisSign[i] * f[i] / mSettings.maxForce;
        const int64_t magnitude = mCodec.magnitudeValue(fraction);
        if (magnitude == mSentMagnitude[i]) continue;
        mCodec.encodeConstantForce(mBlockIndex[i], fraction, mOut);
        if (!mTransport->writeReport(mOut.view())) return false;
        mSentMagnitude[i] = magnitude;
        mForceReports.fetch_add(1, std::memory_order_relaxed);
    }
    return true;
}

void HidPidDevice::publish(const InputSample& sample, int64_t timeNs) noexcept {
    const double hw = mSettings.workspaceHalfWidth;
    const glm::dvec3 pos{mSettings.axisSign[0] * sample.axes[0] * hw,
                         mForceAxes > 1 ? mSettings.axisSign[1] * sample.axes[1] * hw : 0.0, mSettings.depth};
    if (mPrevTimeNs >= 0 && timeNs > mPrevTimeNs) {
        // First-order low pass of the finite difference: alpha = dt / (dt + 1 / (2 pi fc)).
        const double dt = double(timeNs - mPrevTimeNs) * 1e-9;
        const double tau = 1.0 / (2.0 * std::numbers::pi * mSettings.velocityCutoffHz);
        const double alpha = dt / (dt + tau);
        mVel += alpha * ((pos - mPrevPos) / dt - mVel);
    } else if (mPrevTimeNs < 0) {
        mVel = glm::dvec3(0.0);
    }
    mPrevPos = pos;
    mPrevTimeNs = timeNs;

    Published p;
    p.position = pos;
    p.velocity = glm::dvec3(mVel.x, mVel.y, 0.0);
    p.timeNs = timeNs;
    p.buttons = sample.buttons;
    p.valid = true;
    mState.write(p);
}

bool HidPidDevice::read(DeviceState& out) noexcept {
    mState.take();
    const Published& p = mState.read();
    if (p.valid) {  // nothing published before start()
        mLastRead.position = p.position;
        mLastRead.velocity = p.velocity;
        mLastRead.timeNs = p.timeNs;
        mLastRead.buttons = p.buttons;
    }
    const bool ok = mConnected.load(std::memory_order_acquire);
    mLastRead.connected = ok;
    out = mLastRead;
    return ok;
}

void HidPidDevice::write(const glm::dvec3& force) noexcept {
    const bool finite = std::isfinite(force.x) && std::isfinite(force.y) && std::isfinite(force.z);
    const float x = finite ? float(force.x) : 0.0f;
    const float y = finite ? float(force.y) : 0.0f;
    mForceWord.store(packForce(x, y), std::memory_order_release);
}

HidPidCounters HidPidDevice::counters() const noexcept {
    return {mInputReports.load(std::memory_order_relaxed), mForceReports.load(std::memory_order_relaxed)};
}

}  // namespace kizamu::haptics::hid
