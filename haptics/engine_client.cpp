// SPDX-License-Identifier: Apache-2.0
/// @file engine_client.cpp
/// @brief EngineHapticClient: one guard, one renderer update and one push per servo tick.
#include "haptics/engine_client.h"

#include "engine/tool_sample.h"

namespace kizamu::haptics {

EngineHapticClient::EngineHapticClient(adf::SnapshotStore& store, engine::SampleQueue& samples, ProxyRenderer& renderer)
    : mReader(store), mSamples(samples), mRenderer(renderer) {
    const auto guard = mReader.acquire();
    mAccessor.emplace(guard);
}

void EngineHapticClient::tick(const DeviceState& state, double dt, glm::dvec3& force) noexcept {
    const bool carving = (state.buttons & engine::kButtonPrimary) != 0;
    {
        const auto guard = mReader.acquire();
        mLast = mRenderer.update(state, *mAccessor, guard, dt, carving);
    }
    force = mLast.force;
    if (mLast.fault) return;  // an unusable device state: nothing to carve with either
    engine::ToolSample s;
    s.timeNs = state.timeNs;
    s.posWorld = mLast.proxy;
    s.orientation = glm::quat(state.orientation);
    s.buttons = state.buttons;
    if (!mSamples.push(s)) ++mRefused;
}

void EngineHapticClient::restart(const DeviceState& /*state*/) noexcept { mRenderer.reset(); }

}  // namespace kizamu::haptics
