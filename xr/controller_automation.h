// SPDX-License-Identifier: Apache-2.0
/// @file controller_automation.h
/// @brief Plays an input script's controller events into the OpenXR runtime through
/// XR_EXT_conformance_automation, so a script drives the headset's controllers the way a hand
/// would: the application then reads them back through its actions, the same path as real input.
///
/// Each input is set on the path Kizamu's action is bound to in the hand's current interaction
/// profile (controller_bindings.h). Threading: the session's thread. Errors: XrFailure.
#pragma once

#include "interact/input_script.h"
#include "xr/controller_bindings.h"
#include "xr/pose.h"

#include <openxr/openxr.h>

#include <array>
#include <string>

namespace kizamu::xr {

class ControllerAutomation {
public:
    /// Scripted positions are in `space` (the session's reference space). Precondition: the
    /// instance was created with XR_EXT_conformance_automation.
    /// @throw XrFailure when the runtime lacks its functions
    ControllerAutomation(XrInstance instance, XrSession session, XrSpace space);

    /// Sets what `input` names on its hand; `profile` is the hand's current interaction profile
    /// (Controllers::currentProfile; empty before the runtime chose one: nothing but the pose
    /// and activity can be set then). @throw XrFailure
    void apply(const interact::ControllerInput& input, const std::string& profile);

private:
    XrPath path(const std::string& s) const;
    XrInstance mInstance;
    XrSession mSession;
    std::array<XrPath, 2> mHands{};
    PFN_xrSetInputDeviceActiveEXT mActive = nullptr;
    PFN_xrSetInputDeviceStateBoolEXT mBool = nullptr;
    PFN_xrSetInputDeviceStateFloatEXT mFloat = nullptr;
    PFN_xrSetInputDeviceStateVector2fEXT mVector = nullptr;
    PFN_xrSetInputDeviceLocationEXT mLocation = nullptr;
    XrSpace mSpace;
    std::array<Pose, 2> mPoses{};  ///< each hand's last scripted pose (a script may set half of one)
};

}  // namespace kizamu::xr
