// SPDX-License-Identifier: Apache-2.0
/// @file frame_test.cpp
/// @brief The frame loop and swapchain rules, the read-back of projection views (a clear colour
/// rendered into a swapchain image through an FBO) in an EGL and in a GLX context, views and
/// spaces, and the capture files. The GLX case needs an X display ($DISPLAY; scripts/test starts
/// Xvfb): without one it skips, unless KIZAMU_REQUIRE_DISPLAY is set, when it fails.
#include "tests/unit/xrsim/xrsim_fixture.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <tuple>

#include <unistd.h>

namespace kizamu::xrsim::test {
namespace {

/// A rectangle of a swapchain image (GL's origin: bottom left) cleared to a colour, in the
/// image's texture (layer -1) or in one layer of a texture array.
struct Fill {
    int x, y, width, height;
    float rgba[4];
    int layer = -1;
};

/// Acquires, waits, clears each of `fills` through an FBO, and releases.
void renderInto(XrSwapchain sc, const std::vector<XrSwapchainImageOpenGLKHR>& images,
                const std::vector<Fill>& fills) {
    uint32_t index = 0;
    ASSERT_EQ(XR_SUCCESS, xrAcquireSwapchainImage(sc, nullptr, &index));
    XrSwapchainImageWaitInfo wi{XR_TYPE_SWAPCHAIN_IMAGE_WAIT_INFO};
    wi.timeout = XR_INFINITE_DURATION;
    ASSERT_EQ(XR_SUCCESS, xrWaitSwapchainImage(sc, &wi));
    GLuint fbo = 0;
    glGenFramebuffers(1, &fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glEnable(GL_SCISSOR_TEST);
    for (const Fill& f : fills) {
        if (f.layer < 0)
            glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D,
                                   images[index].image, 0);
        else
            glFramebufferTextureLayer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, images[index].image, 0,
                                      f.layer);
        EXPECT_EQ(glCheckFramebufferStatus(GL_FRAMEBUFFER), GLenum(GL_FRAMEBUFFER_COMPLETE));
        glScissor(f.x, f.y, f.width, f.height);
        glClearColor(f.rgba[0], f.rgba[1], f.rgba[2], f.rgba[3]);
        glClear(GL_COLOR_BUFFER_BIT);
    }
    glDisable(GL_SCISSOR_TEST);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glDeleteFramebuffers(1, &fbo);
    ASSERT_EQ(XR_SUCCESS, xrReleaseSwapchainImage(sc, nullptr));
}

std::vector<XrSwapchainImageOpenGLKHR> images(XrSwapchain sc) {
    uint32_t n = 0;
    EXPECT_EQ(XR_SUCCESS, xrEnumerateSwapchainImages(sc, 0, &n, nullptr));
    std::vector<XrSwapchainImageOpenGLKHR> out(n, {XR_TYPE_SWAPCHAIN_IMAGE_OPENGL_KHR});
    EXPECT_EQ(XR_SUCCESS,
              xrEnumerateSwapchainImages(
                  sc, n, &n, reinterpret_cast<XrSwapchainImageBaseHeader*>(out.data())));
    return out;
}

/// A projection layer of two views side by side in one swapchain (each eye w x h).
struct Projection {
    XrCompositionLayerProjectionView views[2];
    XrCompositionLayerProjection layer{XR_TYPE_COMPOSITION_LAYER_PROJECTION};
    Projection(XrSpace space, XrSwapchain sc, int w, int h) {
        for (int eye = 0; eye < 2; ++eye) {
            views[eye] = {XR_TYPE_COMPOSITION_LAYER_PROJECTION_VIEW};
            views[eye].pose.orientation.w = 1.0f;
            views[eye].fov = {-0.78f, 0.78f, 0.78f, -0.78f};
            views[eye].subImage.swapchain = sc;
            views[eye].subImage.imageRect = {{eye * w, 0}, {w, h}};
        }
        layer.space = space;
        layer.viewCount = 2;
        layer.views = views;
    }
    const XrCompositionLayerBaseHeader* header() const {
        return reinterpret_cast<const XrCompositionLayerBaseHeader*>(&layer);
    }
};

TEST_F(XrSimTest, FrameLoopOrderIsEnforced) {
    createInstance();
    createSession();
    KIZAMU_ASSERT_XR(XR_SUCCESS, beginSession());
    KIZAMU_EXPECT_XR(XR_ERROR_CALL_ORDER_INVALID, beginFrame());
    KIZAMU_EXPECT_XR(XR_ERROR_CALL_ORDER_INVALID, endFrame());
    KIZAMU_ASSERT_XR(XR_SUCCESS, waitFrame());
    KIZAMU_ASSERT_XR(XR_SUCCESS, beginFrame());
    KIZAMU_ASSERT_XR(XR_SUCCESS, waitFrame());
    KIZAMU_EXPECT_XR(XR_FRAME_DISCARDED, beginFrame());
    KIZAMU_EXPECT_XR(XR_SUCCESS, endFrame());
    KIZAMU_EXPECT_XR(XR_ERROR_CALL_ORDER_INVALID, endFrame());
}

TEST_F(XrSimTest, SwapchainOrderIsEnforced) {
    runToFocused();
    uint32_t n = 0;
    KIZAMU_ASSERT_XR(XR_SUCCESS, xrEnumerateSwapchainFormats(session, 0, &n, nullptr));
    std::vector<int64_t> formats(n);
    KIZAMU_ASSERT_XR(XR_SUCCESS, xrEnumerateSwapchainFormats(session, n, &n, formats.data()));
    ASSERT_EQ(formats, (std::vector<int64_t>{GL_SRGB8_ALPHA8, GL_RGBA8}));
    const XrSwapchain sc = createSwapchain(GL_SRGB8_ALPHA8, 32, 32);
    EXPECT_EQ(images(sc).size(), 3u);
    XrSwapchainImageWaitInfo wi{XR_TYPE_SWAPCHAIN_IMAGE_WAIT_INFO};
    wi.timeout = XR_INFINITE_DURATION;
    KIZAMU_EXPECT_XR(XR_ERROR_CALL_ORDER_INVALID, xrWaitSwapchainImage(sc, &wi));
    uint32_t index = 0;
    KIZAMU_ASSERT_XR(XR_SUCCESS, xrAcquireSwapchainImage(sc, nullptr, &index));
    EXPECT_EQ(index, 0u);
    KIZAMU_EXPECT_XR(XR_ERROR_CALL_ORDER_INVALID, xrReleaseSwapchainImage(sc, nullptr));
    KIZAMU_ASSERT_XR(XR_SUCCESS, xrAcquireSwapchainImage(sc, nullptr, &index));
    KIZAMU_ASSERT_XR(XR_SUCCESS, xrAcquireSwapchainImage(sc, nullptr, &index));
    EXPECT_EQ(index, 2u);
    KIZAMU_EXPECT_XR(XR_ERROR_CALL_ORDER_INVALID, xrAcquireSwapchainImage(sc, nullptr, &index));
    KIZAMU_ASSERT_XR(XR_SUCCESS, xrWaitSwapchainImage(sc, &wi));
    KIZAMU_ASSERT_XR(XR_SUCCESS, xrReleaseSwapchainImage(sc, nullptr));
    KIZAMU_ASSERT_XR(XR_SUCCESS, xrAcquireSwapchainImage(sc, nullptr, &index));
    EXPECT_EQ(index, 0u);

    XrSwapchainCreateInfo ci{XR_TYPE_SWAPCHAIN_CREATE_INFO};
    ci.format = GL_RGB8;
    ci.sampleCount = ci.faceCount = ci.arraySize = ci.mipCount = 1;
    ci.width = ci.height = 16;
    XrSwapchain bad = XR_NULL_HANDLE;
    KIZAMU_EXPECT_XR(XR_ERROR_SWAPCHAIN_FORMAT_UNSUPPORTED, xrCreateSwapchain(session, &ci, &bad));
    KIZAMU_ASSERT_XR(XR_SUCCESS, xrDestroySwapchain(sc));
    KIZAMU_EXPECT_XR(XR_ERROR_HANDLE_INVALID, xrAcquireSwapchainImage(sc, nullptr, &index));
}

TEST_F(XrSimTest, LayerWithoutAReleasedImageIsInvalid) {
    runToFocused();
    const XrSwapchain sc = createSwapchain(GL_RGBA8, 64, 32);
    const Projection p(local, sc, 32, 32);
    KIZAMU_ASSERT_XR(XR_SUCCESS, waitFrame());
    KIZAMU_ASSERT_XR(XR_SUCCESS, beginFrame());
    KIZAMU_EXPECT_XR(XR_ERROR_LAYER_INVALID, endFrame({p.header()}));
    renderInto(sc, images(sc), {{0, 0, 64, 32, {0.5f, 0.5f, 0.5f, 1.0f}}});
    Projection outside(local, sc, 40, 32);
    KIZAMU_EXPECT_XR(XR_ERROR_SWAPCHAIN_RECT_INVALID, endFrame({outside.header()}));
    KIZAMU_EXPECT_XR(XR_SUCCESS, endFrame({p.header()}));
}

TEST_F(XrSimTest, SubmittedViewsAreReadBackTopRowFirst) {
    runToFocused();
    const std::vector<int64_t> formats = {GL_SRGB8_ALPHA8, GL_RGBA8};
    for (int64_t format : formats) {
        kizamuXrSimReset();
        const XrSwapchain sc = createSwapchain(format, 64, 32);
        const auto imgs = images(sc);
        KIZAMU_ASSERT_XR(XR_SUCCESS, waitFrame());
        KIZAMU_ASSERT_XR(XR_SUCCESS, beginFrame());
        // Left eye red over green (GL's y grows upwards), right eye blue, all in one image.
        renderInto(sc, imgs,
                   {{0, 16, 32, 16, {1, 0, 0, 1}},
                    {0, 0, 32, 16, {0, 1, 0, 1}},
                    {32, 0, 32, 32, {0, 0, 1, 1}}});
        const Projection p(local, sc, 32, 32);
        KIZAMU_ASSERT_XR(XR_SUCCESS, endFrame({p.header()}));

        int w = 0, h = 0;
        const unsigned char* rgba = nullptr;
        ASSERT_EQ(kizamuXrSimLastView(0, &w, &h, &rgba), 0);
        ASSERT_EQ(w, 32);
        ASSERT_EQ(h, 32);
        auto at = [&](int x, int y) {
            const unsigned char* q = rgba + (static_cast<size_t>(y) * w + x) * 4;
            return std::tuple{int(q[0]), int(q[1]), int(q[2]), int(q[3])};
        };
        EXPECT_EQ(at(0, 0), std::tuple(255, 0, 0, 255)) << "format " << format;
        EXPECT_EQ(at(31, 31), std::tuple(0, 255, 0, 255)) << "format " << format;
        ASSERT_EQ(kizamuXrSimLastView(1, &w, &h, &rgba), 0);
        EXPECT_EQ(at(5, 5), std::tuple(0, 0, 255, 255)) << "format " << format;
        KIZAMU_ASSERT_XR(XR_SUCCESS, xrDestroySwapchain(sc));
    }
    EXPECT_EQ(kizamuXrSimLastView(2, nullptr, nullptr, nullptr), 2);
}

TEST_F(XrSimTest, ArraySwapchainViewsAreReadFromTheirLayers) {
    runToFocused();
    XrSwapchainCreateInfo ci{XR_TYPE_SWAPCHAIN_CREATE_INFO};
    ci.usageFlags = XR_SWAPCHAIN_USAGE_COLOR_ATTACHMENT_BIT;
    ci.format = GL_RGBA8;
    ci.sampleCount = ci.faceCount = ci.mipCount = 1;
    ci.arraySize = 2;
    ci.width = ci.height = 8;
    XrSwapchain sc = XR_NULL_HANDLE;
    KIZAMU_ASSERT_XR(XR_SUCCESS, xrCreateSwapchain(session, &ci, &sc));
    const auto imgs = images(sc);
    KIZAMU_ASSERT_XR(XR_SUCCESS, waitFrame());
    KIZAMU_ASSERT_XR(XR_SUCCESS, beginFrame());
    renderInto(sc, imgs, {{0, 0, 8, 8, {1, 0, 0, 1}, 0}, {0, 0, 8, 8, {0, 0, 1, 1}, 1}});
    Projection p(local, sc, 8, 8);
    p.views[1].subImage.imageRect.offset.x = 0;
    p.views[1].subImage.imageArrayIndex = 1;
    KIZAMU_ASSERT_XR(XR_SUCCESS, endFrame({p.header()}));
    int w = 0, h = 0;
    const unsigned char* px = nullptr;
    ASSERT_EQ(kizamuXrSimLastView(0, &w, &h, &px), 0);
    EXPECT_EQ(std::tuple(px[0], px[2]), std::tuple(255, 0));
    ASSERT_EQ(kizamuXrSimLastView(1, &w, &h, &px), 0);
    EXPECT_EQ(std::tuple(px[0], px[2]), std::tuple(0, 255));
}

TEST_F(XrSimTest, GlxContextOfTheApplicationWorksToo) {
    if (std::getenv("DISPLAY") == nullptr) {
        if (std::getenv("KIZAMU_REQUIRE_DISPLAY"))
            FAIL() << "no DISPLAY, and KIZAMU_REQUIRE_DISPLAY is set";
        GTEST_SKIP() << "no display";
    }
    mGl.reset();  // only the GLX context is current from here on
    Display* display = XOpenDisplay(nullptr);
    ASSERT_NE(display, nullptr);
    const int fbAttribs[] = {GLX_DRAWABLE_TYPE,
                             GLX_PBUFFER_BIT,
                             GLX_RENDER_TYPE,
                             GLX_RGBA_BIT,
                             GLX_RED_SIZE,
                             8,
                             GLX_GREEN_SIZE,
                             8,
                             GLX_BLUE_SIZE,
                             8,
                             None};
    int count = 0;
    GLXFBConfig* configs = glXChooseFBConfig(display, DefaultScreen(display), fbAttribs, &count);
    ASSERT_TRUE(configs != nullptr && count > 0);
    const int contextAttribs[] = {GLX_CONTEXT_MAJOR_VERSION_ARB,
                                  3,
                                  GLX_CONTEXT_MINOR_VERSION_ARB,
                                  3,
                                  GLX_CONTEXT_PROFILE_MASK_ARB,
                                  GLX_CONTEXT_CORE_PROFILE_BIT_ARB,
                                  None};
    GLXContext context =
        glXCreateContextAttribsARB(display, configs[0], nullptr, True, contextAttribs);
    ASSERT_NE(context, nullptr);
    const int pbufferAttribs[] = {GLX_PBUFFER_WIDTH, 16, GLX_PBUFFER_HEIGHT, 16, None};
    const GLXPbuffer pbuffer = glXCreatePbuffer(display, configs[0], pbufferAttribs);
    ASSERT_TRUE(glXMakeContextCurrent(display, pbuffer, pbuffer, context));
    binding.xDisplay = display;
    binding.glxFBConfig = configs[0];
    binding.glxDrawable = pbuffer;
    binding.glxContext = context;

    runToFocused();
    const XrSwapchain sc = createSwapchain(GL_RGBA8, 32, 16);
    KIZAMU_ASSERT_XR(XR_SUCCESS, waitFrame());
    KIZAMU_ASSERT_XR(XR_SUCCESS, beginFrame());
    renderInto(sc, images(sc), {{0, 0, 16, 16, {0.0f, 1.0f, 0.0f, 1.0f}}});
    const Projection p(local, sc, 16, 16);
    KIZAMU_ASSERT_XR(XR_SUCCESS, endFrame({p.header()}));
    int w = 0, h = 0;
    const unsigned char* px = nullptr;
    ASSERT_EQ(kizamuXrSimLastView(0, &w, &h, &px), 0);
    EXPECT_EQ(std::tuple(px[0], px[1], px[2], px[3]), std::tuple(0, 255, 0, 255));
    KIZAMU_EXPECT_XR(XR_SUCCESS, xrDestroyInstance(instance));
    instance = XR_NULL_HANDLE;

    glXMakeContextCurrent(display, None, None, nullptr);
    glXDestroyPbuffer(display, pbuffer);
    glXDestroyContext(display, context);
    XFree(configs);
    XCloseDisplay(display);
}

TEST_F(XrSimTest, ViewsAreEyesEitherSideOfTheHead) {
    runToFocused();
    XrViewLocateInfo li{XR_TYPE_VIEW_LOCATE_INFO};
    li.viewConfigurationType = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO;
    li.displayTime = lastDisplayTime;
    li.space = local;
    XrViewState vs{XR_TYPE_VIEW_STATE};
    XrView views[2] = {{XR_TYPE_VIEW}, {XR_TYPE_VIEW}};
    uint32_t n = 0;
    KIZAMU_ASSERT_XR(XR_SUCCESS, xrLocateViews(session, &li, &vs, 2, &n, views));
    ASSERT_EQ(n, 2u);
    EXPECT_FLOAT_EQ(views[0].pose.position.x, -0.032f);
    EXPECT_FLOAT_EQ(views[1].pose.position.x, 0.032f);
    EXPECT_FLOAT_EQ(views[0].pose.orientation.w, 1.0f);
    EXPECT_NEAR(views[0].fov.angleLeft, -0.7853982f, 1e-6);
    EXPECT_NEAR(views[1].fov.angleUp, 0.7853982f, 1e-6);
    EXPECT_TRUE(vs.viewStateFlags & XR_VIEW_STATE_POSITION_VALID_BIT);

    // The head moved up 1.5 m: the VIEW space sits there in LOCAL.
    const float up[3] = {0.0f, 1.5f, 0.0f}, identity[4] = {0, 0, 0, 1};
    kizamuXrSimSetHeadPose(up, identity);
    XrReferenceSpaceCreateInfo si{XR_TYPE_REFERENCE_SPACE_CREATE_INFO};
    si.referenceSpaceType = XR_REFERENCE_SPACE_TYPE_VIEW;
    si.poseInReferenceSpace.orientation.w = 1.0f;
    XrSpace view = XR_NULL_HANDLE;
    KIZAMU_ASSERT_XR(XR_SUCCESS, xrCreateReferenceSpace(session, &si, &view));
    XrSpaceLocation loc{XR_TYPE_SPACE_LOCATION};
    KIZAMU_ASSERT_XR(XR_SUCCESS, xrLocateSpace(view, local, lastDisplayTime, &loc));
    EXPECT_FLOAT_EQ(loc.pose.position.y, 1.5f);
    si.referenceSpaceType = XR_REFERENCE_SPACE_TYPE_UNBOUNDED_MSFT;
    KIZAMU_EXPECT_XR(XR_ERROR_REFERENCE_SPACE_UNSUPPORTED,
                     xrCreateReferenceSpace(session, &si, &view));
}

TEST_F(XrSimTest, CaptureWritesEventsAndViewPngs) {
    const std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                      ("kizamu_xrsim_capture_" + std::to_string(getpid()));
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    setenv("KIZAMU_XRSIM_CAPTURE", dir.c_str(), 1);
    runToFocused();
    unsetenv("KIZAMU_XRSIM_CAPTURE");
    const XrSwapchain sc = createSwapchain(GL_RGBA8, 32, 16);
    for (int frame = 0; frame < 90; ++frame) {
        KIZAMU_ASSERT_XR(XR_SUCCESS, waitFrame());
        KIZAMU_ASSERT_XR(XR_SUCCESS, beginFrame());
        renderInto(sc, images(sc), {{0, 0, 32, 16, {0.5f, 0.5f, 0.5f, 1.0f}}});
        const Projection p(local, sc, 16, 16);
        KIZAMU_ASSERT_XR(XR_SUCCESS, endFrame({p.header()}));
    }
    KIZAMU_ASSERT_XR(XR_SUCCESS, xrDestroySession(session));
    EXPECT_TRUE(std::filesystem::file_size(dir / "left.png") > 0);
    EXPECT_TRUE(std::filesystem::file_size(dir / "right.png") > 0);
    std::ifstream events(dir / "events.jsonl");
    std::stringstream all;
    all << events.rdbuf();
    EXPECT_NE(all.str().find("{\"event\":\"state\",\"state\":\"FOCUSED\",\"time\":1000000000}"),
              std::string::npos)
        << all.str();
    EXPECT_NE(all.str().find("{\"event\":\"frame\",\"n\":90,"), std::string::npos) << all.str();
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace kizamu::xrsim::test
