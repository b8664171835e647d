// SPDX-License-Identifier: Apache-2.0
/// @file session_test.cpp
/// @brief The runtime through the real loader: instance and system queries, the session
/// lifecycle and its events, the rules on session transitions, runtime stop and session loss,
/// and the graphics binding checks.
#include "tests/unit/xrsim/xrsim_fixture.h"

#include <cstring>

namespace kizamu::xrsim::test {
namespace {

using States = std::vector<XrSessionState>;

TEST_F(XrSimTest, LoaderFindsTheRuntime) {
    createInstance();
    XrInstanceProperties props{XR_TYPE_INSTANCE_PROPERTIES};
    KIZAMU_ASSERT_XR(XR_SUCCESS, xrGetInstanceProperties(instance, &props));
    EXPECT_STREQ(props.runtimeName, "Kizamu simulated runtime");
    char name[XR_MAX_RESULT_STRING_SIZE];
    KIZAMU_EXPECT_XR(XR_SUCCESS, xrResultToString(instance, XR_ERROR_SESSION_LOST, name));
    EXPECT_STREQ(name, "XR_ERROR_SESSION_LOST");
    char type[XR_MAX_STRUCTURE_NAME_SIZE];
    KIZAMU_EXPECT_XR(XR_SUCCESS, xrStructureTypeToString(instance, XR_TYPE_FRAME_STATE, type));
    EXPECT_STREQ(type, "XR_TYPE_FRAME_STATE");
}

TEST_F(XrSimTest, ExtensionsAndUnknownOnes) {
    uint32_t n = 0;
    KIZAMU_ASSERT_XR(XR_SUCCESS, xrEnumerateInstanceExtensionProperties(nullptr, 0, &n, nullptr));
    std::vector<XrExtensionProperties> ext(n, {XR_TYPE_EXTENSION_PROPERTIES});
    KIZAMU_ASSERT_XR(XR_SUCCESS,
                     xrEnumerateInstanceExtensionProperties(nullptr, n, &n, ext.data()));
    std::vector<std::string> names;
    for (const auto& e : ext) names.push_back(e.extensionName);
    EXPECT_NE(std::find(names.begin(), names.end(), "XR_KHR_opengl_enable"), names.end());
    EXPECT_NE(std::find(names.begin(), names.end(), "XR_EXT_conformance_automation"), names.end());

    const char* unknown[] = {"XR_KHR_vulkan_enable"};
    XrInstanceCreateInfo ci{XR_TYPE_INSTANCE_CREATE_INFO};
    std::snprintf(ci.applicationInfo.applicationName, XR_MAX_APPLICATION_NAME_SIZE, "x");
    ci.applicationInfo.apiVersion = XR_MAKE_VERSION(1, 0, 0);
    ci.enabledExtensionCount = 1;
    ci.enabledExtensionNames = unknown;
    XrInstance other = XR_NULL_HANDLE;
    KIZAMU_EXPECT_XR(XR_ERROR_EXTENSION_NOT_PRESENT, xrCreateInstance(&ci, &other));
}

TEST_F(XrSimTest, PathsRoundTripAndMalformedOnesFail) {
    createInstance();
    const XrPath p = path("/user/hand/left/input/trigger/value");
    EXPECT_EQ(p, path("/user/hand/left/input/trigger/value"));
    char buf[XR_MAX_PATH_LENGTH];
    uint32_t n = 0;
    KIZAMU_ASSERT_XR(XR_SUCCESS, xrPathToString(instance, p, sizeof(buf), &n, buf));
    EXPECT_STREQ(buf, "/user/hand/left/input/trigger/value");
    XrPath bad = XR_NULL_PATH;
    for (const char* s : {"user/hand", "/user//hand", "/user/Hand", "/user/hand/", "/.."})
        KIZAMU_EXPECT_XR(XR_ERROR_PATH_FORMAT_INVALID, xrStringToPath(instance, s, &bad)) << s;
    KIZAMU_EXPECT_XR(XR_ERROR_PATH_INVALID, xrPathToString(instance, 987654, sizeof(buf), &n, buf));
}

TEST_F(XrSimTest, SystemViewsAndEyeSizeFromTheEnvironment) {
    createInstance();
    XrSystemGetInfo gi{XR_TYPE_SYSTEM_GET_INFO};
    gi.formFactor = XR_FORM_FACTOR_HANDHELD_DISPLAY;
    XrSystemId other = XR_NULL_SYSTEM_ID;
    KIZAMU_EXPECT_XR(XR_ERROR_FORM_FACTOR_UNSUPPORTED, xrGetSystem(instance, &gi, &other));
    uint32_t n = 0;
    KIZAMU_ASSERT_XR(XR_SUCCESS, xrEnumerateViewConfigurationViews(
                                     instance, system, XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO, 0,
                                     &n, nullptr));
    ASSERT_EQ(n, 2u);
    std::vector<XrViewConfigurationView> views(n, {XR_TYPE_VIEW_CONFIGURATION_VIEW});
    KIZAMU_ASSERT_XR(XR_SUCCESS, xrEnumerateViewConfigurationViews(
                                     instance, system, XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO, n,
                                     &n, views.data()));
    EXPECT_EQ(views[0].recommendedImageRectWidth, 640u);
    EXPECT_EQ(views[1].recommendedImageRectHeight, 640u);
    setenv("KIZAMU_XRSIM_EYE_SIZE", "320x200", 1);
    KIZAMU_ASSERT_XR(XR_SUCCESS, xrEnumerateViewConfigurationViews(
                                     instance, system, XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO, n,
                                     &n, views.data()));
    unsetenv("KIZAMU_XRSIM_EYE_SIZE");
    EXPECT_EQ(views[0].recommendedImageRectWidth, 320u);
    EXPECT_EQ(views[0].recommendedImageRectHeight, 200u);
    XrEnvironmentBlendMode mode{};
    KIZAMU_ASSERT_XR(
        XR_SUCCESS, xrEnumerateEnvironmentBlendModes(
                        instance, system, XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO, 1, &n, &mode));
    EXPECT_EQ(mode, XR_ENVIRONMENT_BLEND_MODE_OPAQUE);
    XrGraphicsRequirementsOpenGLKHR req{XR_TYPE_GRAPHICS_REQUIREMENTS_OPENGL_KHR};
    KIZAMU_ASSERT_XR(XR_SUCCESS, glRequirements(instance, system, &req));
    EXPECT_EQ(req.minApiVersionSupported, XR_MAKE_VERSION(3, 3, 0));
    EXPECT_EQ(req.maxApiVersionSupported, XR_MAKE_VERSION(4, 6, 0));
}

TEST_F(XrSimTest, SessionNeedsTheGlBindingAndTheRequirementsCall) {
    createInstance();
    XrSessionCreateInfo ci{XR_TYPE_SESSION_CREATE_INFO};
    ci.systemId = system;
    ci.next = &binding;
    KIZAMU_EXPECT_XR(XR_ERROR_GRAPHICS_REQUIREMENTS_CALL_MISSING,
                     xrCreateSession(instance, &ci, &session));
    XrGraphicsRequirementsOpenGLKHR req{XR_TYPE_GRAPHICS_REQUIREMENTS_OPENGL_KHR};
    KIZAMU_ASSERT_XR(XR_SUCCESS, glRequirements(instance, system, &req));
    ci.next = nullptr;
    KIZAMU_EXPECT_XR(XR_ERROR_GRAPHICS_DEVICE_INVALID, xrCreateSession(instance, &ci, &session));
    ci.next = &binding;
    KIZAMU_EXPECT_XR(XR_SUCCESS, xrCreateSession(instance, &ci, &session));
}

TEST_F(XrSimTest, FullLifecycleReachesFocusedAndEndsCleanly) {
    createInstance();
    createSession();
    EXPECT_EQ(pollStates(), (States{XR_SESSION_STATE_IDLE, XR_SESSION_STATE_READY}));
    KIZAMU_ASSERT_XR(XR_SUCCESS, beginSession());
    EXPECT_EQ(pollStates(), (States{XR_SESSION_STATE_SYNCHRONIZED}));
    XrFrameState fs{XR_TYPE_FRAME_STATE};
    KIZAMU_ASSERT_XR(XR_SUCCESS, waitFrame(&fs));
    EXPECT_FALSE(fs.shouldRender);
    KIZAMU_ASSERT_XR(XR_SUCCESS, beginFrame());
    KIZAMU_ASSERT_XR(XR_SUCCESS, endFrame());
    EXPECT_EQ(pollStates(), (States{XR_SESSION_STATE_VISIBLE, XR_SESSION_STATE_FOCUSED}));
    KIZAMU_ASSERT_XR(XR_SUCCESS, waitFrame(&fs));
    EXPECT_TRUE(fs.shouldRender);
    KIZAMU_ASSERT_XR(XR_SUCCESS, beginFrame());
    KIZAMU_ASSERT_XR(XR_SUCCESS, endFrame());
    EXPECT_EQ(kizamuXrSimFramesEnded(), 2u);

    KIZAMU_ASSERT_XR(XR_SUCCESS, xrRequestExitSession(session));
    EXPECT_EQ(pollStates(), (States{XR_SESSION_STATE_VISIBLE, XR_SESSION_STATE_SYNCHRONIZED,
                                    XR_SESSION_STATE_STOPPING}));
    KIZAMU_ASSERT_XR(XR_SUCCESS, xrEndSession(session));
    EXPECT_EQ(pollStates(), (States{XR_SESSION_STATE_IDLE, XR_SESSION_STATE_EXITING}));
    KIZAMU_ASSERT_XR(XR_SUCCESS, xrDestroySession(session));
    KIZAMU_EXPECT_XR(XR_ERROR_HANDLE_INVALID, xrDestroySession(session));
    KIZAMU_EXPECT_XR(XR_ERROR_HANDLE_INVALID, xrDestroySpace(local));
}

TEST_F(XrSimTest, ClockAdvancesOneNinetiethPerWaitFromOneSecond) {
    runToFocused();
    XrFrameState fs{XR_TYPE_FRAME_STATE};
    KIZAMU_ASSERT_XR(XR_SUCCESS, waitFrame(&fs));
    EXPECT_EQ(fs.predictedDisplayTime, 1'000'000'000 + 11'111'111);
    EXPECT_EQ(fs.predictedDisplayPeriod, 11'111'111);
    KIZAMU_ASSERT_XR(XR_SUCCESS, beginFrame());
    KIZAMU_ASSERT_XR(XR_SUCCESS, endFrame());
    KIZAMU_ASSERT_XR(XR_SUCCESS, waitFrame(&fs));
    EXPECT_EQ(fs.predictedDisplayTime, 1'000'000'000 + 2 * 11'111'111);
}

TEST_F(XrSimTest, SessionTransitionRules) {
    createInstance();
    createSession();
    KIZAMU_EXPECT_XR(XR_ERROR_SESSION_NOT_RUNNING, xrEndSession(session));
    KIZAMU_EXPECT_XR(XR_ERROR_SESSION_NOT_RUNNING, waitFrame());
    KIZAMU_EXPECT_XR(XR_ERROR_SESSION_NOT_RUNNING, beginFrame());
    KIZAMU_EXPECT_XR(XR_ERROR_SESSION_NOT_RUNNING, xrRequestExitSession(session));
    KIZAMU_ASSERT_XR(XR_SUCCESS, beginSession());
    KIZAMU_EXPECT_XR(XR_ERROR_SESSION_RUNNING, beginSession());
    KIZAMU_EXPECT_XR(XR_ERROR_SESSION_NOT_STOPPING, xrEndSession(session));
    KIZAMU_ASSERT_XR(XR_SUCCESS, xrRequestExitSession(session));
    KIZAMU_ASSERT_XR(XR_SUCCESS, xrEndSession(session));
    // Now IDLE then EXITING: not READY.
    KIZAMU_EXPECT_XR(XR_ERROR_SESSION_NOT_READY, beginSession());
}

TEST_F(XrSimTest, RuntimeInitiatedStopGoesThroughStoppingToExiting) {
    runToFocused();
    pollStates();
    kizamuXrSimRequestStop();
    EXPECT_EQ(pollStates(), (States{XR_SESSION_STATE_VISIBLE, XR_SESSION_STATE_SYNCHRONIZED,
                                    XR_SESSION_STATE_STOPPING}));
    KIZAMU_ASSERT_XR(XR_SUCCESS, xrEndSession(session));
    EXPECT_EQ(pollStates(), (States{XR_SESSION_STATE_IDLE, XR_SESSION_STATE_EXITING}));
}

TEST_F(XrSimTest, LostSessionAnswersSessionLost) {
    runToFocused();
    pollStates();
    kizamuXrSimLoseSession();
    EXPECT_EQ(pollStates(), (States{XR_SESSION_STATE_LOSS_PENDING}));
    KIZAMU_EXPECT_XR(XR_ERROR_SESSION_LOST, waitFrame());
    KIZAMU_EXPECT_XR(XR_ERROR_SESSION_LOST, xrRequestExitSession(session));
    uint32_t n = 0;
    KIZAMU_EXPECT_XR(XR_ERROR_SESSION_LOST, xrEnumerateSwapchainFormats(session, 0, &n, nullptr));
    KIZAMU_EXPECT_XR(XR_SUCCESS, xrDestroySession(session));
}

TEST_F(XrSimTest, DestroyedAndUnknownHandlesAreInvalid) {
    createInstance();
    createSession();
    XrSession bogus = reinterpret_cast<XrSession>(uintptr_t{0xdead});
    KIZAMU_EXPECT_XR(XR_ERROR_HANDLE_INVALID, xrBeginSession(bogus, nullptr));
    KIZAMU_ASSERT_XR(XR_SUCCESS, xrDestroySpace(local));
    XrSpaceLocation loc{XR_TYPE_SPACE_LOCATION};
    KIZAMU_EXPECT_XR(XR_ERROR_HANDLE_INVALID, xrLocateSpace(local, local, 1, &loc));
}

}  // namespace
}  // namespace kizamu::xrsim::test
