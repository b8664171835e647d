// SPDX-License-Identifier: Apache-2.0
/// @file automation.cpp
/// @brief XR_EXT_conformance_automation: the state of the simulated controllers, addressed by
/// top-level path (/user/hand/left, /user/hand/right) and input source path.
///
/// Controllers start active, at the LOCAL origin, with nothing pressed. A source path without a
/// component is stored under the component the call's type implies (bool: click, float: value,
/// location: pose); a 2D vector is stored as its /x and /y components. Actions read the state at
/// their next xrSyncActions.
#include "sim/openxr/entry_points.h"
#include "sim/openxr/interaction_profiles.h"
#include "sim/openxr/pose_math.h"
#include "sim/openxr/runtime_state.h"

namespace kizamu::xrsim {
namespace {

/// Whether the last component of `path` names an input component.
bool hasComponent(const std::string& path) {
    const std::string leaf = path.substr(path.rfind('/') + 1);
    for (const char* c : {"click", "touch", "value", "force", "x", "y", "pose"})
        if (leaf == c) return true;
    return false;
}

/// One xrSetInputDeviceState* / Location call: checks the session, the top-level path (a hand)
/// and that the source lies under it, appends `component` to a source path that has none, then
/// lets `store(rt, session, source)` write the state and give the result.
template <class Store>
XrResult setSourceState(XrSession session, XrPath topPath, XrPath inputSourcePath,
                        const char* component, Store store) {
    return onSession(session, [&](Runtime& rt, SessionObject& s) -> XrResult {
        const std::string* top = pathString(rt, topPath);
        const std::string* src = pathString(rt, inputSourcePath);
        if (top == nullptr || src == nullptr) return XR_ERROR_PATH_INVALID;
        if ((*top != kHandLeft && *top != kHandRight) || topLevelPath(*src) != *top ||
            src->size() == top->size())
            return XR_ERROR_PATH_UNSUPPORTED;
        std::string source = *src;
        if (component != nullptr && !hasComponent(source)) source += std::string("/") + component;
        return store(rt, s, source);
    });
}

}  // namespace

/// XR_ERROR_PATH_UNSUPPORTED for a top-level path that is not a hand or an unknown profile.
XrResult xrSetInputDeviceActiveEXT(XrSession session, XrPath interactionProfile,
                                   XrPath topLevelPath, XrBool32 isActive) {
    return onSession(session, [&](Runtime& rt, SessionObject& s) -> XrResult {
        const std::string* profile = pathString(rt, interactionProfile);
        const std::string* top = pathString(rt, topLevelPath);
        if (profile == nullptr || top == nullptr) return XR_ERROR_PATH_INVALID;
        if (!isKnownProfile(*profile) || (*top != kHandLeft && *top != kHandRight))
            return XR_ERROR_PATH_UNSUPPORTED;
        s.inactive[*top] = isActive == XR_FALSE;
        return XR_SUCCESS;
    });
}

XrResult xrSetInputDeviceStateBoolEXT(XrSession session, XrPath topLevelPath,
                                      XrPath inputSourcePath, XrBool32 state) {
    return setSourceState(session, topLevelPath, inputSourcePath, "click",
                          [&](Runtime&, SessionObject& s, const std::string& src) {
                              s.inputs[src] = state != XR_FALSE ? 1.0f : 0.0f;
                              return XR_SUCCESS;
                          });
}

XrResult xrSetInputDeviceStateFloatEXT(XrSession session, XrPath topLevelPath,
                                       XrPath inputSourcePath, float state) {
    return setSourceState(session, topLevelPath, inputSourcePath, "value",
                          [&](Runtime&, SessionObject& s, const std::string& src) {
                              s.inputs[src] = state;
                              return XR_SUCCESS;
                          });
}

XrResult xrSetInputDeviceStateVector2fEXT(XrSession session, XrPath topLevelPath,
                                          XrPath inputSourcePath, XrVector2f state) {
    return setSourceState(session, topLevelPath, inputSourcePath, nullptr,
                          [&](Runtime&, SessionObject& s, const std::string& src) {
                              s.inputs[src + "/x"] = state.x;
                              s.inputs[src + "/y"] = state.y;
                              return XR_SUCCESS;
                          });
}

/// `pose` is relative to `space` (located now); XR_ERROR_HANDLE_INVALID for a space of another
/// session or an action space; XR_ERROR_POSE_INVALID for a non-unit orientation.
XrResult xrSetInputDeviceLocationEXT(XrSession session, XrPath topLevelPath, XrPath inputSourcePath,
                                     XrSpace space, XrPosef pose) {
    return setSourceState(
        session, topLevelPath, inputSourcePath, "pose",
        [&](Runtime& rt, SessionObject& s, const std::string& src) {
            const SpaceObject* sp = rt.find<SpaceObject>(space);
            if (sp == nullptr || sp->session != session || sp->action != XR_NULL_HANDLE)
                return XR_ERROR_HANDLE_INVALID;
            if (!isValidPose(pose)) return XR_ERROR_POSE_INVALID;
            const XrPosef base =
                sp->referenceType == XR_REFERENCE_SPACE_TYPE_VIEW ? rt.headPose : identityPose();
            s.poses[src] = compose(compose(base, sp->offset), pose);
            return XR_SUCCESS;
        });
}

}  // namespace kizamu::xrsim
