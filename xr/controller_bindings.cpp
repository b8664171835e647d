// SPDX-License-Identifier: Apache-2.0
#include "xr/controller_bindings.h"

namespace kizamu::xr {

std::string_view boundComponent(std::string_view profile, ControllerAction action, Hand hand) {
    const bool left = hand == Hand::Left;
    const bool simple = profile == kProfiles[0], touch = profile == kProfiles[1], index = profile == kProfiles[2];
    if (!simple && !touch && !index) return {};
    switch (action) {
    case ControllerAction::GripPose: return "/input/grip/pose";
    case ControllerAction::AimPose: return "/input/aim/pose";
    case ControllerAction::Trigger: return simple ? "/input/select/click" : "/input/trigger/value";
    case ControllerAction::Squeeze: return simple ? "" : "/input/squeeze/value";
    case ControllerAction::Thumbstick: return simple ? "" : "/input/thumbstick";
    case ControllerAction::Primary:
        if (simple) return {};
        return touch && left ? "/input/x/click" : "/input/a/click";
    case ControllerAction::Secondary:
        if (simple) return "/input/menu/click";
        return touch && left ? "/input/y/click" : "/input/b/click";
    case ControllerAction::Vibrate: return "/output/haptic";
    }
    return {};
}

}  // namespace kizamu::xr
