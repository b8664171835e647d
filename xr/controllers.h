// SPDX-License-Identifier: Apache-2.0
/// @file controllers.h
/// @brief The two hand controllers through OpenXR actions: one action set with Kizamu's actions
/// (controller_bindings.h) for both hands, bindings suggested for every profile in kProfiles,
/// attached once; each frame synced and read into a ControllerFrame (poses in the session's
/// reference space at the frame's display time); vibration out.
///
/// Threading: the session's thread. Not copyable. Errors: setup throws XrFailure; reading a
/// frame reports an untracked or inactive hand as such, never throws for it.
#pragma once

#include "xr/controller_bindings.h"
#include "xr/pose.h"

#include <openxr/openxr.h>

#include <glm/vec2.hpp>

#include <array>
#include <string>

namespace kizamu::xr {

/// One hand's inputs this frame.
struct HandInput {
    bool tracked = false;  ///< the grip pose is valid (position and orientation)
    Pose grip, aim;        ///< reference space
    float trigger = 0.0f, squeeze = 0.0f;  ///< 0..1
    glm::vec2 thumbstick{0.0f};            ///< −1..1 each
    bool primary = false, secondary = false;
};

struct ControllerFrame {
    std::array<HandInput, 2> hands{};  ///< by Hand
    XrTime time = 0;                   ///< the display time they were located for (ns)
    const HandInput& operator[](Hand h) const { return hands[std::size_t(h)]; }
};

class Controllers {
public:
    /// Creates the action set, its actions and their spaces, suggests bindings for every
    /// profile in kProfiles and attaches the set to `session`. @throw XrFailure
    Controllers(XrInstance instance, XrSession session);
    ~Controllers();
    Controllers(const Controllers&) = delete;
    Controllers& operator=(const Controllers&) = delete;

    /// xrSyncActions, then every hand's inputs located in `space` at `time`. A session that is
    /// not focused reads as nothing held (the runtime says inactive). @throw XrFailure
    ControllerFrame read(XrSpace space, XrTime time);
    /// A pulse on `hand` of `amplitude` 0..1 for `durationNs` (0: the runtime's shortest).
    void vibrate(Hand hand, float amplitude, XrDuration durationNs);
    void stopVibration(Hand hand);
    /// The profile the runtime uses for `hand` now (empty before it chose one).
    std::string currentProfile(Hand hand) const;

private:
    XrInstance mInstance;
    XrSession mSession;
    XrActionSet mSet = XR_NULL_HANDLE;
    std::array<XrAction, kControllerActionCount> mActions{};
    std::array<XrPath, 2> mHandPaths{};
    std::array<XrSpace, 2> mGripSpaces{}, mAimSpaces{};
};

}  // namespace kizamu::xr
