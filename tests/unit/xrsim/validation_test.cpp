// SPDX-License-Identifier: Apache-2.0
/// @file validation_test.cpp
/// @brief The whole lifecycle again under Khronos' core validation layer
/// (XR_APILAYER_LUNARG_core_validation, found by the loader in its explicit layer directory),
/// which writes what it finds as text to a file (XR_CORE_VALIDATION_EXPORT_TYPE=text,
/// XR_CORE_VALIDATION_FILE_NAME): the file must report no error.
#include "tests/unit/xrsim/xrsim_fixture.h"

#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <unistd.h>

namespace kizamu::xrsim::test {
namespace {

constexpr char kLayer[] = "XR_APILAYER_LUNARG_core_validation";

class XrSimValidationTest : public XrSimTest {
protected:
    void SetUp() override {
        XrSimTest::SetUp();
        mReport = std::filesystem::temp_directory_path() /
                  ("kizamu_xrsim_validation_" + std::to_string(getpid()) + ".txt");
        std::filesystem::remove(mReport);
        // The layer reads these when it is first loaded (at xrCreateInstance).
        setenv("XR_CORE_VALIDATION_EXPORT_TYPE", "text", 1);
        setenv("XR_CORE_VALIDATION_FILE_NAME", mReport.c_str(), 1);
    }
    void TearDown() override {
        XrSimTest::TearDown();
        std::filesystem::remove(mReport);
    }
    /// What the layer wrote (empty when nothing).
    std::string report() const {
        std::ifstream in(mReport);
        std::stringstream s;
        s << in.rdbuf();
        return s.str();
    }
    std::filesystem::path mReport;
};

TEST_F(XrSimValidationTest, LayerIsAvailable) {
    uint32_t n = 0;
    KIZAMU_ASSERT_XR(XR_SUCCESS, xrEnumerateApiLayerProperties(0, &n, nullptr));
    std::vector<XrApiLayerProperties> layers(n, {XR_TYPE_API_LAYER_PROPERTIES});
    KIZAMU_ASSERT_XR(XR_SUCCESS, xrEnumerateApiLayerProperties(n, &n, layers.data()));
    bool found = false;
    for (const auto& l : layers) found = found || std::strcmp(l.layerName, kLayer) == 0;
    EXPECT_TRUE(found) << "openxr-layer-corevalidation is not installed";
}

TEST_F(XrSimValidationTest, FullLifecycleReportsNoErrors) {
    createInstance({kLayer});
    createSession();

    // Actions: one boolean and one pose, synced every frame.
    XrPath right = path("/user/hand/right");
    XrActionSetCreateInfo si{XR_TYPE_ACTION_SET_CREATE_INFO};
    std::strcpy(si.actionSetName, "play");
    std::strcpy(si.localizedActionSetName, "Play");
    XrActionSet set = XR_NULL_HANDLE;
    KIZAMU_ASSERT_XR(XR_SUCCESS, xrCreateActionSet(instance, &si, &set));
    XrActionCreateInfo ci{XR_TYPE_ACTION_CREATE_INFO};
    std::strcpy(ci.actionName, "select");
    std::strcpy(ci.localizedActionName, "Select");
    ci.actionType = XR_ACTION_TYPE_BOOLEAN_INPUT;
    ci.countSubactionPaths = 1;
    ci.subactionPaths = &right;
    XrAction select = XR_NULL_HANDLE;
    KIZAMU_ASSERT_XR(XR_SUCCESS, xrCreateAction(set, &ci, &select));
    XrActionSuggestedBinding b{select, path("/user/hand/right/input/select/click")};
    XrInteractionProfileSuggestedBinding sb{XR_TYPE_INTERACTION_PROFILE_SUGGESTED_BINDING};
    sb.interactionProfile = path("/interaction_profiles/khr/simple_controller");
    sb.countSuggestedBindings = 1;
    sb.suggestedBindings = &b;
    KIZAMU_ASSERT_XR(XR_SUCCESS, xrSuggestInteractionProfileBindings(instance, &sb));
    XrSessionActionSetsAttachInfo ai{XR_TYPE_SESSION_ACTION_SETS_ATTACH_INFO};
    ai.countActionSets = 1;
    ai.actionSets = &set;
    KIZAMU_ASSERT_XR(XR_SUCCESS, xrAttachSessionActionSets(session, &ai));

    const XrSwapchain sc = createSwapchain(GL_SRGB8_ALPHA8, 64, 32);
    uint32_t n = 0;
    KIZAMU_ASSERT_XR(XR_SUCCESS, xrEnumerateSwapchainImages(sc, 0, &n, nullptr));
    std::vector<XrSwapchainImageOpenGLKHR> images(n, {XR_TYPE_SWAPCHAIN_IMAGE_OPENGL_KHR});
    KIZAMU_ASSERT_XR(XR_SUCCESS,
                     xrEnumerateSwapchainImages(
                         sc, n, &n, reinterpret_cast<XrSwapchainImageBaseHeader*>(images.data())));

    bool exiting = false;
    bool running = false;
    for (int frame = 0; frame < 200 && !exiting; ++frame) {
        XrEventDataBuffer e{XR_TYPE_EVENT_DATA_BUFFER};
        while (xrPollEvent(instance, &e) == XR_SUCCESS) {
            if (e.type == XR_TYPE_EVENT_DATA_SESSION_STATE_CHANGED) {
                const auto state = reinterpret_cast<XrEventDataSessionStateChanged&>(e).state;
                if (state == XR_SESSION_STATE_READY) {
                    KIZAMU_ASSERT_XR(XR_SUCCESS, beginSession());
                    running = true;
                } else if (state == XR_SESSION_STATE_STOPPING) {
                    KIZAMU_ASSERT_XR(XR_SUCCESS, xrEndSession(session));
                    running = false;
                } else if (state == XR_SESSION_STATE_EXITING) {
                    exiting = true;
                }
            }
            e = XrEventDataBuffer{XR_TYPE_EVENT_DATA_BUFFER};
        }
        if (!running) continue;
        XrFrameState fs{XR_TYPE_FRAME_STATE};
        KIZAMU_ASSERT_XR(XR_SUCCESS, waitFrame(&fs));
        KIZAMU_ASSERT_XR(XR_SUCCESS, beginFrame());
        XrActiveActionSet active{set, XR_NULL_PATH};
        XrActionsSyncInfo sync{XR_TYPE_ACTIONS_SYNC_INFO};
        sync.countActiveActionSets = 1;
        sync.activeActionSets = &active;
        const XrResult synced = xrSyncActions(session, &sync);
        EXPECT_TRUE(synced == XR_SUCCESS || synced == XR_SESSION_NOT_FOCUSED);
        std::vector<const XrCompositionLayerBaseHeader*> layers;
        XrCompositionLayerProjectionView views[2] = {{XR_TYPE_COMPOSITION_LAYER_PROJECTION_VIEW},
                                                     {XR_TYPE_COMPOSITION_LAYER_PROJECTION_VIEW}};
        XrCompositionLayerProjection layer{XR_TYPE_COMPOSITION_LAYER_PROJECTION};
        if (fs.shouldRender) {
            XrViewLocateInfo li{XR_TYPE_VIEW_LOCATE_INFO};
            li.viewConfigurationType = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO;
            li.displayTime = fs.predictedDisplayTime;
            li.space = local;
            XrViewState vs{XR_TYPE_VIEW_STATE};
            XrView located[2] = {{XR_TYPE_VIEW}, {XR_TYPE_VIEW}};
            KIZAMU_ASSERT_XR(XR_SUCCESS, xrLocateViews(session, &li, &vs, 2, &n, located));
            uint32_t index = 0;
            KIZAMU_ASSERT_XR(XR_SUCCESS, xrAcquireSwapchainImage(sc, nullptr, &index));
            XrSwapchainImageWaitInfo wi{XR_TYPE_SWAPCHAIN_IMAGE_WAIT_INFO};
            wi.timeout = XR_INFINITE_DURATION;
            KIZAMU_ASSERT_XR(XR_SUCCESS, xrWaitSwapchainImage(sc, &wi));
            KIZAMU_ASSERT_XR(XR_SUCCESS, xrReleaseSwapchainImage(sc, nullptr));
            for (int eye = 0; eye < 2; ++eye) {
                views[eye].pose = located[eye].pose;
                views[eye].fov = located[eye].fov;
                views[eye].subImage.swapchain = sc;
                views[eye].subImage.imageRect = {{eye * 32, 0}, {32, 32}};
            }
            layer.space = local;
            layer.viewCount = 2;
            layer.views = views;
            layers.push_back(reinterpret_cast<const XrCompositionLayerBaseHeader*>(&layer));
        }
        KIZAMU_ASSERT_XR(XR_SUCCESS, endFrame(layers));
        if (frame == 10) {
            KIZAMU_ASSERT_XR(XR_SUCCESS, xrRequestExitSession(session));
        }
    }
    EXPECT_TRUE(exiting);
    EXPECT_GT(kizamuXrSimFramesEnded(), 5u);
    KIZAMU_ASSERT_XR(XR_SUCCESS, xrDestroySwapchain(sc));
    KIZAMU_ASSERT_XR(XR_SUCCESS, xrDestroySession(session));
    KIZAMU_ASSERT_XR(XR_SUCCESS, xrDestroyInstance(instance));
    instance = XR_NULL_HANDLE;
    const std::string text = report();
    EXPECT_EQ(text.find("Error"), std::string::npos) << text;
    EXPECT_EQ(text.find("VUID"), std::string::npos) << text;
}

/// The layer does report: an invalid structure type is in the file (so an empty report above
/// means no errors, not no output).
TEST_F(XrSimValidationTest, LayerReportsAnInvalidCall) {
    createInstance({kLayer});
    XrSystemProperties props{XR_TYPE_FRAME_STATE};
    EXPECT_NE(XR_SUCCESS, xrGetSystemProperties(instance, system, &props));
    KIZAMU_ASSERT_XR(XR_SUCCESS, xrDestroyInstance(instance));
    instance = XR_NULL_HANDLE;
    EXPECT_NE(report().find("VUID-XrSystemProperties-type-type"), std::string::npos) << report();
}

}  // namespace
}  // namespace kizamu::xrsim::test
