// SPDX-License-Identifier: Apache-2.0
/// @file system.cpp
/// @brief The one HMD system: properties, the PRIMARY_STEREO view configuration (recommended eye
/// size $KIZAMU_XRSIM_EYE_SIZE=WxH, 640x640 by default), OPAQUE blending and the OpenGL
/// requirements of XR_KHR_opengl_enable.
#include "sim/openxr/entry_points.h"
#include "sim/openxr/runtime_state.h"

#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace kizamu::xrsim {
namespace {

/// The recommended eye size: $KIZAMU_XRSIM_EYE_SIZE when it reads "WxH" within 1..4096, else
/// 640x640.
void eyeSize(uint32_t* width, uint32_t* height) {
    *width = *height = 640;
    const char* env = std::getenv("KIZAMU_XRSIM_EYE_SIZE");
    unsigned w = 0, h = 0;
    if (env != nullptr && std::sscanf(env, "%ux%u", &w, &h) == 2 && w >= 1 && h >= 1 &&
        w <= kMaxImageSize && h <= kMaxImageSize) {
        *width = w;
        *height = h;
    }
}

/// XR_ERROR_HANDLE_INVALID or XR_ERROR_SYSTEM_INVALID, else XR_SUCCESS.
XrResult checkSystem(Runtime& rt, XrInstance instance, XrSystemId systemId) {
    if (rt.find<InstanceObject>(instance) == nullptr) return XR_ERROR_HANDLE_INVALID;
    return systemId == kSystemId ? XR_SUCCESS : XR_ERROR_SYSTEM_INVALID;
}

}  // namespace

/// XR_ERROR_FORM_FACTOR_UNSUPPORTED for anything but a head-mounted display.
XrResult xrGetSystem(XrInstance instance, const XrSystemGetInfo* getInfo, XrSystemId* systemId) {
    Runtime& rt = runtime();
    std::lock_guard lock(rt.mutex);
    if (rt.find<InstanceObject>(instance) == nullptr) return XR_ERROR_HANDLE_INVALID;
    if (getInfo->formFactor != XR_FORM_FACTOR_HEAD_MOUNTED_DISPLAY)
        return XR_ERROR_FORM_FACTOR_UNSUPPORTED;
    *systemId = kSystemId;
    return XR_SUCCESS;
}

XrResult xrGetSystemProperties(XrInstance instance, XrSystemId systemId,
                               XrSystemProperties* properties) {
    Runtime& rt = runtime();
    std::lock_guard lock(rt.mutex);
    if (const XrResult r = checkSystem(rt, instance, systemId); r != XR_SUCCESS) return r;
    properties->systemId = kSystemId;
    properties->vendorId = 0;
    std::strncpy(properties->systemName, "Kizamu simulated HMD", XR_MAX_SYSTEM_NAME_SIZE);
    properties->graphicsProperties.maxSwapchainImageWidth = kMaxImageSize;
    properties->graphicsProperties.maxSwapchainImageHeight = kMaxImageSize;
    properties->graphicsProperties.maxLayerCount = kMaxLayers;
    properties->trackingProperties.orientationTracking = XR_TRUE;
    properties->trackingProperties.positionTracking = XR_TRUE;
    return XR_SUCCESS;
}

/// XR_ERROR_VIEW_CONFIGURATION_TYPE_UNSUPPORTED for anything but PRIMARY_STEREO.
XrResult xrEnumerateEnvironmentBlendModes(XrInstance instance, XrSystemId systemId,
                                          XrViewConfigurationType viewConfigurationType,
                                          uint32_t environmentBlendModeCapacityInput,
                                          uint32_t* environmentBlendModeCountOutput,
                                          XrEnvironmentBlendMode* environmentBlendModes) {
    Runtime& rt = runtime();
    std::lock_guard lock(rt.mutex);
    if (const XrResult r = checkSystem(rt, instance, systemId); r != XR_SUCCESS) return r;
    if (viewConfigurationType != XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO)
        return XR_ERROR_VIEW_CONFIGURATION_TYPE_UNSUPPORTED;
    return twoCall(environmentBlendModeCapacityInput, environmentBlendModeCountOutput, 1,
                   [&](uint32_t) { environmentBlendModes[0] = XR_ENVIRONMENT_BLEND_MODE_OPAQUE; });
}

