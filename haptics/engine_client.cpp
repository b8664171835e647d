// SPDX-License-Identifier: Apache-2.0
/// @file engine_client.cpp
/// @brief EngineHapticClient: buttons, map, one guard, one renderer update and one push per
/// servo tick.
#include "haptics/engine_client.h"

#include "haptics/haptic_trace.h"

#include <glm/geometric.hpp>

#include <cmath>
#include <stdexcept>

namespace kizamu::haptics {

EngineHapticClient::EngineHapticClient(adf::SnapshotStore& store, engine::SampleQueue& samples, ProxyRenderer& renderer,
                                       const HapticToolSettings& settings)
    : mReader(store), mSamples(samples), mRenderer(renderer), mSettings(settings), mFilter(settings.filter),
      mMapping(settings.mapping) {
    if (!(settings.fineScale > 0.0 && settings.fineScale <= 1.0))
        throw std::invalid_argument("haptic tool: fineScale must be in (0, 1]");
    if (!(settings.mapping.scale > 0.0 && std::isfinite(settings.mapping.scale)))
        throw std::invalid_argument("haptic tool: the workspace scale must be positive");
    if (settings.planar) {
        if (std::abs(glm::length(settings.planarAxis) - 1.0) > 1e-6)
            throw std::invalid_argument("haptic tool: planarAxis must be a unit vector");
        if (!(settings.planarPress >= 0.0)) throw std::invalid_argument("haptic tool: planarPress must be >= 0");
    }
    const auto guard = mReader.acquire();
    mAccessor.emplace(guard);
}

bool EngineHapticClient::buttons(const DeviceState& filtered) noexcept {
    const uint32_t held = filtered.buttons;
    const uint32_t pressed = held & ~mPrevButtons;
    mPrevButtons = held;
    if (mSettings.clutchButton != 0 && (held & mSettings.clutchButton)) {
        mClutched = true;
        return true;
    }
    if (mClutched) {
        // Released: the device's new place is the tool's, so nothing jumps; the renderer's
        // proxy starts again there and its force ramps on.
        mClutched = false;
        if (mHasTool) mMapping.anchor(filtered.position, mTool);
        mRenderer.reset();
    }
    if (mSettings.fineButton != 0 && (pressed & mSettings.fineButton)) {
        // Scale about the device's own world point, so a device pressed into the clay keeps its
        // penetration and the force does not jump.
        const glm::dvec3 here = mMapping.toWorld(filtered.position);
        mFine = !mFine;
        mMapping.scale = mSettings.mapping.scale * (mFine ? mSettings.fineScale : 1.0);
        mMapping.anchor(filtered.position, here);
    }
    return false;
}

DeviceState EngineHapticClient::place(const DeviceState& filtered, adf::AdfAccessor& clay, double reach) const noexcept {
    DeviceState w = mMapping.toWorld(filtered);
    if (!mSettings.deviceOrientation) w.orientation = mSettings.toolOrientation;
    if (!mSettings.planar) return w;
    const glm::dvec3 a = mSettings.planarAxis;
    const glm::dvec3 from = w.position + a * reach, to = w.position - a * reach;
    const double t = mRenderer.contactFraction(clay, from, to);
    if (t < 1.0) w.position = from + (to - from) * t - a * mSettings.planarPress;
    w.velocity -= a * glm::dot(a, w.velocity);
    return w;
}

void EngineHapticClient::push(const DeviceState& world, uint32_t buttons, bool clutched) noexcept {
    engine::ToolSample s;
    s.timeNs = world.timeNs;
    s.posWorld = mTool;
    s.orientation = glm::quat(world.orientation);
    s.buttons = clutched ? buttons & ~uint32_t(engine::kButtonPrimary) : buttons;
    if (!mSamples.push(s)) ++mRefused;
    if (mTrace) {
        TraceRecord r;
        r.timeNs = world.timeNs;
        r.device = world.position;
        r.velocity = world.velocity;
        r.proxy = mTool;
        r.force = mLast.force;
        r.orientation = world.orientation;
        r.buttons = s.buttons;
        r.contact = mLast.contact;
        r.clutched = clutched;
        mTrace->push(r);
    }
}

void EngineHapticClient::tick(const DeviceState& state, double dt, glm::dvec3& force) noexcept {
    DeviceState filtered = state;
    mFilter.update(filtered, dt);
    const bool clutched = buttons(filtered);
    const auto guard = mReader.acquire();
    adf::AdfAccessor& clay = mAccessor->bound(guard);
    const DeviceState world = place(filtered, clay, guard.adf().domain().sizeWorld);
    if (clutched) {
        mLast = ProxyOutput{};
        mLast.proxy = mTool;
        force = glm::dvec3(0.0);
        if (mHasTool) push(world, state.buttons, true);
        return;
    }
    const bool carving = (state.buttons & engine::kButtonPrimary) != 0;
    mLast = mRenderer.update(world, clay, guard.sequence(), dt, carving);
    force = mMapping.forceToDevice(mLast.force);
    if (mLast.fault) return;  // an unusable device state: nothing to carve with either
    mTool = mLast.proxy;
    mHasTool = true;
    push(world, state.buttons, false);
}

void EngineHapticClient::restart(const DeviceState& /*state*/) noexcept {
    mRenderer.reset();
    mFilter.reset();
}

}  // namespace kizamu::haptics
