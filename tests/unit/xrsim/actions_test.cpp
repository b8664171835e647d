// SPDX-License-Identifier: Apache-2.0
/// @file actions_test.cpp
/// @brief Actions bound in each of the three interaction profiles read the state set through
/// XR_EXT_conformance_automation; pose actions are located through action spaces; the rules on
/// attachment, sync and paths; haptics recorded; the current profile, bound sources and names.
#include "tests/unit/xrsim/xrsim_fixture.h"

#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <unistd.h>

namespace kizamu::xrsim::test {
namespace {

constexpr char kSimple[] = "/interaction_profiles/khr/simple_controller";
constexpr char kTouch[] = "/interaction_profiles/oculus/touch_controller";
constexpr char kIndex[] = "/interaction_profiles/valve/index_controller";

class XrSimActionsTest : public XrSimTest {
protected:
    /// The action set "play": trigger (float), select (boolean), stick (2D vector), grip (pose),
    /// buzz (vibration), each for both hands.
    void createActions() {
        hands[0] = path("/user/hand/left");
        hands[1] = path("/user/hand/right");
        XrActionSetCreateInfo si{XR_TYPE_ACTION_SET_CREATE_INFO};
        std::strcpy(si.actionSetName, "play");
        std::strcpy(si.localizedActionSetName, "Play");
        KIZAMU_ASSERT_XR(XR_SUCCESS, xrCreateActionSet(instance, &si, &set));
        trigger = action("trigger", XR_ACTION_TYPE_FLOAT_INPUT);
        select = action("select", XR_ACTION_TYPE_BOOLEAN_INPUT);
        stick = action("stick", XR_ACTION_TYPE_VECTOR2F_INPUT);
        grip = action("grip", XR_ACTION_TYPE_POSE_INPUT);
        buzz = action("buzz", XR_ACTION_TYPE_VIBRATION_OUTPUT);
    }

    XrAction action(const char* name, XrActionType type) {
        XrActionCreateInfo ci{XR_TYPE_ACTION_CREATE_INFO};
        std::strcpy(ci.actionName, name);
        std::strcpy(ci.localizedActionName, name);
        ci.actionType = type;
        ci.countSubactionPaths = 2;
        ci.subactionPaths = hands;
        XrAction a = XR_NULL_HANDLE;
        EXPECT_EQ(XR_SUCCESS, xrCreateAction(set, &ci, &a)) << name;
        return a;
    }

    XrResult suggest(const char* profile, const std::vector<std::pair<XrAction, const char*>>& b) {
        std::vector<XrActionSuggestedBinding> bindings;
        for (const auto& [a, p] : b) bindings.push_back({a, path(p)});
        XrInteractionProfileSuggestedBinding sb{XR_TYPE_INTERACTION_PROFILE_SUGGESTED_BINDING};
        sb.interactionProfile = path(profile);
        sb.countSuggestedBindings = static_cast<uint32_t>(bindings.size());
        sb.suggestedBindings = bindings.data();
        return xrSuggestInteractionProfileBindings(instance, &sb);
    }

    /// The bindings each test profile suggests: shorthand and full paths, bool from float and
    /// float from bool where the profile has them.
    XrResult suggestFor(const std::string& profile) {
        if (profile == kSimple)
            return suggest(kSimple, {{trigger, "/user/hand/right/input/select/click"},
                                     {select, "/user/hand/right/input/select"},
                                     {grip, "/user/hand/right/input/grip/pose"},
                                     {buzz, "/user/hand/right/output/haptic"}});
        if (profile == kTouch)
            return suggest(kTouch, {{trigger, "/user/hand/right/input/trigger"},
                                    {select, "/user/hand/right/input/a/click"},
                                    {select, "/user/hand/left/input/squeeze/value"},
                                    {stick, "/user/hand/right/input/thumbstick"},
                                    {grip, "/user/hand/right/input/grip"},
                                    {buzz, "/user/hand/right/output/haptic"}});
        return suggest(kIndex, {{trigger, "/user/hand/right/input/trigger/value"},
                                {select, "/user/hand/right/input/trigger"},
                                {stick, "/user/hand/right/input/thumbstick"},
                                {grip, "/user/hand/right/input/grip/pose"},
                                {buzz, "/user/hand/right/output/haptic"},
                                {buzz, "/user/hand/left/output/haptic"}});
    }

