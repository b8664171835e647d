// SPDX-License-Identifier: Apache-2.0
/// @file engine_client.h
/// @brief The servo thread's work on the live engine: feel the published clay, carve with the
/// proxy. A ServoClient (servo_loop.h) that joins the device, its place in the clay, the proxy
/// renderer and the Engine.
///
/// Each tick: smooth the device's position (optional, input_filter.h), map it into the clay
/// (workspace.h), on a 2-DOF input project the tool onto the surface, acquire the published
/// snapshot (SnapshotStore::Reader, lock-free), run the proxy renderer on it through a
/// GuardedAccessor (its cache never outlives the snapshot), turn the force back into the
/// device's axes, and push the tool's pose to the engine's sample queue (wait-free, no
/// allocation). The pose pushed is the proxy's, not the device's: while the carve button is held
/// the proxy advances into the clay at the removal rate, so the engine carves where the proxy is
/// and never ahead of the hand (issue 32, "Carving with force").
///
/// Buttons (HapticToolSettings): the clutch, while held, leaves the tool where it is with no
/// force and no carving while the hand repositions the device; on release the device's new place
/// maps onto the tool (no jump) and the force ramps on again. The fine button toggles the
/// relative mode (Galyean and Hughes 2.2.2): the workspace shrinks by fineScale around the tool
/// for fine work, and back. The renderer is built for the normal scale, so it stays passive in
/// the fine mode (workspace.h).
///
/// Orientation: a device that measures none (a 3-DOF device such as the Falcon, or a 2-DOF one)
/// carves with HapticToolSettings::toolOrientation, which the application sets (the desktop
/// app: the view direction); a 6-DOF device's own, mapped into the world.
///
/// 2-DOF input (HID wheels and joysticks, hid_pid_device.h): the device gives a point in a
/// plane; the tool is put on the clay below it, along −planarAxis, pressed planarPress into the
/// contact surface, so the renderer's force is the surface's normal force and its in-plane part
/// is what the device renders: the hand feels slopes and edges as forces along the plane.
/// Threading: constructed on a cold path (it registers a Reader); tick() and restart() on the
/// servo thread only, which must be the sample queue's only producer.
#pragma once

#include "adf/guarded_accessor.h"
#include "adf/snapshot_store.h"
#include "engine/sample_queue.h"
#include "engine/tool_sample.h"
#include "haptics/input_filter.h"
#include "haptics/proxy_renderer.h"
#include "haptics/servo_loop.h"
#include "haptics/workspace.h"

#include <glm/gtc/quaternion.hpp>

#include <cstdint>
#include <optional>

namespace kizamu::haptics {

class TraceRing;

/// How the device becomes the tool. Plain values.
struct HapticToolSettings {
    WorkspaceMapping mapping;                         ///< the normal mode's map; the renderer's spec is mapping.worldSpec()
    double fineScale = 0.25;                          ///< the fine mode's scale as a fraction of mapping.scale, (0, 1]
    uint32_t clutchButton = engine::kButtonSecondary; ///< held: the tool stays, the device moves freely; 0: none
    uint32_t fineButton = engine::kButtonTertiary;    ///< each press toggles the fine mode; 0: none
    InputFilterSettings filter;                       ///< smoothing of the device's position (off by default)
    glm::dquat toolOrientation{1.0, 0.0, 0.0, 0.0};   ///< world; carves with it unless deviceOrientation
    bool deviceOrientation = false;                   ///< carve with the device's own (DeviceSpec::orientation)
    bool planar = false;                              ///< a 2-DOF input: project the tool onto the clay
    glm::dvec3 planarAxis{0.0, 0.0, 1.0};             ///< world, unit: the projection comes down along −planarAxis
    double planarPress = 0.001;                       ///< m (world): how far the projected tool is pressed in
};

class EngineHapticClient final : public ServoClient {
public:
    /// All three must outlive the client; `renderer` must have been built on
    /// settings.mapping.worldSpec(device spec) (the constructor does not check it).
    /// Cold path: registers a reader slot in `store`.
    /// @throw std::runtime_error when the store has no reader slot left;
    ///        std::invalid_argument for a fineScale outside (0, 1], a bad filter or planar axis
    EngineHapticClient(adf::SnapshotStore& store, engine::SampleQueue& samples, ProxyRenderer& renderer,
                       const HapticToolSettings& settings = {});
    void tick(const DeviceState& state, double dt, glm::dvec3& force) noexcept override;
    void restart(const DeviceState& state) noexcept override;

    /// Every tick is also pushed to `ring` (world frame; a full ring counts a drop). Null: none.
    /// Set before the servo loop starts.
    void setTrace(TraceRing* ring) noexcept { mTrace = ring; }

    /// The last tick's renderer output, in the world (the servo thread, or a lock-step test).
    const ProxyOutput& last() const noexcept { return mLast; }
    /// The map in use (the normal or the fine one, re-anchored by the clutch).
    const WorkspaceMapping& mapping() const noexcept { return mMapping; }
    bool fine() const noexcept { return mFine; }
    bool clutched() const noexcept { return mClutched; }
    /// Samples the queue refused (its pending buffer full of button edges): the next accepted
    /// sample carries the buttons on.
    uint64_t refusedSamples() const noexcept { return mRefused; }

private:
    /// The device's state in the world, on a 2-DOF input projected onto the clay.
    /// `reach` (m): how far above and below the plane point the projection looks.
    DeviceState place(const DeviceState& filtered, adf::AdfAccessor& clay, double reach) const noexcept;
    /// Handles the clutch and fine buttons; true while the clutch holds the tool.
    bool buttons(const DeviceState& filtered) noexcept;
    void push(const DeviceState& world, uint32_t buttons, bool clutched) noexcept;

    adf::SnapshotStore::Reader mReader;
    std::optional<adf::GuardedAccessor> mAccessor;  ///< engaged by the constructor: no allocation on the servo thread
    engine::SampleQueue& mSamples;
    ProxyRenderer& mRenderer;
    HapticToolSettings mSettings;
    InputFilter mFilter;
    WorkspaceMapping mMapping;
    TraceRing* mTrace = nullptr;
    ProxyOutput mLast;
    glm::dvec3 mTool{0.0};        ///< world: where the tool is (the proxy of the last tick)
    bool mHasTool = false;
    bool mFine = false;
    bool mClutched = false;
    uint32_t mPrevButtons = 0;
    uint64_t mRefused = 0;
};

}  // namespace kizamu::haptics
