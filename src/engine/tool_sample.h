// SPDX-License-Identifier: Apache-2.0
/// @file tool_sample.h
/// @brief One reading of a tool from a producer (the stylus's servo thread, a headset
/// controller, the mouse): time stamp, pose, strength, buttons.
///
/// Where it sits: the first thing the live engine takes in (design brief, "The live pipeline").
/// Each producer pushes its samples through its own SampleQueue (sample_queue.h); the edit
/// thread drains them and turns the runs with a button held into strokes. A plain value,
/// copied by every thread that touches it. Units SI (m), except the time stamp (ns).
#pragma once

#include <glm/gtc/quaternion.hpp>
#include <glm/vec3.hpp>

#include <cstdint>
#include <type_traits>

namespace kizamu::engine {

/// Button bits of ToolSample::buttons. A producer with fewer buttons leaves the others 0.
enum ToolButton : uint32_t {
    kButtonPrimary = 1u << 0,  ///< carve / add while held: one stroke per press
    kButtonSecondary = 1u << 1,
    kButtonTertiary = 1u << 2,
};

/// A tool pose at one instant, as its producer read it. 56 bytes, trivially copyable.
///
/// The time stamp is integer nanoseconds on the producer's monotonic clock
/// (std::chrono::steady_clock's epoch in the app, a virtual clock in sim/ and tests): exact,
/// so two samples never compare equal by rounding, differences are exact over sessions of
/// any length, and it is the clock's own representation. Within one queue time stamps do not
/// decrease. The orientation is single precision: 1e-7 rad is far below any device's noise
/// (about 1e-3 rad), and it keeps a sample within a cache line (56 bytes).
struct ToolSample {
    int64_t timeNs = 0;                             ///< ns, producer's monotonic clock
    glm::dvec3 posWorld{0.0};                       ///< m, world: the tool's reference point
    glm::quat orientation{1.0f, 0.0f, 0.0f, 0.0f};  ///< tool frame to world, unit
    float strength = 1.0f;                          ///< pressure or strength, 0..1
    uint32_t buttons = 0;                           ///< ToolButton bits held at `timeNs`
};

static_assert(std::is_trivially_copyable_v<ToolSample>);
static_assert(sizeof(ToolSample) <= 64, "a sample should fit one cache line");

}  // namespace kizamu::engine
