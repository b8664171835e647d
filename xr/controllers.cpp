// SPDX-License-Identifier: Apache-2.0
#include "xr/controllers.h"

#include "xr/xr_error.h"

#include <cstring>
#include <string>
#include <vector>

namespace kizamu::xr {

namespace {

struct ActionSpec {
    const char* name;
    const char* localized;
    XrActionType type;
};

constexpr std::array<ActionSpec, kControllerActionCount> kActionSpecs{{
    {"grip_pose", "Tool and grab pose", XR_ACTION_TYPE_POSE_INPUT},
    {"aim_pose", "Pointer", XR_ACTION_TYPE_POSE_INPUT},
    {"trigger", "Sculpt", XR_ACTION_TYPE_FLOAT_INPUT},
    {"squeeze", "Grab the clay", XR_ACTION_TYPE_FLOAT_INPUT},
    {"thumbstick", "Tool and size", XR_ACTION_TYPE_VECTOR2F_INPUT},
    {"primary", "Invert the tool", XR_ACTION_TYPE_BOOLEAN_INPUT},
    {"secondary", "Undo", XR_ACTION_TYPE_BOOLEAN_INPUT},
    {"vibrate", "Contact", XR_ACTION_TYPE_VIBRATION_OUTPUT},
}};

XrPath path(XrInstance instance, const std::string& s) {
    XrPath p = XR_NULL_PATH;
    check(instance, xrStringToPath(instance, s.c_str(), &p), ("xrStringToPath(" + s + ")").c_str());
    return p;
}

XrSpace actionSpace(XrInstance instance, XrSession session, XrAction action, XrPath hand) {
    XrActionSpaceCreateInfo info{XR_TYPE_ACTION_SPACE_CREATE_INFO};
    info.action = action;
    info.subactionPath = hand;
    info.poseInActionSpace = toXr(Pose{});
    XrSpace space = XR_NULL_HANDLE;
    check(instance, xrCreateActionSpace(session, &info, &space), "xrCreateActionSpace");
    return space;
}

bool locate(XrSpace space, XrSpace base, XrTime time, Pose& out) {
    XrSpaceLocation loc{XR_TYPE_SPACE_LOCATION};
    if (XR_FAILED(xrLocateSpace(space, base, time, &loc))) return false;
    constexpr XrSpaceLocationFlags kValid = XR_SPACE_LOCATION_POSITION_VALID_BIT | XR_SPACE_LOCATION_ORIENTATION_VALID_BIT;
    if ((loc.locationFlags & kValid) != kValid) return false;
    out = fromXr(loc.pose);
    return true;
}

}  // namespace

Controllers::Controllers(XrInstance instance, XrSession session) : mInstance(instance), mSession(session) {
    XrActionSetCreateInfo si{XR_TYPE_ACTION_SET_CREATE_INFO};
    std::strcpy(si.actionSetName, "sculpting");
    std::strcpy(si.localizedActionSetName, "Sculpting");
    check(instance, xrCreateActionSet(instance, &si, &mSet), "xrCreateActionSet");
    for (std::size_t h = 0; h < 2; ++h) mHandPaths[h] = path(instance, std::string(kHandPaths[h]));

    for (std::size_t a = 0; a < kActionSpecs.size(); ++a) {
        XrActionCreateInfo ai{XR_TYPE_ACTION_CREATE_INFO};
        std::strcpy(ai.actionName, kActionSpecs[a].name);
        std::strcpy(ai.localizedActionName, kActionSpecs[a].localized);
        ai.actionType = kActionSpecs[a].type;
        ai.countSubactionPaths = 2;
        ai.subactionPaths = mHandPaths.data();
        check(instance, xrCreateAction(mSet, &ai, &mActions[a]), "xrCreateAction");
    }

    for (const std::string_view profile : kProfiles) {
        std::vector<XrActionSuggestedBinding> bindings;
        for (std::size_t a = 0; a < kActionSpecs.size(); ++a) {
            for (std::size_t h = 0; h < 2; ++h) {
                const std::string_view component = boundComponent(profile, ControllerAction(a), Hand(h));
                if (!component.empty()) bindings.push_back({mActions[a], path(instance, std::string(kHandPaths[h]) + std::string(component))});
            }
        }
        XrInteractionProfileSuggestedBinding sb{XR_TYPE_INTERACTION_PROFILE_SUGGESTED_BINDING};
        sb.interactionProfile = path(instance, std::string(profile));
        sb.countSuggestedBindings = uint32_t(bindings.size());
        sb.suggestedBindings = bindings.data();
        check(instance, xrSuggestInteractionProfileBindings(instance, &sb), "xrSuggestInteractionProfileBindings");
    }

    for (std::size_t h = 0; h < 2; ++h) {
        mGripSpaces[h] = actionSpace(instance, session, mActions[std::size_t(ControllerAction::GripPose)], mHandPaths[h]);
        mAimSpaces[h] = actionSpace(instance, session, mActions[std::size_t(ControllerAction::AimPose)], mHandPaths[h]);
    }
    XrSessionActionSetsAttachInfo attach{XR_TYPE_SESSION_ACTION_SETS_ATTACH_INFO};
    attach.countActionSets = 1;
    attach.actionSets = &mSet;
    check(instance, xrAttachSessionActionSets(session, &attach), "xrAttachSessionActionSets");
}

Controllers::~Controllers() {
    for (std::size_t h = 0; h < 2; ++h) {
        if (mGripSpaces[h] != XR_NULL_HANDLE) xrDestroySpace(mGripSpaces[h]);
        if (mAimSpaces[h] != XR_NULL_HANDLE) xrDestroySpace(mAimSpaces[h]);
    }
    if (mSet != XR_NULL_HANDLE) xrDestroyActionSet(mSet);  // destroys its actions
}

ControllerFrame Controllers::read(XrSpace space, XrTime time) {
    XrActiveActionSet active{mSet, XR_NULL_PATH};
    XrActionsSyncInfo sync{XR_TYPE_ACTIONS_SYNC_INFO};
    sync.countActiveActionSets = 1;
    sync.activeActionSets = &active;
    ControllerFrame frame;
    frame.time = time;
    const XrResult synced = xrSyncActions(mSession, &sync);
    if (synced == XR_SESSION_NOT_FOCUSED) return frame;  // the runtime holds the input elsewhere
    check(mInstance, synced, "xrSyncActions");

    auto action = [&](ControllerAction a) { return mActions[std::size_t(a)]; };
    for (std::size_t h = 0; h < 2; ++h) {
        HandInput& in = frame.hands[h];
        XrActionStateGetInfo gi{XR_TYPE_ACTION_STATE_GET_INFO};
        gi.subactionPath = mHandPaths[h];
        gi.action = action(ControllerAction::GripPose);
        XrActionStatePose pose{XR_TYPE_ACTION_STATE_POSE};
        if (XR_SUCCEEDED(xrGetActionStatePose(mSession, &gi, &pose)) && pose.isActive)
            in.tracked = locate(mGripSpaces[h], space, time, in.grip);
        if (in.tracked && !locate(mAimSpaces[h], space, time, in.aim)) in.aim = in.grip;

        XrActionStateFloat f{XR_TYPE_ACTION_STATE_FLOAT};
        gi.action = action(ControllerAction::Trigger);
        if (XR_SUCCEEDED(xrGetActionStateFloat(mSession, &gi, &f)) && f.isActive) in.trigger = f.currentState;
        f = {XR_TYPE_ACTION_STATE_FLOAT};
        gi.action = action(ControllerAction::Squeeze);
        if (XR_SUCCEEDED(xrGetActionStateFloat(mSession, &gi, &f)) && f.isActive) in.squeeze = f.currentState;
        XrActionStateVector2f v{XR_TYPE_ACTION_STATE_VECTOR2F};
        gi.action = action(ControllerAction::Thumbstick);
        if (XR_SUCCEEDED(xrGetActionStateVector2f(mSession, &gi, &v)) && v.isActive) in.thumbstick = {v.currentState.x, v.currentState.y};
        XrActionStateBoolean b{XR_TYPE_ACTION_STATE_BOOLEAN};
        gi.action = action(ControllerAction::Primary);
        if (XR_SUCCEEDED(xrGetActionStateBoolean(mSession, &gi, &b)) && b.isActive) in.primary = b.currentState;
        b = {XR_TYPE_ACTION_STATE_BOOLEAN};
        gi.action = action(ControllerAction::Secondary);
        if (XR_SUCCEEDED(xrGetActionStateBoolean(mSession, &gi, &b)) && b.isActive) in.secondary = b.currentState;
    }
    return frame;
}

void Controllers::vibrate(Hand hand, float amplitude, XrDuration durationNs) {
    XrHapticActionInfo info{XR_TYPE_HAPTIC_ACTION_INFO};
    info.action = mActions[std::size_t(ControllerAction::Vibrate)];
    info.subactionPath = mHandPaths[std::size_t(hand)];
    XrHapticVibration v{XR_TYPE_HAPTIC_VIBRATION};
    v.amplitude = amplitude;
    v.duration = durationNs > 0 ? durationNs : XR_MIN_HAPTIC_DURATION;
    v.frequency = XR_FREQUENCY_UNSPECIFIED;
    check(mInstance, xrApplyHapticFeedback(mSession, &info, reinterpret_cast<const XrHapticBaseHeader*>(&v)), "xrApplyHapticFeedback");
}

void Controllers::stopVibration(Hand hand) {
    XrHapticActionInfo info{XR_TYPE_HAPTIC_ACTION_INFO};
    info.action = mActions[std::size_t(ControllerAction::Vibrate)];
    info.subactionPath = mHandPaths[std::size_t(hand)];
    check(mInstance, xrStopHapticFeedback(mSession, &info), "xrStopHapticFeedback");
}

std::string Controllers::currentProfile(Hand hand) const {
    XrInteractionProfileState state{XR_TYPE_INTERACTION_PROFILE_STATE};
    if (XR_FAILED(xrGetCurrentInteractionProfile(mSession, mHandPaths[std::size_t(hand)], &state)) ||
        state.interactionProfile == XR_NULL_PATH)
        return {};
    char buffer[XR_MAX_PATH_LENGTH] = {};
    uint32_t n = 0;
    if (XR_FAILED(xrPathToString(mInstance, state.interactionProfile, sizeof buffer, &n, buffer))) return {};
    return buffer;
}

}  // namespace kizamu::xr