    XrResult attach() {
        XrSessionActionSetsAttachInfo ai{XR_TYPE_SESSION_ACTION_SETS_ATTACH_INFO};
        ai.countActionSets = 1;
        ai.actionSets = &set;
        return xrAttachSessionActionSets(session, &ai);
    }

    /// Session, attach, begin, one frame: FOCUSED with the action set attached.
    void focusWithActions() {
        createSession();
        ASSERT_EQ(XR_SUCCESS, attach());
        ASSERT_EQ(XR_SUCCESS, beginSession());
        ASSERT_EQ(XR_SUCCESS, waitFrame());
        ASSERT_EQ(XR_SUCCESS, beginFrame());
        ASSERT_EQ(XR_SUCCESS, endFrame());
    }

    XrResult sync(XrActionSet which) {
        XrActiveActionSet active{which, XR_NULL_PATH};
        XrActionsSyncInfo si{XR_TYPE_ACTIONS_SYNC_INFO};
        si.countActiveActionSets = 1;
        si.activeActionSets = &active;
        return xrSyncActions(session, &si);
    }

    XrActionStateGetInfo info(XrAction a, XrPath sub = XR_NULL_PATH) {
        XrActionStateGetInfo gi{XR_TYPE_ACTION_STATE_GET_INFO};
        gi.action = a;
        gi.subactionPath = sub;
        return gi;
    }
    XrActionStateFloat floatState(XrAction a, XrPath sub = XR_NULL_PATH) {
        XrActionStateFloat s{XR_TYPE_ACTION_STATE_FLOAT};
        const XrActionStateGetInfo gi = info(a, sub);
        EXPECT_EQ(XR_SUCCESS, xrGetActionStateFloat(session, &gi, &s));
        return s;
    }
    XrActionStateBoolean boolState(XrAction a, XrPath sub = XR_NULL_PATH) {
        XrActionStateBoolean s{XR_TYPE_ACTION_STATE_BOOLEAN};
        const XrActionStateGetInfo gi = info(a, sub);
        EXPECT_EQ(XR_SUCCESS, xrGetActionStateBoolean(session, &gi, &s));
        return s;
    }
    XrActionStateVector2f vectorState(XrAction a) {
        XrActionStateVector2f s{XR_TYPE_ACTION_STATE_VECTOR2F};
        const XrActionStateGetInfo gi = info(a);
        EXPECT_EQ(XR_SUCCESS, xrGetActionStateVector2f(session, &gi, &s));
        return s;
    }