XrResult xrEnumerateViewConfigurations(XrInstance instance, XrSystemId systemId,
                                       uint32_t viewConfigurationTypeCapacityInput,
                                       uint32_t* viewConfigurationTypeCountOutput,
                                       XrViewConfigurationType* viewConfigurationTypes) {
    Runtime& rt = runtime();
    std::lock_guard lock(rt.mutex);
    if (const XrResult r = checkSystem(rt, instance, systemId); r != XR_SUCCESS) return r;
    return twoCall(
        viewConfigurationTypeCapacityInput, viewConfigurationTypeCountOutput, 1,
        [&](uint32_t) { viewConfigurationTypes[0] = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO; });
}

/// XR_ERROR_VIEW_CONFIGURATION_TYPE_UNSUPPORTED for anything but PRIMARY_STEREO.
XrResult xrGetViewConfigurationProperties(XrInstance instance, XrSystemId systemId,
                                          XrViewConfigurationType viewConfigurationType,
                                          XrViewConfigurationProperties* configurationProperties) {
    Runtime& rt = runtime();
    std::lock_guard lock(rt.mutex);
    if (const XrResult r = checkSystem(rt, instance, systemId); r != XR_SUCCESS) return r;
    if (viewConfigurationType != XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO)
        return XR_ERROR_VIEW_CONFIGURATION_TYPE_UNSUPPORTED;
    configurationProperties->viewConfigurationType = viewConfigurationType;
    configurationProperties->fovMutable = XR_TRUE;
    return XR_SUCCESS;
}

/// Two views of the recommended eye size; XR_ERROR_VIEW_CONFIGURATION_TYPE_UNSUPPORTED for
/// anything but PRIMARY_STEREO.
XrResult xrEnumerateViewConfigurationViews(XrInstance instance, XrSystemId systemId,
                                           XrViewConfigurationType viewConfigurationType,
                                           uint32_t viewCapacityInput, uint32_t* viewCountOutput,
                                           XrViewConfigurationView* views) {
    Runtime& rt = runtime();
    std::lock_guard lock(rt.mutex);
    if (const XrResult r = checkSystem(rt, instance, systemId); r != XR_SUCCESS) return r;
    if (viewConfigurationType != XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO)
        return XR_ERROR_VIEW_CONFIGURATION_TYPE_UNSUPPORTED;
    uint32_t w = 0, h = 0;
    eyeSize(&w, &h);
    return twoCall(viewCapacityInput, viewCountOutput, 2, [&](uint32_t i) {
        views[i].recommendedImageRectWidth = w;
        views[i].recommendedImageRectHeight = h;
        views[i].maxImageRectWidth = kMaxImageSize;
        views[i].maxImageRectHeight = kMaxImageSize;
        views[i].recommendedSwapchainSampleCount = 1;
        views[i].maxSwapchainSampleCount = 1;
    });
}

/// OpenGL 3.3 to 4.6. Calling it is what xrCreateSession requires first (the spec's
/// XR_ERROR_GRAPHICS_REQUIREMENTS_CALL_MISSING).
XrResult xrGetOpenGLGraphicsRequirementsKHR(XrInstance instance, XrSystemId systemId,
                                            XrGraphicsRequirementsOpenGLKHR* graphicsRequirements) {
    Runtime& rt = runtime();
    std::lock_guard lock(rt.mutex);
    if (const XrResult r = checkSystem(rt, instance, systemId); r != XR_SUCCESS) return r;
    graphicsRequirements->minApiVersionSupported = XR_MAKE_VERSION(3, 3, 0);
    graphicsRequirements->maxApiVersionSupported = XR_MAKE_VERSION(4, 6, 0);
    rt.find<InstanceObject>(instance)->glRequirementsQueried = true;
    return XR_SUCCESS;
}

}  // namespace kizamu::xrsim
