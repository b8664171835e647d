// SPDX-License-Identifier: Apache-2.0
/// @file xrsim_fixture.h
/// @brief The fixture of the simulated runtime's tests: an off-screen GL context current on the
/// test thread, the real OpenXR loader pointed at the runtime's manifest, and helpers that walk
/// an application through instance, session, frames and swapchains.
///
/// Every call goes through the loader (libopenxr_loader) to libkizamu_xrsim.so, which the test
/// also links, so the control API (xrsim_control.h) reads the same runtime.
#pragma once

#include <gtest/gtest.h>

// openxr_platform.h's Xlib binding needs the X11 and GLX types first (after gtest: Xlib's
// macros must not reach gtest's headers).
#include <epoxy/gl.h>
#include <epoxy/glx.h>
#define XR_USE_PLATFORM_XLIB
#define XR_USE_GRAPHICS_API_OPENGL
#include <openxr/openxr.h>
#include <openxr/openxr_platform.h>

#include "render/gl_context.h"
#include "sim/openxr/xrsim_control.h"

#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

namespace kizamu::xrsim::test {

/// Asserts an XrResult with its name.
#define KIZAMU_EXPECT_XR(expected, call) EXPECT_EQ(XrResult(expected), XrResult(call)) << #call
#define KIZAMU_ASSERT_XR(expected, call) ASSERT_EQ(XrResult(expected), XrResult(call)) << #call

class XrSimTest : public ::testing::Test {
protected:
    void SetUp() override {
        setenv("XR_RUNTIME_JSON", KIZAMU_XRSIM_MANIFEST, 1);
        setenv("LP_NUM_THREADS", "2", 0);
        mGl = render::GlContext::createOffscreen();
        kizamuXrSimReset();
    }

    void TearDown() override {
        if (instance != XR_NULL_HANDLE) xrDestroyInstance(instance);
    }

    /// Creates the instance with both extensions (and `layers`), gets the system and the
    /// extension functions.
    void createInstance(const std::vector<const char*>& layers = {}) {
        const char* extensions[] = {"XR_KHR_opengl_enable", "XR_EXT_conformance_automation"};
        XrInstanceCreateInfo ci{XR_TYPE_INSTANCE_CREATE_INFO};
        std::snprintf(ci.applicationInfo.applicationName, XR_MAX_APPLICATION_NAME_SIZE,
                      "xrsim test");
        ci.applicationInfo.apiVersion = XR_MAKE_VERSION(1, 0, 0);
        ci.enabledExtensionCount = 2;
        ci.enabledExtensionNames = extensions;
        ci.enabledApiLayerCount = static_cast<uint32_t>(layers.size());
        ci.enabledApiLayerNames = layers.data();
        KIZAMU_ASSERT_XR(XR_SUCCESS, xrCreateInstance(&ci, &instance));
        XrSystemGetInfo gi{XR_TYPE_SYSTEM_GET_INFO};
        gi.formFactor = XR_FORM_FACTOR_HEAD_MOUNTED_DISPLAY;
        KIZAMU_ASSERT_XR(XR_SUCCESS, xrGetSystem(instance, &gi, &system));
        load("xrGetOpenGLGraphicsRequirementsKHR", glRequirements);
        load("xrSetInputDeviceActiveEXT", setActive);
        load("xrSetInputDeviceStateBoolEXT", setBool);
        load("xrSetInputDeviceStateFloatEXT", setFloat);
        load("xrSetInputDeviceStateVector2fEXT", setVector2f);
        load("xrSetInputDeviceLocationEXT", setLocation);
    }

    /// Queries the GL requirements and creates the session (binding with null Display and
    /// context: the runtime uses the current context), plus a LOCAL space.
    void createSession() {
        XrGraphicsRequirementsOpenGLKHR req{XR_TYPE_GRAPHICS_REQUIREMENTS_OPENGL_KHR};
        KIZAMU_ASSERT_XR(XR_SUCCESS, glRequirements(instance, system, &req));
        XrSessionCreateInfo ci{XR_TYPE_SESSION_CREATE_INFO};
        ci.next = &binding;
        ci.systemId = system;
        KIZAMU_ASSERT_XR(XR_SUCCESS, xrCreateSession(instance, &ci, &session));
        XrReferenceSpaceCreateInfo si{XR_TYPE_REFERENCE_SPACE_CREATE_INFO};
        si.referenceSpaceType = XR_REFERENCE_SPACE_TYPE_LOCAL;
        si.poseInReferenceSpace.orientation.w = 1.0f;
        KIZAMU_ASSERT_XR(XR_SUCCESS, xrCreateReferenceSpace(session, &si, &local));
    }

