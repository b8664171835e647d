// SPDX-License-Identifier: Apache-2.0
/// @file spaces.cpp
/// @brief Reference spaces (VIEW, LOCAL, STAGE), action spaces, xrLocateSpace and xrLocateViews.
///
/// LOCAL and STAGE coincide (the origin, Y up); VIEW is the head pose (kizamuXrSimSetHeadPose,
/// at the origin looking down -Z by default); the eyes sit kEyeOffset either side of the head
/// on its X axis with a symmetric ±45° field of view. Nothing moves unless told, so a location
/// is the same at every time.
#include "sim/openxr/actions.h"
#include "sim/openxr/entry_points.h"
#include "sim/openxr/pose_math.h"
#include "sim/openxr/runtime_state.h"

#include <algorithm>
#include <iterator>

namespace kizamu::xrsim {
namespace {

const XrReferenceSpaceType kReferenceSpaces[] = {
    XR_REFERENCE_SPACE_TYPE_VIEW, XR_REFERENCE_SPACE_TYPE_LOCAL, XR_REFERENCE_SPACE_TYPE_STAGE};

/// The pose of a space in LOCAL; false when it cannot be located (an inactive action).
bool spacePose(Runtime& rt, const SessionObject& s, const SpaceObject& space, XrPosef* out) {
    if (space.action != XR_NULL_HANDLE) return actionSpacePose(rt, s, space, out);
    const XrPosef base =
        space.referenceType == XR_REFERENCE_SPACE_TYPE_VIEW ? rt.headPose : identityPose();
    *out = compose(base, space.offset);
    return true;
}

}  // namespace

XrResult xrEnumerateReferenceSpaces(XrSession session, uint32_t spaceCapacityInput,
                                    uint32_t* spaceCountOutput, XrReferenceSpaceType* spaces) {
    return onSession(session, [&](Runtime&, SessionObject&) -> XrResult {
        return twoCall(spaceCapacityInput, spaceCountOutput,
                       static_cast<uint32_t>(std::size(kReferenceSpaces)),
                       [&](uint32_t i) { spaces[i] = kReferenceSpaces[i]; });
    });
}

/// XR_ERROR_REFERENCE_SPACE_UNSUPPORTED for another type; XR_ERROR_POSE_INVALID for an
/// orientation that is not a unit quaternion.
XrResult xrCreateReferenceSpace(XrSession session, const XrReferenceSpaceCreateInfo* createInfo,
                                XrSpace* space) {
    return onSession(session, [&](Runtime& rt, SessionObject&) -> XrResult {
        if (std::find(std::begin(kReferenceSpaces), std::end(kReferenceSpaces),
                      createInfo->referenceSpaceType) == std::end(kReferenceSpaces))
            return XR_ERROR_REFERENCE_SPACE_UNSUPPORTED;
        if (!isValidPose(createInfo->poseInReferenceSpace)) return XR_ERROR_POSE_INVALID;
        SpaceObject sp;
        sp.session = session;
        sp.referenceType = createInfo->referenceSpaceType;
        sp.offset = createInfo->poseInReferenceSpace;
        *space = rt.add<XrSpace>(std::move(sp));
        return XR_SUCCESS;
    });
}

/// STAGE is 2 m x 2 m; the others have no bounds (XR_SPACE_BOUNDS_UNAVAILABLE, zero extent).
XrResult xrGetReferenceSpaceBoundsRect(XrSession session, XrReferenceSpaceType referenceSpaceType,
                                       XrExtent2Df* bounds) {
    return onSession(session, [&](Runtime&, SessionObject&) -> XrResult {
        if (std::find(std::begin(kReferenceSpaces), std::end(kReferenceSpaces),
                      referenceSpaceType) == std::end(kReferenceSpaces))
            return XR_ERROR_REFERENCE_SPACE_UNSUPPORTED;
        if (referenceSpaceType == XR_REFERENCE_SPACE_TYPE_STAGE) {
            *bounds = XrExtent2Df{2.0f, 2.0f};
            return XR_SUCCESS;
        }
        *bounds = XrExtent2Df{0.0f, 0.0f};
        return XR_SPACE_BOUNDS_UNAVAILABLE;
    });
}

/// XR_ERROR_ACTION_TYPE_MISMATCH for an action that is not a pose; XR_ERROR_PATH_INVALID /
/// UNSUPPORTED for a subaction path the action lacks; XR_ERROR_POSE_INVALID as above.
XrResult xrCreateActionSpace(XrSession session, const XrActionSpaceCreateInfo* createInfo,
                             XrSpace* space) {
    return onSession(session, [&](Runtime& rt, SessionObject&) -> XrResult {
        const ActionObject* a = rt.find<ActionObject>(createInfo->action);
        if (a == nullptr) return XR_ERROR_HANDLE_INVALID;
        if (a->type != XR_ACTION_TYPE_POSE_INPUT) return XR_ERROR_ACTION_TYPE_MISMATCH;
        if (const XrResult r = checkSubactionPath(rt, *a, createInfo->subactionPath);
            r != XR_SUCCESS)
            return r;
        if (!isValidPose(createInfo->poseInActionSpace)) return XR_ERROR_POSE_INVALID;
        SpaceObject sp;
        sp.session = session;
        sp.action = createInfo->action;
        sp.subactionPath = createInfo->subactionPath;
        sp.offset = createInfo->poseInActionSpace;
        *space = rt.add<XrSpace>(std::move(sp));
        return XR_SUCCESS;
    });
}

/// `space` in `baseSpace`, valid and tracked, or flags 0 when either cannot be located;
/// XR_ERROR_TIME_INVALID for a time <= 0; XR_ERROR_VALIDATION_FAILURE for spaces of two
/// sessions. Fills an XrSpaceVelocity in `next` with zero velocities.
XrResult xrLocateSpace(XrSpace space, XrSpace baseSpace, XrTime time, XrSpaceLocation* location) {
    Runtime& rt = runtime();
    std::lock_guard lock(rt.mutex);
    SpaceObject *sp = nullptr, *base = nullptr;
    SessionObject *s = nullptr, *baseSession = nullptr;
    if (const XrResult r = findSessionChild(rt, space, &sp, &s); r != XR_SUCCESS) return r;
    if (const XrResult r = findSessionChild(rt, baseSpace, &base, &baseSession); r != XR_SUCCESS)
        return r;
    if (sp->session != base->session) return XR_ERROR_VALIDATION_FAILURE;
    if (time <= 0) return XR_ERROR_TIME_INVALID;
    XrPosef spaceLocal{}, baseLocal{};
    const bool located =
        spacePose(rt, *s, *sp, &spaceLocal) && spacePose(rt, *s, *base, &baseLocal);
    location->locationFlags = 0;
    location->pose = identityPose();
    if (located) {
        location->pose = compose(inverse(baseLocal), spaceLocal);
        location->locationFlags =
            XR_SPACE_LOCATION_ORIENTATION_VALID_BIT | XR_SPACE_LOCATION_POSITION_VALID_BIT |
            XR_SPACE_LOCATION_ORIENTATION_TRACKED_BIT | XR_SPACE_LOCATION_POSITION_TRACKED_BIT;
    }
    for (auto* n = static_cast<XrBaseOutStructure*>(location->next); n != nullptr; n = n->next) {
        if (n->type != XR_TYPE_SPACE_VELOCITY) continue;
        auto* v = reinterpret_cast<XrSpaceVelocity*>(n);
        v->linearVelocity = {0.0f, 0.0f, 0.0f};
        v->angularVelocity = {0.0f, 0.0f, 0.0f};
        v->velocityFlags =
            located ? XR_SPACE_VELOCITY_LINEAR_VALID_BIT | XR_SPACE_VELOCITY_ANGULAR_VALID_BIT : 0;
    }
    return XR_SUCCESS;
}

XrResult xrDestroySpace(XrSpace space) {
    return destroyObject<SpaceObject>(space);
}

/// Two views, left then right; XR_ERROR_VIEW_CONFIGURATION_TYPE_UNSUPPORTED for anything but
/// PRIMARY_STEREO; XR_ERROR_TIME_INVALID for a time <= 0.
XrResult xrLocateViews(XrSession session, const XrViewLocateInfo* viewLocateInfo,
                       XrViewState* viewState, uint32_t viewCapacityInput,
                       uint32_t* viewCountOutput, XrView* views) {
    return onSession(session, [&](Runtime& rt, SessionObject& s) -> XrResult {
        if (viewLocateInfo->viewConfigurationType != XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO)
            return XR_ERROR_VIEW_CONFIGURATION_TYPE_UNSUPPORTED;
        if (viewLocateInfo->displayTime <= 0) return XR_ERROR_TIME_INVALID;
        SpaceObject* sp = rt.find<SpaceObject>(viewLocateInfo->space);
        if (sp == nullptr || sp->session != session) return XR_ERROR_HANDLE_INVALID;
        XrPosef spaceLocal{};
        const bool located = spacePose(rt, s, *sp, &spaceLocal);
        viewState->viewStateFlags =
            located ? XR_VIEW_STATE_ORIENTATION_VALID_BIT | XR_VIEW_STATE_POSITION_VALID_BIT |
                          XR_VIEW_STATE_ORIENTATION_TRACKED_BIT | XR_VIEW_STATE_POSITION_TRACKED_BIT
                    : 0;
        return twoCall(viewCapacityInput, viewCountOutput, 2, [&](uint32_t i) {
            const XrPosef eyeInHead{{0.0f, 0.0f, 0.0f, 1.0f},
                                    {i == 0 ? -kEyeOffset : kEyeOffset, 0.0f, 0.0f}};
            views[i].pose = located ? compose(inverse(spaceLocal), compose(rt.headPose, eyeInHead))
                                    : identityPose();
            views[i].fov = XrFovf{-kFovHalfAngle, kFovHalfAngle, kFovHalfAngle, -kFovHalfAngle};
        });
    });
}

}  // namespace kizamu::xrsim
