// SPDX-License-Identifier: Apache-2.0
#include "xr/headset_session.h"

#include "xr/xr_error.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <cstring>
#include <stdexcept>

namespace kizamu::xr {

namespace {

constexpr const char* kValidationLayer = "XR_APILAYER_LUNARG_core_validation";

/// The active runtime's manifest where the loader looks for it (XR_RUNTIME_JSON, then
/// active_runtime.json under the XDG configuration directories and /etc), or empty: asked
/// first, so a machine with no runtime gets one clear line instead of the loader's errors.
std::string activeRuntimeManifest() {
    namespace fs = std::filesystem;
    if (const char* json = std::getenv("XR_RUNTIME_JSON"); json && *json) return fs::exists(json) ? json : "";
    std::vector<fs::path> dirs;
    if (const char* home = std::getenv("XDG_CONFIG_HOME"); home && *home) dirs.emplace_back(home);
    else if (const char* h = std::getenv("HOME"); h && *h) dirs.push_back(fs::path(h) / ".config");
    const char* configDirs = std::getenv("XDG_CONFIG_DIRS");
    std::string list = configDirs && *configDirs ? configDirs : "/etc/xdg";
    for (std::size_t start = 0; start <= list.size();) {
        const std::size_t end = std::min(list.find(':', start), list.size());
        if (end > start) dirs.emplace_back(list.substr(start, end - start));
        start = end + 1;
    }
    dirs.emplace_back("/etc");
    for (const fs::path& d : dirs) {
        const fs::path manifest = d / "openxr" / "1" / "active_runtime.json";
        if (std::error_code ec; fs::exists(manifest, ec)) return manifest.string();
    }
    return {};
}

bool hasExtension(const char* name) {
    uint32_t count = 0;
    if (XR_FAILED(xrEnumerateInstanceExtensionProperties(nullptr, 0, &count, nullptr)))
        throw std::runtime_error("the OpenXR runtime did not load (the loader's messages above say why)");
    std::vector<XrExtensionProperties> props(count, {XR_TYPE_EXTENSION_PROPERTIES});
    if (XR_FAILED(xrEnumerateInstanceExtensionProperties(nullptr, count, &count, props.data()))) return false;
    return std::any_of(props.begin(), props.end(), [&](const XrExtensionProperties& p) { return std::strcmp(p.extensionName, name) == 0; });
}

bool hasLayer(const char* name) {
    uint32_t count = 0;
    if (XR_FAILED(xrEnumerateApiLayerProperties(0, &count, nullptr))) return false;
    std::vector<XrApiLayerProperties> props(count, {XR_TYPE_API_LAYER_PROPERTIES});
    if (XR_FAILED(xrEnumerateApiLayerProperties(count, &count, props.data()))) return false;
    return std::any_of(props.begin(), props.end(), [&](const XrApiLayerProperties& p) { return std::strcmp(p.layerName, name) == 0; });
}

/// The GLX objects behind the current context, as XR_KHR_opengl_enable's Xlib binding names them.
XrGraphicsBindingOpenGLXlibKHR glxBinding() {
    XrGraphicsBindingOpenGLXlibKHR b{XR_TYPE_GRAPHICS_BINDING_OPENGL_XLIB_KHR};
    b.xDisplay = glXGetCurrentDisplay();
    b.glxContext = glXGetCurrentContext();
    b.glxDrawable = glXGetCurrentDrawable();
    if (!b.xDisplay || !b.glxContext) throw std::runtime_error("the current OpenGL context is not a GLX context (OpenXR needs one)");
    int id = 0;
    glXQueryContext(b.xDisplay, b.glxContext, GLX_FBCONFIG_ID, &id);
    const int attributes[] = {GLX_FBCONFIG_ID, id, None};
    int n = 0;
    if (GLXFBConfig* configs = glXChooseFBConfig(b.xDisplay, DefaultScreen(b.xDisplay), attributes, &n)) {
        if (n > 0) {
            b.glxFBConfig = configs[0];
            if (XVisualInfo* visual = glXGetVisualFromFBConfig(b.xDisplay, configs[0])) {
                b.visualid = uint32_t(visual->visualid);
                XFree(visual);
            }
        }
        XFree(configs);
    }
    return b;
}

}  // namespace

HeadsetSession::HeadsetSession(const HeadsetOptions& options) : mPanelWidthM(options.panelWidthM) {
    if (activeRuntimeManifest().empty())
        throw std::runtime_error("no OpenXR runtime is installed (set XR_RUNTIME_JSON to a runtime's manifest, or install "
                                 "one, such as Monado or SteamVR)");
    std::vector<const char*> extensions{XR_KHR_OPENGL_ENABLE_EXTENSION_NAME};
    if (!hasExtension(XR_KHR_OPENGL_ENABLE_EXTENSION_NAME))
        throw std::runtime_error("the OpenXR runtime has no OpenGL support (XR_KHR_opengl_enable)");
    mAutomation = hasExtension(XR_EXT_CONFORMANCE_AUTOMATION_EXTENSION_NAME);
    if (mAutomation) extensions.push_back(XR_EXT_CONFORMANCE_AUTOMATION_EXTENSION_NAME);
    std::vector<const char*> layers;
    if (options.validation && hasLayer(kValidationLayer)) layers.push_back(kValidationLayer);

    XrInstanceCreateInfo ci{XR_TYPE_INSTANCE_CREATE_INFO};
    std::strncpy(ci.applicationInfo.applicationName, "Kizamu", XR_MAX_APPLICATION_NAME_SIZE - 1);
    ci.applicationInfo.applicationVersion = 1;
    std::strncpy(ci.applicationInfo.engineName, "Kizamu", XR_MAX_ENGINE_NAME_SIZE - 1);
    ci.applicationInfo.apiVersion = XR_MAKE_VERSION(1, 0, 0);
    ci.enabledExtensionCount = uint32_t(extensions.size());
    ci.enabledExtensionNames = extensions.data();
    ci.enabledApiLayerCount = uint32_t(layers.size());
    ci.enabledApiLayerNames = layers.data();
    check(XR_NULL_HANDLE, xrCreateInstance(&ci, &mInstance), "xrCreateInstance");

    try {
        XrInstanceProperties ip{XR_TYPE_INSTANCE_PROPERTIES};
        check(mInstance, xrGetInstanceProperties(mInstance, &ip), "xrGetInstanceProperties");
        mRuntimeName = std::string(ip.runtimeName) + " " + std::to_string(XR_VERSION_MAJOR(ip.runtimeVersion)) + "." +
                       std::to_string(XR_VERSION_MINOR(ip.runtimeVersion)) + "." + std::to_string(XR_VERSION_PATCH(ip.runtimeVersion));

        XrSystemGetInfo si{XR_TYPE_SYSTEM_GET_INFO};
        si.formFactor = XR_FORM_FACTOR_HEAD_MOUNTED_DISPLAY;
        check(mInstance, xrGetSystem(mInstance, &si, &mSystem), "xrGetSystem");

        PFN_xrGetOpenGLGraphicsRequirementsKHR requirements = nullptr;
        check(mInstance,
              xrGetInstanceProcAddr(mInstance, "xrGetOpenGLGraphicsRequirementsKHR", reinterpret_cast<PFN_xrVoidFunction*>(&requirements)),
              "xrGetInstanceProcAddr(xrGetOpenGLGraphicsRequirementsKHR)");
        XrGraphicsRequirementsOpenGLKHR req{XR_TYPE_GRAPHICS_REQUIREMENTS_OPENGL_KHR};
        check(mInstance, requirements(mInstance, mSystem, &req), "xrGetOpenGLGraphicsRequirementsKHR");
        GLint major = 0, minor = 0;
        glGetIntegerv(GL_MAJOR_VERSION, &major);
        glGetIntegerv(GL_MINOR_VERSION, &minor);
        if (XR_MAKE_VERSION(major, minor, 0) < req.minApiVersionSupported)
            throw std::runtime_error("the OpenXR runtime needs a newer OpenGL than this context's " + std::to_string(major) + "." +
                                     std::to_string(minor));

        const XrGraphicsBindingOpenGLXlibKHR binding = glxBinding();
        XrSessionCreateInfo sc{XR_TYPE_SESSION_CREATE_INFO};
        sc.next = &binding;
        sc.systemId = mSystem;
        check(mInstance, xrCreateSession(mInstance, &sc, &mSession), "xrCreateSession");

        // LOCAL: the seated origin where the session started, so the clay appears in front of the
        // artist wherever the room's floor is.
        uint32_t count = 0;
        XrReferenceSpaceCreateInfo rs{XR_TYPE_REFERENCE_SPACE_CREATE_INFO};
        rs.referenceSpaceType = XR_REFERENCE_SPACE_TYPE_LOCAL;
        rs.poseInReferenceSpace = toXr(Pose{});
        check(mInstance, xrCreateReferenceSpace(mSession, &rs, &mSpace), "xrCreateReferenceSpace");

        check(mInstance,
              xrEnumerateViewConfigurationViews(mInstance, mSystem, XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO, 0, &count, nullptr),
              "xrEnumerateViewConfigurationViews");
        std::vector<XrViewConfigurationView> views(count, {XR_TYPE_VIEW_CONFIGURATION_VIEW});
        check(mInstance,
              xrEnumerateViewConfigurationViews(mInstance, mSystem, XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO, count, &count,
                                                views.data()),
              "xrEnumerateViewConfigurationViews");
        if (count != 2) throw std::runtime_error("the OpenXR system's stereo view has " + std::to_string(count) + " views, not 2");
        for (std::size_t i = 0; i < 2; ++i) {
            mEyeSwapchains[i] = std::make_unique<ColourSwapchain>(mInstance, mSession, int(views[i].recommendedImageRectWidth),
                                                                  int(views[i].recommendedImageRectHeight));
            mEyes[i].size = mEyeSwapchains[i]->size();
            mViews[i] = {XR_TYPE_VIEW};
        }
        mPanel = std::make_unique<ColourSwapchain>(mInstance, mSession, options.panelWidth, options.panelHeight);
        // The panel floats to the left of where the clay first appears, turned towards the eye.
        panelPose.position = glm::dvec3(-0.32, -0.05, -0.42);
        panelPose.orientation = glm::angleAxis(0.6, glm::dvec3(0.0, 1.0, 0.0));
    } catch (...) {
        mEyeSwapchains = {};
        mPanel.reset();
        xrDestroyInstance(mInstance);  // destroys the session and spaces with it
        throw;
    }
}

HeadsetSession::~HeadsetSession() {
    mEyeSwapchains = {};
    mPanel.reset();
    if (mSpace != XR_NULL_HANDLE) xrDestroySpace(mSpace);
    if (mSession != XR_NULL_HANDLE) xrDestroySession(mSession);
    if (mInstance != XR_NULL_HANDLE) xrDestroyInstance(mInstance);
}

glm::dvec2 HeadsetSession::panelSizeM() const {
    const glm::ivec2 px = mPanel->size();
    return {mPanelWidthM, mPanelWidthM * double(px.y) / double(px.x)};
}

void HeadsetSession::requestExit() {
    if (mRunning) xrRequestExitSession(mSession);
}

void HeadsetSession::handleStateChange(XrSessionState next) {
    mState = next;
    if (next == XR_SESSION_STATE_READY) {
        XrSessionBeginInfo bi{XR_TYPE_SESSION_BEGIN_INFO};
        bi.primaryViewConfigurationType = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO;
        check(mInstance, xrBeginSession(mSession, &bi), "xrBeginSession");
        mRunning = true;
    } else if (next == XR_SESSION_STATE_STOPPING) {
        mRunning = false;
        check(mInstance, xrEndSession(mSession), "xrEndSession");
    } else if (next == XR_SESSION_STATE_EXITING || next == XR_SESSION_STATE_LOSS_PENDING) {
        mRunning = false;
        mExited = true;
    }
}

bool HeadsetSession::pollEvents() {
    for (;;) {
        XrEventDataBuffer event{XR_TYPE_EVENT_DATA_BUFFER};
        const XrResult r = xrPollEvent(mInstance, &event);
        if (r == XR_EVENT_UNAVAILABLE) break;
        check(mInstance, r, "xrPollEvent");
        if (event.type == XR_TYPE_EVENT_DATA_SESSION_STATE_CHANGED) {
            handleStateChange(reinterpret_cast<const XrEventDataSessionStateChanged&>(event).state);
        } else if (event.type == XR_TYPE_EVENT_DATA_INSTANCE_LOSS_PENDING) {
            mRunning = false;
            mExited = true;
        }
    }
    return !mExited;
}

FrameTiming HeadsetSession::beginFrame() {
    XrFrameWaitInfo wi{XR_TYPE_FRAME_WAIT_INFO};
    XrFrameState fs{XR_TYPE_FRAME_STATE};
    check(mInstance, xrWaitFrame(mSession, &wi, &fs), "xrWaitFrame");
    XrFrameBeginInfo bi{XR_TYPE_FRAME_BEGIN_INFO};
    check(mInstance, xrBeginFrame(mSession, &bi), "xrBeginFrame");
    mFrame.displayTime = fs.predictedDisplayTime;
    mFrame.displayPeriod = fs.predictedDisplayPeriod;
    mFrame.shouldRender = fs.shouldRender == XR_TRUE;
    if (!mFrame.shouldRender) return mFrame;

    XrViewLocateInfo li{XR_TYPE_VIEW_LOCATE_INFO};
    li.viewConfigurationType = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO;
    li.displayTime = fs.predictedDisplayTime;
    li.space = mSpace;
    XrViewState vs{XR_TYPE_VIEW_STATE};
    uint32_t count = 0;
    check(mInstance, xrLocateViews(mSession, &li, &vs, 2, &count, mViews.data()), "xrLocateViews");
    const bool located = (vs.viewStateFlags & XR_VIEW_STATE_POSITION_VALID_BIT) && (vs.viewStateFlags & XR_VIEW_STATE_ORIENTATION_VALID_BIT);
    if (!located || count != 2) {
        mFrame.shouldRender = false;  // no head pose: nothing can be drawn where it belongs
        return mFrame;
    }
    for (std::size_t i = 0; i < 2; ++i) {
        mEyes[i].pose = fromXr(mViews[i].pose);
        mEyes[i].view = viewMatrix(mEyes[i].pose);
        mEyes[i].projection = projectionMatrix(mViews[i].fov, 0.02f, 20.0f);
    }
    return mFrame;
}

void HeadsetSession::endFrame(bool showPanel) {
    std::array<XrCompositionLayerProjectionView, 2> views{};
    for (std::size_t i = 0; i < 2; ++i) {
        views[i] = {XR_TYPE_COMPOSITION_LAYER_PROJECTION_VIEW};
        views[i].pose = mViews[i].pose;
        views[i].fov = mViews[i].fov;
        views[i].subImage.swapchain = mEyeSwapchains[i]->handle();
        views[i].subImage.imageRect = {{0, 0}, {mEyes[i].size.x, mEyes[i].size.y}};
    }
    XrCompositionLayerProjection projection{XR_TYPE_COMPOSITION_LAYER_PROJECTION};
    projection.space = mSpace;
    projection.viewCount = 2;
    projection.views = views.data();
    XrCompositionLayerQuad quad{XR_TYPE_COMPOSITION_LAYER_QUAD};
    quad.layerFlags = XR_COMPOSITION_LAYER_BLEND_TEXTURE_SOURCE_ALPHA_BIT;
    quad.space = mSpace;
    quad.eyeVisibility = XR_EYE_VISIBILITY_BOTH;
    quad.subImage.swapchain = mPanel->handle();
    quad.subImage.imageRect = {{0, 0}, {mPanel->size().x, mPanel->size().y}};
    quad.pose = toXr(panelPose);
    const glm::dvec2 sizeM = panelSizeM();
    quad.size = {float(sizeM.x), float(sizeM.y)};
    std::array<const XrCompositionLayerBaseHeader*, 2> layers{};
    uint32_t layerCount = 0;
    if (mFrame.shouldRender) {
        layers[layerCount++] = reinterpret_cast<const XrCompositionLayerBaseHeader*>(&projection);
        if (showPanel) layers[layerCount++] = reinterpret_cast<const XrCompositionLayerBaseHeader*>(&quad);
    }
    XrFrameEndInfo ei{XR_TYPE_FRAME_END_INFO};
    ei.displayTime = mFrame.displayTime;
    ei.environmentBlendMode = XR_ENVIRONMENT_BLEND_MODE_OPAQUE;
    ei.layerCount = layerCount;
    ei.layers = layers.data();
    check(mInstance, xrEndFrame(mSession, &ei), "xrEndFrame");
}

}  // namespace kizamu::xr
