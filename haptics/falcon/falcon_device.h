// SPDX-License-Identifier: Apache-2.0
/// @file falcon_device.h
/// @brief The Novint Falcon as a haptics::Device: firmware check and load, homing, and a device
/// thread that exchanges packets with the Falcon while the servo thread reads and writes
/// lock-free mailboxes.
///
/// Where it sits: the application builds a FalconDevice from a transport (FalconUsbTransport
/// for hardware) and gives it to a ServoLoop (haptics/servo_loop.h) like any Device.
/// Threads: the constructor runs on the caller's thread and does all cold work (open, firmware,
/// homing); then the device thread owns the transport, the packet parser and the kinematics:
/// per exchange it takes the newest force, turns it into motor units at the newest position,
/// writes one packet and reads the answer. Why a device thread: USB transfers block for up to
/// a millisecond or more and the servo thread must never block (servo_loop.h); the thread keeps
/// every transfer off it. The two threads meet only in two wait-free mailboxes
/// (util::TripleBuffer): the state (the device thread writes, the servo thread reads) and the
/// force (the servo side writes, the device thread reads; the watchdog's zero arrives through the
/// servo loop's gate, so the writes never overlap). read() and write() take no lock, never
/// allocate, never do I/O.
///
/// Velocity: the backward difference of consecutive positions over their arrival times,
/// through a first-order low-pass (VelocityEstimator, 40 Hz by default): the finite-difference
/// method with a low-pass filter, the usual estimator on encoder-only haptic devices (Chawda,
/// Celik and O'Malley, "A method for selecting velocity filter cut-off frequency ...", J. Dyn.
/// Sys. Meas. Control, 2015). One encoder count is ~0.04 mm at the grip, so the unfiltered
/// difference at 1 kHz is quantised to ~0.04 m/s; a 40 Hz cut-off passes voluntary hand motion
/// (under ~10 Hz) and attenuates that 500 Hz-band noise about 12-fold, for ~4 ms of lag.
///
/// Features:
///  [X] firmware detection; firmware load from a user-supplied file; clear error without one
///  [X] homing mode until all three axes report homed, with a timeout (red LED while homing,
///      green when running)
///  [X] position by forward kinematics (warm-started), filtered velocity, four grip buttons
///  [X] force -> motor units on the device thread; non-finite force -> zero; |force| clamped
///  [X] transport error -> disconnected, force zero; silence -> disconnected until packets return
///  [ ] reconnect after a transport error (a new FalconDevice is needed)
///  [ ] gravity compensation, per-unit calibration, button mapping to engine::ToolButton
/// Changes (breaking): 2026-12-06 first version.
#pragma once

#include "haptics/device.h"
#include "haptics/falcon/falcon_codec.h"
#include "haptics/falcon/falcon_transport.h"
#include "util/triple_buffer.h"

#include <glm/vec3.hpp>

#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <memory>
#include <thread>
#include <type_traits>

namespace kizamu::haptics::falcon {

/// What a FalconDevice is built with. Defaults suit a real Falcon.
struct FalconSettings {
    unsigned deviceIndex = 0;  ///< which Falcon the transport opens when it is not open yet
    int probeTries = 10;       ///< packets sent to detect firmware (libnifalcon tries 10)
    int replyTimeoutMs = 20;   ///< how long one exchange waits for the answer (ms)
    std::chrono::milliseconds homingTimeout{30'000};  ///< homing must finish within this
    std::chrono::milliseconds silenceTimeout{100};    ///< no packet for this long: disconnected
    double velocityCutoffHz = 40.0;                   ///< the velocity low-pass (Hz, > 0)
};

/// The filtered finite-difference velocity: v += alpha (dp/dt - v), alpha = dt / (dt + tau),
/// tau = 1 / (2 pi cutoff): a first-order low-pass of the backward difference, exact for any
/// sample spacing dt. The first sample, and one after a gap longer than kMaxGap, give zero.
/// Owned by one thread (FalconDevice's device thread, or a test).
class VelocityEstimator {
public:
    static constexpr double kMaxGap = 0.05;  ///< s: a longer gap restarts the estimate
    explicit VelocityEstimator(double cutoffHz = 40.0) noexcept;
    /// Takes the position `pos` (m) sampled `dt` (s) after the previous one; returns the
    /// velocity (m/s). dt <= 0 keeps the estimate; dt > kMaxGap or NaN restarts it at rest; a
    /// non-finite position is ignored. Complexity O(1). Memory: none.
    glm::dvec3 update(const glm::dvec3& pos, double dt) noexcept;
    void reset() noexcept {
        mHave = false;
        mVelocity = glm::dvec3(0.0);
    }
    const glm::dvec3& velocity() const noexcept { return mVelocity; }

private:
    double mTau;
    bool mHave = false;
    glm::dvec3 mPrev{0.0}, mVelocity{0.0};
};

/// Counts since construction, readable from any thread (each exact by itself).
struct FalconCounts {
    uint64_t exchanges = 0;     ///< packets written by the device thread
    uint64_t packets = 0;       ///< valid device packets received
    uint64_t skippedBytes = 0;  ///< bytes the parser dropped
    uint64_t badFrames = 0;
    uint64_t kinematicFailures = 0;  ///< forward kinematics that did not converge (state kept)
};

namespace detail {

/// The state the device thread publishes.
struct PublishedState {
    double position[3] = {0.0, 0.0, 0.0};  ///< m, device frame
    double velocity[3] = {0.0, 0.0, 0.0};  ///< m/s
    int64_t timeNs = 0;                    ///< servo clock at the packet's arrival
    uint32_t buttons = 0;
    uint32_t connected = 0;
};

/// The force the servo thread asks for (N, device frame); always finite.
struct PublishedForce {
    double force[3] = {0.0, 0.0, 0.0};
};

}  // namespace detail

/// A Novint Falcon. Owned by the application, one per physical device; outlives the ServoLoop
/// that uses it. read()/write() from the servo thread (write() of zero also from its watchdog,
/// never concurrently, servo_loop.h); spec(), counts() and the queries from any thread.
class FalconDevice final : public Device {
public:
    /// Opens `transport` (when not open yet), detects the firmware and loads `firmwareFile`
    /// when the Falcon has none, homes the three axes, then starts the device thread.
    /// Blocks until homed: the firmware's homing needs the grip moved through its range.
    /// @param transport    the byte pipe (not null); the device owns it from here on
    /// @param firmwareFile Novint's firmware file (we cannot ship it); empty: none given, which
    ///                     is fine when the Falcon already runs its firmware
    /// @throw std::invalid_argument for a null transport or bad settings; std::runtime_error
    ///        when the transport fails, when the Falcon has no firmware and no file was given
    ///        (or the file cannot be read or loaded), or when homing times out.
    /// Complexity: seconds (firmware upload, homing). Cold path.
    FalconDevice(std::unique_ptr<FalconTransport> transport, std::filesystem::path firmwareFile,
                 const FalconSettings& settings = {});
    /// Stops the device thread (which sends zero motor commands on its way out when the device
    /// still answers) and closes the transport.
    ~FalconDevice() override;
    FalconDevice(const FalconDevice&) = delete;
    FalconDevice& operator=(const FalconDevice&) = delete;

