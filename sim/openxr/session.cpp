// SPDX-License-Identifier: Apache-2.0
/// @file session.cpp
/// @brief Sessions and their lifecycle, as the spec's state diagram: creation queues IDLE then
/// READY; xrBeginSession gives SYNCHRONIZED (VISIBLE and FOCUSED follow the first xrEndFrame,
/// frame.cpp); xrRequestExitSession (or the control API's stop) goes down to STOPPING;
/// xrEndSession gives IDLE then EXITING.
#include "sim/openxr/capture.h"
#include "sim/openxr/entry_points.h"
#include "sim/openxr/gl_objects.h"
#include "sim/openxr/runtime_state.h"

#include <algorithm>

namespace kizamu::xrsim {

void destroySession(Runtime& rt, XrSession handle) {
    SessionObject* s = rt.find<SessionObject>(handle);
    if (s == nullptr) return;
    if (InstanceObject* inst = rt.find<InstanceObject>(s->instance)) {
        inst->session = XR_NULL_HANDLE;
        std::erase_if(inst->events, [&](const XrEventDataBuffer& e) {
            return e.type == XR_TYPE_EVENT_DATA_SESSION_STATE_CHANGED &&
                   reinterpret_cast<const XrEventDataSessionStateChanged&>(e).session == handle;
        });
    }
    for (auto it = rt.objects.begin(); it != rt.objects.end();) {
        bool owned = false;
        if (const auto* sp = std::get_if<SpaceObject>(&it->second)) owned = sp->session == handle;
        if (auto* sc = std::get_if<SwapchainObject>(&it->second)) {
            owned = sc->session == handle;
            if (owned) deleteTextures(sc->textures);
        }
        it = owned ? rt.objects.erase(it) : std::next(it);
    }
    rt.erase(handle);
}

/// XR_ERROR_SYSTEM_INVALID for another system; XR_ERROR_GRAPHICS_DEVICE_INVALID without an
/// XrGraphicsBindingOpenGLXlibKHR in `next` (or without XR_KHR_opengl_enable);
/// XR_ERROR_GRAPHICS_REQUIREMENTS_CALL_MISSING before xrGetOpenGLGraphicsRequirementsKHR;
/// XR_ERROR_LIMIT_REACHED when the instance has an XrSession already. The binding's Display and
/// context are not used: swapchain images are made in whatever GL context is current.
XrResult xrCreateSession(XrInstance instance, const XrSessionCreateInfo* createInfo,
                         XrSession* session) {
    Runtime& rt = runtime();
    std::lock_guard lock(rt.mutex);
    InstanceObject* inst = rt.find<InstanceObject>(instance);
    if (inst == nullptr) return XR_ERROR_HANDLE_INVALID;
    if (createInfo->systemId != kSystemId) return XR_ERROR_SYSTEM_INVALID;
    if (!inst->extensions.count(kExtOpenGl) ||
        findInChain(createInfo->next, XR_TYPE_GRAPHICS_BINDING_OPENGL_XLIB_KHR) == nullptr)
        return XR_ERROR_GRAPHICS_DEVICE_INVALID;
    if (!inst->glRequirementsQueried) return XR_ERROR_GRAPHICS_REQUIREMENTS_CALL_MISSING;
    if (inst->session != XR_NULL_HANDLE) return XR_ERROR_LIMIT_REACHED;
    SessionObject s;
    s.instance = instance;
    const XrSession handle = rt.add<XrSession>(std::move(s));
    inst->session = handle;
    SessionObject& live = *rt.find<SessionObject>(handle);
    setSessionState(rt, handle, live, XR_SESSION_STATE_IDLE);
    setSessionState(rt, handle, live, XR_SESSION_STATE_READY);
    *session = handle;
    return XR_SUCCESS;
}

/// Writes the capture PNGs (when $KIZAMU_XRSIM_CAPTURE is set), then destroys the XrSession, its
/// spaces and swapchains. Works on a lost XrSession too.
XrResult xrDestroySession(XrSession session) {
    Runtime& rt = runtime();
    std::lock_guard lock(rt.mutex);
    if (rt.find<SessionObject>(session) == nullptr) return XR_ERROR_HANDLE_INVALID;
    captureViews(rt);
    destroySession(rt, session);
    return XR_SUCCESS;
}

/// XR_ERROR_SESSION_RUNNING when running; XR_ERROR_SESSION_NOT_READY when not READY;
/// XR_ERROR_VIEW_CONFIGURATION_TYPE_UNSUPPORTED for anything but PRIMARY_STEREO.
XrResult xrBeginSession(XrSession session, const XrSessionBeginInfo* beginInfo) {
    return onSession(session, [&](Runtime& rt, SessionObject& s) -> XrResult {
        if (beginInfo->primaryViewConfigurationType != XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO)
            return XR_ERROR_VIEW_CONFIGURATION_TYPE_UNSUPPORTED;
        if (s.running) return XR_ERROR_SESSION_RUNNING;
        if (s.state != XR_SESSION_STATE_READY) return XR_ERROR_SESSION_NOT_READY;
        s.running = true;
        setSessionState(rt, session, s, XR_SESSION_STATE_SYNCHRONIZED);
        return XR_SUCCESS;
    });
}

/// XR_ERROR_SESSION_NOT_RUNNING when not running; XR_ERROR_SESSION_NOT_STOPPING when not
/// STOPPING. Then IDLE, and EXITING (every stop here means the user or the application quits).
XrResult xrEndSession(XrSession session) {
    return onSession(session, [&](Runtime& rt, SessionObject& s) -> XrResult {
        if (!s.running) return XR_ERROR_SESSION_NOT_RUNNING;
        if (s.state != XR_SESSION_STATE_STOPPING) return XR_ERROR_SESSION_NOT_STOPPING;
        s.running = false;
        s.pendingWaits = 0;
        s.frameBegun = false;
        setSessionState(rt, session, s, XR_SESSION_STATE_IDLE);
        setSessionState(rt, session, s, XR_SESSION_STATE_EXITING);
        return XR_SUCCESS;
    });
}

/// XR_ERROR_SESSION_NOT_RUNNING when not running; else the XrSession goes down to STOPPING.
XrResult xrRequestExitSession(XrSession session) {
    return onSession(session, [&](Runtime& rt, SessionObject& s) -> XrResult {
        if (!s.running) return XR_ERROR_SESSION_NOT_RUNNING;
        stopSession(rt, session, s);
        return XR_SUCCESS;
    });
}

}  // namespace kizamu::xrsim