    XrPath hands[2] = {};
    XrActionSet set = XR_NULL_HANDLE;
    XrAction trigger = XR_NULL_HANDLE, select = XR_NULL_HANDLE, stick = XR_NULL_HANDLE,
             grip = XR_NULL_HANDLE, buzz = XR_NULL_HANDLE;
};

class XrSimProfileTest : public XrSimActionsTest,
                         public ::testing::WithParamInterface<const char*> {};

TEST_P(XrSimProfileTest, ActionsReadTheAutomationState) {
    const std::string profile = GetParam();
    createInstance();
    createActions();
    KIZAMU_ASSERT_XR(XR_SUCCESS, suggestFor(profile));
    focusWithActions();
    XrInteractionProfileState ps{XR_TYPE_INTERACTION_PROFILE_STATE};
    KIZAMU_ASSERT_XR(XR_SUCCESS, xrGetCurrentInteractionProfile(session, hands[1], &ps));
    EXPECT_EQ(ps.interactionProfile, path(profile.c_str()));

    // Nothing pressed at first.
    KIZAMU_ASSERT_XR(XR_SUCCESS, sync(set));
    EXPECT_TRUE(floatState(trigger).isActive);
    EXPECT_EQ(floatState(trigger).currentState, 0.0f);
    EXPECT_FALSE(boolState(select).currentState);

    const XrPath right = hands[1];
    if (profile == kSimple) {
        KIZAMU_ASSERT_XR(XR_SUCCESS, setBool(session, right,
                                             path("/user/hand/right/input/select/click"), XR_TRUE));
    } else if (profile == kTouch) {
        KIZAMU_ASSERT_XR(XR_SUCCESS, setFloat(session, right,
                                              path("/user/hand/right/input/trigger/value"), 1.0f));
        KIZAMU_ASSERT_XR(XR_SUCCESS,
                         setBool(session, right, path("/user/hand/right/input/a/click"), XR_TRUE));
        KIZAMU_ASSERT_XR(XR_SUCCESS,
                         setVector2f(session, right, path("/user/hand/right/input/thumbstick"),
                                     XrVector2f{0.25f, -0.5f}));
    } else {
        // The shorthand .../trigger of a boolean reads the click, which follows the value.
        KIZAMU_ASSERT_XR(XR_SUCCESS, setFloat(session, right,
                                              path("/user/hand/right/input/trigger/value"), 1.0f));
        KIZAMU_ASSERT_XR(XR_SUCCESS,
                         setVector2f(session, right, path("/user/hand/right/input/thumbstick"),
                                     XrVector2f{0.25f, -0.5f}));
    }
    // Read at the next sync only.
    EXPECT_EQ(floatState(trigger).currentState, 0.0f);
    KIZAMU_ASSERT_XR(XR_SUCCESS, sync(set));
    EXPECT_EQ(floatState(trigger).currentState, 1.0f);
    EXPECT_TRUE(floatState(trigger).changedSinceLastSync);
    EXPECT_EQ(floatState(trigger, hands[1]).currentState, 1.0f);
    EXPECT_FALSE(floatState(trigger, hands[0]).isActive);
    EXPECT_TRUE(boolState(select).currentState);
    if (profile != kSimple) {
        const XrActionStateVector2f v = vectorState(stick);
        EXPECT_TRUE(v.isActive);
        EXPECT_EQ(v.currentState.x, 0.25f);
        EXPECT_EQ(v.currentState.y, -0.5f);
    }
    // A device switched off makes its actions inactive.
    KIZAMU_ASSERT_XR(XR_SUCCESS, setActive(session, path(profile.c_str()), right, XR_FALSE));
    KIZAMU_ASSERT_XR(XR_SUCCESS, sync(set));
    EXPECT_FALSE(floatState(trigger).isActive);
}

INSTANTIATE_TEST_SUITE_P(Profiles, XrSimProfileTest, ::testing::Values(kSimple, kTouch, kIndex),
                         [](const auto& param) {
                             const std::string p = param.param;
                             return p == kSimple  ? "KhrSimple"
                                    : p == kTouch ? "OculusTouch"
                                                  : "ValveIndex";
                         });

TEST_F(XrSimActionsTest, BoolFromFloatOnTheOtherHand) {
    createInstance();
    createActions();
    KIZAMU_ASSERT_XR(XR_SUCCESS, suggestFor(kTouch));
    focusWithActions();
    KIZAMU_ASSERT_XR(
        XR_SUCCESS, setFloat(session, hands[0], path("/user/hand/left/input/squeeze/value"), 0.4f));
    KIZAMU_ASSERT_XR(XR_SUCCESS, sync(set));
    EXPECT_FALSE(boolState(select, hands[0]).currentState);
    KIZAMU_ASSERT_XR(
        XR_SUCCESS, setFloat(session, hands[0], path("/user/hand/left/input/squeeze/value"), 0.6f));
    KIZAMU_ASSERT_XR(XR_SUCCESS, sync(set));
    EXPECT_TRUE(boolState(select, hands[0]).currentState);
    EXPECT_FALSE(boolState(select, hands[1]).currentState);
}

TEST_F(XrSimActionsTest, PreferredProfileAndTheEnvironmentsChoice) {
    createInstance();
    createActions();
    for (const char* p : {kSimple, kTouch, kIndex}) KIZAMU_ASSERT_XR(XR_SUCCESS, suggestFor(p));
    createSession();
    KIZAMU_ASSERT_XR(XR_SUCCESS, attach());
    XrInteractionProfileState ps{XR_TYPE_INTERACTION_PROFILE_STATE};
    KIZAMU_ASSERT_XR(XR_SUCCESS, xrGetCurrentInteractionProfile(session, hands[0], &ps));
    EXPECT_EQ(ps.interactionProfile, path(kIndex));
    KIZAMU_ASSERT_XR(XR_SUCCESS, xrDestroySession(session));

    setenv("KIZAMU_XRSIM_PROFILE", "oculus/touch_controller", 1);
    createSession();
    KIZAMU_ASSERT_XR(XR_SUCCESS, attach());
    unsetenv("KIZAMU_XRSIM_PROFILE");
    KIZAMU_ASSERT_XR(XR_SUCCESS, xrGetCurrentInteractionProfile(session, hands[0], &ps));
    EXPECT_EQ(ps.interactionProfile, path(kTouch));
}

TEST_F(XrSimActionsTest, StateBeforeAnySyncIsInactive) {
    createInstance();
    createActions();
    KIZAMU_ASSERT_XR(XR_SUCCESS, suggestFor(kIndex));
    focusWithActions();
    KIZAMU_ASSERT_XR(XR_SUCCESS, setFloat(session, hands[1],
                                          path("/user/hand/right/input/trigger/value"), 1.0f));
    EXPECT_FALSE(floatState(trigger).isActive);
    EXPECT_EQ(floatState(trigger).currentState, 0.0f);
}

TEST_F(XrSimActionsTest, AttachmentRules) {
    createInstance();
    createActions();
    KIZAMU_ASSERT_XR(XR_SUCCESS, suggestFor(kIndex));
    createSession();
    XrActionStateFloat fs{XR_TYPE_ACTION_STATE_FLOAT};
    const XrActionStateGetInfo gi = info(trigger);
    KIZAMU_EXPECT_XR(XR_ERROR_ACTIONSET_NOT_ATTACHED, xrGetActionStateFloat(session, &gi, &fs));
    KIZAMU_EXPECT_XR(XR_ERROR_ACTIONSET_NOT_ATTACHED, sync(set));
    KIZAMU_ASSERT_XR(XR_SUCCESS, attach());
    KIZAMU_EXPECT_XR(XR_ERROR_ACTIONSETS_ALREADY_ATTACHED, attach());
    XrActionCreateInfo ci{XR_TYPE_ACTION_CREATE_INFO};
    std::strcpy(ci.actionName, "late");
    std::strcpy(ci.localizedActionName, "Late");
    ci.actionType = XR_ACTION_TYPE_BOOLEAN_INPUT;
    XrAction late = XR_NULL_HANDLE;
    KIZAMU_EXPECT_XR(XR_ERROR_ACTIONSETS_ALREADY_ATTACHED, xrCreateAction(set, &ci, &late));
    KIZAMU_EXPECT_XR(XR_ERROR_ACTIONSETS_ALREADY_ATTACHED, suggestFor(kTouch));

    // A set never attached to this session.
    XrActionSetCreateInfo si{XR_TYPE_ACTION_SET_CREATE_INFO};
    std::strcpy(si.actionSetName, "other");
    std::strcpy(si.localizedActionSetName, "Other");
    XrActionSet other = XR_NULL_HANDLE;
    KIZAMU_ASSERT_XR(XR_SUCCESS, xrCreateActionSet(instance, &si, &other));
    KIZAMU_EXPECT_XR(XR_ERROR_ACTIONSET_NOT_ATTACHED, sync(other));
    KIZAMU_EXPECT_XR(
        XR_ERROR_ACTION_TYPE_MISMATCH,
        xrGetActionStateBoolean(session, &gi, reinterpret_cast<XrActionStateBoolean*>(&fs)));
    // Not focused yet: the sync succeeds but says so.
    KIZAMU_EXPECT_XR(XR_SESSION_NOT_FOCUSED, sync(set));
}

TEST_F(XrSimActionsTest, UnknownProfilesAndBindingPathsAreUnsupported) {
    createInstance();
    createActions();
    KIZAMU_EXPECT_XR(XR_ERROR_PATH_UNSUPPORTED,
                     suggest("/interaction_profiles/acme/wand",
                             {{select, "/user/hand/right/input/select/click"}}));
    KIZAMU_EXPECT_XR(XR_ERROR_PATH_UNSUPPORTED,
                     suggest(kSimple, {{select, "/user/hand/right/input/trigger/value"}}));
    KIZAMU_EXPECT_XR(XR_ERROR_PATH_UNSUPPORTED,
                     suggest(kTouch, {{select, "/user/hand/left/input/a/click"}}));
    KIZAMU_EXPECT_XR(XR_SUCCESS, suggest(kTouch, {{select, "/user/hand/left/input/x/click"}}));
}

TEST_F(XrSimActionsTest, PoseActionsAreLocatedThroughActionSpaces) {
    createInstance();
    createActions();
    KIZAMU_ASSERT_XR(XR_SUCCESS, suggestFor(kIndex));
    focusWithActions();
    XrActionSpaceCreateInfo ci{XR_TYPE_ACTION_SPACE_CREATE_INFO};
    ci.action = grip;
    ci.subactionPath = hands[1];
    ci.poseInActionSpace.orientation.w = 1.0f;
    XrSpace gripSpace = XR_NULL_HANDLE;
    KIZAMU_ASSERT_XR(XR_SUCCESS, xrCreateActionSpace(session, &ci, &gripSpace));
    XrSpaceLocation loc{XR_TYPE_SPACE_LOCATION};
    // Not synced yet: not located.
    KIZAMU_ASSERT_XR(XR_SUCCESS, xrLocateSpace(gripSpace, local, lastDisplayTime, &loc));
    EXPECT_EQ(loc.locationFlags, 0u);
    // Synced: the controller starts at the origin.
    KIZAMU_ASSERT_XR(XR_SUCCESS, sync(set));
    KIZAMU_ASSERT_XR(XR_SUCCESS, xrLocateSpace(gripSpace, local, lastDisplayTime, &loc));
    EXPECT_TRUE(loc.locationFlags & XR_SPACE_LOCATION_POSITION_TRACKED_BIT);
    EXPECT_EQ(loc.pose.position.x, 0.0f);
    EXPECT_EQ(loc.pose.orientation.w, 1.0f);

    const XrPosef pose{{0.0f, 0.0f, 0.0f, 1.0f}, {0.1f, 1.2f, -0.3f}};
    KIZAMU_ASSERT_XR(
        XR_SUCCESS,
        setLocation(session, hands[1], path("/user/hand/right/input/grip/pose"), local, pose));
    KIZAMU_ASSERT_XR(XR_SUCCESS, sync(set));
    XrActionStatePose ps{XR_TYPE_ACTION_STATE_POSE};
    const XrActionStateGetInfo gi = info(grip);
    KIZAMU_ASSERT_XR(XR_SUCCESS, xrGetActionStatePose(session, &gi, &ps));
    EXPECT_TRUE(ps.isActive);
    KIZAMU_ASSERT_XR(XR_SUCCESS, xrLocateSpace(gripSpace, local, lastDisplayTime, &loc));
    EXPECT_TRUE(loc.locationFlags & XR_SPACE_LOCATION_POSITION_VALID_BIT);
    EXPECT_FLOAT_EQ(loc.pose.position.x, 0.1f);
    EXPECT_FLOAT_EQ(loc.pose.position.y, 1.2f);
    EXPECT_FLOAT_EQ(loc.pose.position.z, -0.3f);
    // Relative to a space offset by 1 m up, the controller is 1 m lower.
    XrReferenceSpaceCreateInfo si{XR_TYPE_REFERENCE_SPACE_CREATE_INFO};
    si.referenceSpaceType = XR_REFERENCE_SPACE_TYPE_STAGE;
    si.poseInReferenceSpace = {{0.0f, 0.0f, 0.0f, 1.0f}, {0.0f, 1.0f, 0.0f}};
    XrSpace raised = XR_NULL_HANDLE;
    KIZAMU_ASSERT_XR(XR_SUCCESS, xrCreateReferenceSpace(session, &si, &raised));
    KIZAMU_ASSERT_XR(XR_SUCCESS, xrLocateSpace(gripSpace, raised, lastDisplayTime, &loc));
    EXPECT_NEAR(loc.pose.position.y, 0.2f, 1e-6);
}

TEST_F(XrSimActionsTest, HapticsAreRecorded) {
    const std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                      ("kizamu_xrsim_haptics_" + std::to_string(getpid()));
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    setenv("KIZAMU_XRSIM_CAPTURE", dir.c_str(), 1);
    createInstance();
    unsetenv("KIZAMU_XRSIM_CAPTURE");
    createActions();
    KIZAMU_ASSERT_XR(XR_SUCCESS, suggestFor(kIndex));
    focusWithActions();
    XrHapticActionInfo hi{XR_TYPE_HAPTIC_ACTION_INFO};
    hi.action = buzz;
    hi.subactionPath = hands[1];
    XrHapticVibration v{XR_TYPE_HAPTIC_VIBRATION};
    v.amplitude = 0.5f;
    v.duration = 20'000'000;
    v.frequency = 160.0f;
    KIZAMU_ASSERT_XR(
        XR_SUCCESS, xrApplyHapticFeedback(session, &hi, reinterpret_cast<XrHapticBaseHeader*>(&v)));
    KIZAMU_ASSERT_XR(XR_SUCCESS, xrStopHapticFeedback(session, &hi));
    ASSERT_EQ(kizamuXrSimHapticCount(), 2);
    KizamuXrSimHaptic h{};
    ASSERT_EQ(kizamuXrSimHapticEvent(0, &h), 0);
    EXPECT_STREQ(h.hand, "/user/hand/right");
    EXPECT_EQ(h.amplitude, 0.5f);
    EXPECT_EQ(h.durationNs, 20'000'000);
    EXPECT_EQ(h.frequencyHz, 160.0f);
    EXPECT_EQ(h.timeNs, lastDisplayTime);
    ASSERT_EQ(kizamuXrSimHapticEvent(1, &h), 0);
    EXPECT_EQ(h.amplitude, 0.0f);
    EXPECT_EQ(kizamuXrSimHapticEvent(2, &h), 1);
    // Without a subaction path every bound hand vibrates.
    hi.subactionPath = XR_NULL_PATH;
    KIZAMU_ASSERT_XR(
        XR_SUCCESS, xrApplyHapticFeedback(session, &hi, reinterpret_cast<XrHapticBaseHeader*>(&v)));
    EXPECT_EQ(kizamuXrSimHapticCount(), 4);
    std::ifstream events(dir / "events.jsonl");
    std::stringstream all;
    all << events.rdbuf();
    EXPECT_NE(all.str().find("{\"event\":\"haptic\",\"hand\":\"/user/hand/right\","
                             "\"amplitude\":0.5,\"duration_ns\":20000000,"),
              std::string::npos)
        << all.str();
    std::filesystem::remove_all(dir);
    hi.action = trigger;
    KIZAMU_EXPECT_XR(
        XR_ERROR_ACTION_TYPE_MISMATCH,
        xrApplyHapticFeedback(session, &hi, reinterpret_cast<XrHapticBaseHeader*>(&v)));
}

TEST_F(XrSimActionsTest, BoundSourcesAndLocalizedNames) {
    createInstance();
    createActions();
    KIZAMU_ASSERT_XR(XR_SUCCESS, suggestFor(kIndex));
    focusWithActions();
    XrBoundSourcesForActionEnumerateInfo ei{XR_TYPE_BOUND_SOURCES_FOR_ACTION_ENUMERATE_INFO};
    ei.action = select;
    uint32_t n = 0;
    KIZAMU_ASSERT_XR(XR_SUCCESS, xrEnumerateBoundSourcesForAction(session, &ei, 0, &n, nullptr));
    ASSERT_EQ(n, 1u);
    XrPath source = XR_NULL_PATH;
    KIZAMU_ASSERT_XR(XR_SUCCESS, xrEnumerateBoundSourcesForAction(session, &ei, 1, &n, &source));
    EXPECT_EQ(source, path("/user/hand/right/input/trigger/click"));
    XrInputSourceLocalizedNameGetInfo li{XR_TYPE_INPUT_SOURCE_LOCALIZED_NAME_GET_INFO};
    li.sourcePath = source;
    li.whichComponents = XR_INPUT_SOURCE_LOCALIZED_NAME_USER_PATH_BIT |
                         XR_INPUT_SOURCE_LOCALIZED_NAME_INTERACTION_PROFILE_BIT |
                         XR_INPUT_SOURCE_LOCALIZED_NAME_COMPONENT_BIT;
    char name[128];
    KIZAMU_ASSERT_XR(XR_SUCCESS,
                     xrGetInputSourceLocalizedName(session, &li, sizeof(name), &n, name));
    EXPECT_STREQ(name, "Right Hand Index Controller Trigger Click");
}

}  // namespace
}  // namespace kizamu::xrsim::test