    /// Novint's published figures (see falconSpec()).
    const DeviceSpec& spec() const noexcept override { return mSpec; }
    /// The newest published state (device frame: the kinematic frame less kWorkspaceCenter).
    /// False, with out.connected false, once the transport failed or the Falcon went silent.
    /// Servo thread. Never blocks, never allocates. Complexity O(1).
    bool read(DeviceState& out) noexcept override;
    /// Holds `force` (N, device frame) for the device thread; non-finite becomes zero and a
    /// magnitude above spec().maxForce is scaled down to it. Servo thread (or its watchdog).
    /// Never blocks, never allocates. Complexity O(1).
    void write(const glm::dvec3& force) noexcept override;

    /// Whether this constructor uploaded firmware (false: the Falcon already had it).
    bool loadedFirmware() const noexcept { return mLoadedFirmware; }
    /// Whether the device thread ended because the transport failed. Any thread.
    bool transportFailed() const noexcept {
        return mTransportFailed.load(std::memory_order_acquire);
    }
    FalconCounts counts() const noexcept;

    /// The Falcon's specification: Novint's published 2 lb (8.9 N) force and 4 x 4 x 4 in
    /// (0.1016 m) workspace, centred on the device frame's origin; 1 kHz; 3-DOF.
    /// Damping b = 0.5 N·s/m: Novint publishes none; this is the least damping with which the
    /// 1000 N/m wall libnifalcon's falcon_test_cli renders on the Falcon (FalconCubeTest) is
    /// passive at 1 kHz (b >= K T / 2, Colgate and Schenkel), so the true figure is at least
    /// this, and maxStiffness = 1000 N/m is that demonstrated wall.
    static DeviceSpec falconSpec();

private:
    /// Writes `packet`, then reads until one device packet arrives (into `reply`) or
    /// `timeoutMs` passes: 1 got one, 0 none, -1 transport failure.
    int exchange(const HostPacket& packet, DevicePacket& reply, int timeoutMs) noexcept;
    bool probeFirmware();
    void loadFirmwareFile();
    void home();
    /// The kinematics of one packet: position (warm-started), velocity, publication.
    void accept(const DevicePacket& packet, int64_t nowNs) noexcept;
    void publishDisconnected() noexcept;
    void deviceMain() noexcept;

    std::unique_ptr<FalconTransport> mTransport;
    std::filesystem::path mFirmwareFile;
    FalconSettings mSettings;
    DeviceSpec mSpec;
    bool mLoadedFirmware = false;

    // Device thread only (and the constructor before the thread starts).
    DevicePacketParser mParser;
    VelocityEstimator mVelocity;
    glm::dvec3 mPosKinematic{0.0};  ///< m, the newest position, the warm start of the next solve
    bool mHavePosition = false;
    int64_t mLastPacketNs = 0;

    detail::PublishedState mPublished;  ///< the last state published (device thread)

    // Shared, wait-free.
    util::TripleBuffer<detail::PublishedState> mState;
    util::TripleBuffer<detail::PublishedForce> mForce;
    std::atomic<bool> mStop{false};
    std::atomic<bool> mTransportFailed{false};
    std::atomic<uint64_t> mExchanges{0}, mPackets{0}, mSkippedBytes{0}, mBadFrames{0},
        mKinematicFailures{0};

    std::thread mThread;
};

}  // namespace kizamu::haptics::falcon
