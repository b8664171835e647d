// SPDX-License-Identifier: Apache-2.0
/// @file controller_bindings.h
/// @brief What each of Kizamu's controller actions is bound to in each interaction profile it
/// suggests (the Khronos simple controller, Oculus Touch, Valve Index): one table, read by the
/// action setup (controllers.h) and by the scripted input that drives a simulated runtime
/// (controller_automation.h), so both always name the same inputs.
/// Pure data; any thread.
#pragma once

#include <array>
#include <string_view>

namespace kizamu::xr {

enum class Hand { Left = 0, Right = 1 };
inline constexpr std::array<std::string_view, 2> kHandPaths{"/user/hand/left", "/user/hand/right"};

/// Kizamu's actions, one per input it reads (and the vibration output).
enum class ControllerAction {
    GripPose,    ///< the hand's grip: the tool's pose (dominant hand), the grab's (other hand)
    AimPose,     ///< the pointing ray: the panel's pointer
    Trigger,     ///< 0..1: carve or add with it as strength; click on the panel
    Squeeze,     ///< 0..1: grab the clay
    Thumbstick,  ///< x flicks through tools, y grows and shrinks the tool
    Primary,     ///< A / X: inverts the tool (carve ↔ add)
    Secondary,   ///< B / Y / menu: a click undoes the last stroke
    Vibrate,     ///< the haptic output
};
inline constexpr int kControllerActionCount = 8;

/// The interaction profiles Kizamu suggests bindings for.
inline constexpr std::array<std::string_view, 3> kProfiles{
    "/interaction_profiles/khr/simple_controller",
    "/interaction_profiles/oculus/touch_controller",
    "/interaction_profiles/valve/index_controller",
};

/// The input (or output) path below the hand's path ("/input/trigger/value") that `action` is
/// bound to in `profile` for `hand`; empty where that profile has no such input (the simple
/// controller has no squeeze or thumbstick) or the profile is not one of kProfiles.
std::string_view boundComponent(std::string_view profile, ControllerAction action, Hand hand);

}  // namespace kizamu::xr