    /// The session states queued since the last call, in order (other events are dropped).
    std::vector<XrSessionState> pollStates() {
        std::vector<XrSessionState> states;
        XrEventDataBuffer e{XR_TYPE_EVENT_DATA_BUFFER};
        while (xrPollEvent(instance, &e) == XR_SUCCESS) {
            if (e.type == XR_TYPE_EVENT_DATA_SESSION_STATE_CHANGED)
                states.push_back(reinterpret_cast<XrEventDataSessionStateChanged&>(e).state);
            e = XrEventDataBuffer{XR_TYPE_EVENT_DATA_BUFFER};
        }
        return states;
    }

    XrResult beginSession() {
        XrSessionBeginInfo bi{XR_TYPE_SESSION_BEGIN_INFO};
        bi.primaryViewConfigurationType = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO;
        return xrBeginSession(session, &bi);
    }

    XrResult waitFrame(XrFrameState* state = nullptr) {
        XrFrameState s{XR_TYPE_FRAME_STATE};
        const XrResult r = xrWaitFrame(session, nullptr, &s);
        if (state != nullptr) *state = s;
        lastDisplayTime = s.predictedDisplayTime;
        return r;
    }
    XrResult beginFrame() { return xrBeginFrame(session, nullptr); }
    XrResult endFrame(const std::vector<const XrCompositionLayerBaseHeader*>& layers = {}) {
        XrFrameEndInfo ei{XR_TYPE_FRAME_END_INFO};
        ei.displayTime = lastDisplayTime;
        ei.environmentBlendMode = XR_ENVIRONMENT_BLEND_MODE_OPAQUE;
        ei.layerCount = static_cast<uint32_t>(layers.size());
        ei.layers = layers.data();
        return xrEndFrame(session, &ei);
    }

    /// Instance, session, begin and one empty frame: the session is FOCUSED.
    void runToFocused() {
        createInstance();
        createSession();
        ASSERT_EQ(XR_SUCCESS, beginSession());
        ASSERT_EQ(XR_SUCCESS, waitFrame());
        ASSERT_EQ(XR_SUCCESS, beginFrame());
        ASSERT_EQ(XR_SUCCESS, endFrame());
    }

    XrSwapchain createSwapchain(int64_t format, uint32_t width, uint32_t height) {
        XrSwapchainCreateInfo ci{XR_TYPE_SWAPCHAIN_CREATE_INFO};
        ci.usageFlags = XR_SWAPCHAIN_USAGE_COLOR_ATTACHMENT_BIT;
        ci.format = format;
        ci.sampleCount = 1;
        ci.width = width;
        ci.height = height;
        ci.faceCount = 1;
        ci.arraySize = 1;
        ci.mipCount = 1;
        XrSwapchain sc = XR_NULL_HANDLE;
        EXPECT_EQ(XR_SUCCESS, xrCreateSwapchain(session, &ci, &sc));
        return sc;
    }

    XrPath path(const char* s) {
        XrPath p = XR_NULL_PATH;
        EXPECT_EQ(XR_SUCCESS, xrStringToPath(instance, s, &p)) << s;
        return p;
    }

    template <class F>
    void load(const char* name, F& f) {
        ASSERT_EQ(XR_SUCCESS,
                  xrGetInstanceProcAddr(instance, name, reinterpret_cast<PFN_xrVoidFunction*>(&f)))
            << name;
    }

    std::unique_ptr<render::GlContext> mGl;
    XrInstance instance = XR_NULL_HANDLE;
    XrSystemId system = XR_NULL_SYSTEM_ID;
    XrSession session = XR_NULL_HANDLE;
    XrSpace local = XR_NULL_HANDLE;
    XrTime lastDisplayTime = 0;
    XrGraphicsBindingOpenGLXlibKHR binding{XR_TYPE_GRAPHICS_BINDING_OPENGL_XLIB_KHR};
    PFN_xrGetOpenGLGraphicsRequirementsKHR glRequirements = nullptr;
    PFN_xrSetInputDeviceActiveEXT setActive = nullptr;
    PFN_xrSetInputDeviceStateBoolEXT setBool = nullptr;
    PFN_xrSetInputDeviceStateFloatEXT setFloat = nullptr;
    PFN_xrSetInputDeviceStateVector2fEXT setVector2f = nullptr;
    PFN_xrSetInputDeviceLocationEXT setLocation = nullptr;
};

}  // namespace kizamu::xrsim::test
