// SPDX-License-Identifier: Apache-2.0
/// @file engine_client.h
/// @brief The servo thread's work on the live engine: feel the published clay, carve with the
/// proxy. A ServoClient (servo_loop.h) that joins the proxy renderer to the Engine.
///
/// Each tick: acquire the published snapshot (SnapshotStore::Reader, lock-free), run the proxy
/// renderer on it through a GuardedAccessor (its cache never outlives the snapshot), return the
/// force, and push the tool's pose to the engine's sample queue (wait-free, no allocation). The
/// pose pushed is the proxy's, not the device's: while the carve button is held the proxy
/// advances into the clay at the removal rate, so the engine carves where the proxy is and never
/// ahead of the hand (issue 32, "Carving with force"). Device frame = world frame for now (the
/// workspace mapping is still to come).
/// Threading: constructed on a cold path (it registers a Reader); tick() and restart() on the
/// servo thread only, which must be the sample queue's only producer.
#pragma once

#include "adf/guarded_accessor.h"
#include "adf/snapshot_store.h"
#include "engine/sample_queue.h"
#include "haptics/proxy_renderer.h"
#include "haptics/servo_loop.h"

#include <cstdint>
#include <optional>

namespace kizamu::haptics {

class EngineHapticClient final : public ServoClient {
public:
    /// All three must outlive the client. Cold path: registers a reader slot in `store`.
    /// @throw std::runtime_error when the store has no reader slot left
    EngineHapticClient(adf::SnapshotStore& store, engine::SampleQueue& samples, ProxyRenderer& renderer);

    void tick(const DeviceState& state, double dt, glm::dvec3& force) noexcept override;
    void restart(const DeviceState& state) noexcept override;

    /// The last tick's renderer output (the servo thread, or a lock-step test between ticks).
    const ProxyOutput& last() const noexcept { return mLast; }
    /// Samples the queue refused (its pending buffer full of button edges): the next accepted
    /// sample carries the buttons on.
    uint64_t refusedSamples() const noexcept { return mRefused; }

private:
    adf::SnapshotStore::Reader mReader;
    std::optional<adf::GuardedAccessor> mAccessor;  ///< engaged by the constructor: no allocation on the servo thread
    engine::SampleQueue& mSamples;
    ProxyRenderer& mRenderer;
    ProxyOutput mLast;
    uint64_t mRefused = 0;
};

}  // namespace kizamu::haptics
