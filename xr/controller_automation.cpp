// SPDX-License-Identifier: Apache-2.0
#include "xr/controller_automation.h"

#include "xr/xr_error.h"

namespace kizamu::xr {

namespace {

template <typename F>
F function(XrInstance instance, const char* name) {
    F f = nullptr;
    check(instance, xrGetInstanceProcAddr(instance, name, reinterpret_cast<PFN_xrVoidFunction*>(&f)), name);
    return f;
}

}  // namespace

ControllerAutomation::ControllerAutomation(XrInstance instance, XrSession session, XrSpace space)
    : mInstance(instance), mSession(session), mSpace(space) {
    mActive = function<PFN_xrSetInputDeviceActiveEXT>(instance, "xrSetInputDeviceActiveEXT");
    mBool = function<PFN_xrSetInputDeviceStateBoolEXT>(instance, "xrSetInputDeviceStateBoolEXT");
    mFloat = function<PFN_xrSetInputDeviceStateFloatEXT>(instance, "xrSetInputDeviceStateFloatEXT");
    mVector = function<PFN_xrSetInputDeviceStateVector2fEXT>(instance, "xrSetInputDeviceStateVector2fEXT");
    mLocation = function<PFN_xrSetInputDeviceLocationEXT>(instance, "xrSetInputDeviceLocationEXT");
    for (std::size_t h = 0; h < 2; ++h) mHands[h] = path(std::string(kHandPaths[h]));
}

XrPath ControllerAutomation::path(const std::string& s) const {
    XrPath p = XR_NULL_PATH;
    check(mInstance, xrStringToPath(mInstance, s.c_str(), &p), "xrStringToPath");
    return p;
}

void ControllerAutomation::apply(const interact::ControllerInput& input, const std::string& profile) {
    const Hand hand = input.hand == 0 ? Hand::Left : Hand::Right;
    const XrPath top = mHands[std::size_t(input.hand)];
    const std::string handPath(kHandPaths[std::size_t(input.hand)]);
    auto source = [&](ControllerAction a) -> XrPath {
        const std::string_view c = boundComponent(profile, a, hand);
        return c.empty() ? XR_NULL_PATH : path(handPath + std::string(c));
    };
    if (input.active && !profile.empty())
        check(mInstance, mActive(mSession, path(profile), top, *input.active ? XR_TRUE : XR_FALSE), "xrSetInputDeviceActiveEXT");
    Pose& pose = mPoses[std::size_t(input.hand)];
    if (input.position || input.orientation) {
        if (input.position) pose.position = *input.position;
        if (input.orientation) pose.orientation = *input.orientation;
        const XrPath grip = source(ControllerAction::GripPose), aim = source(ControllerAction::AimPose);
        const XrPath gripPath = grip != XR_NULL_PATH ? grip : path(handPath + "/input/grip/pose");
        const XrPath aimPath = aim != XR_NULL_PATH ? aim : path(handPath + "/input/aim/pose");
        for (const XrPath p : {gripPath, aimPath})
            check(mInstance, mLocation(mSession, top, p, mSpace, toXr(pose)), "xrSetInputDeviceLocationEXT");
    }
    auto setFloat = [&](ControllerAction a, float v) {
        if (const XrPath p = source(a); p != XR_NULL_PATH) {
            // The simple controller's select is a click: a float action reads it as 0 or 1.
            const XrResult r = boundComponent(profile, a, hand).ends_with("/click") ? mBool(mSession, top, p, v > 0.5f ? XR_TRUE : XR_FALSE)
                                                                                   : mFloat(mSession, top, p, v);
            check(mInstance, r, "xrSetInputDeviceState");
        }
    };
    if (input.trigger) setFloat(ControllerAction::Trigger, *input.trigger);
    if (input.squeeze) setFloat(ControllerAction::Squeeze, *input.squeeze);
    if (input.thumbstick)
        if (const XrPath p = source(ControllerAction::Thumbstick); p != XR_NULL_PATH)
            check(mInstance, mVector(mSession, top, p, {input.thumbstick->x, input.thumbstick->y}), "xrSetInputDeviceStateVector2fEXT");
    auto setBool = [&](ControllerAction a, bool v) {
        if (const XrPath p = source(a); p != XR_NULL_PATH)
            check(mInstance, mBool(mSession, top, p, v ? XR_TRUE : XR_FALSE), "xrSetInputDeviceStateBoolEXT");
    };
    if (input.primary) setBool(ControllerAction::Primary, *input.primary);
    if (input.secondary) setBool(ControllerAction::Secondary, *input.secondary);
}

}  // namespace kizamu::xr
