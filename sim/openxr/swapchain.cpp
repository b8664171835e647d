// SPDX-License-Identifier: Apache-2.0
/// @file swapchain.cpp
/// @brief GL swapchains: formats, three texture images each, and the acquire → wait → release
/// order the spec requires.
#include "sim/openxr/entry_points.h"
#include "sim/openxr/gl_objects.h"
#include "sim/openxr/runtime_state.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <iterator>

namespace kizamu::xrsim {
namespace {

/// Supported formats, preferred first.
const int64_t kFormats[] = {GL_SRGB8_ALPHA8, GL_RGBA8};

/// Runs `body(swapchain)` under the runtime's lock for a live swapchain of a live session
/// (XR_ERROR_HANDLE_INVALID, XR_ERROR_SESSION_LOST otherwise).
template <class Body>
XrResult onSwapchain(XrSwapchain handle, Body&& body) {
    Runtime& rt = runtime();
    std::lock_guard lock(rt.mutex);
    SwapchainObject* sc = nullptr;
    SessionObject* s = nullptr;
    if (const XrResult r = findSessionChild(rt, handle, &sc, &s); r != XR_SUCCESS) return r;
    return body(*sc);
}

}  // namespace

XrResult xrEnumerateSwapchainFormats(XrSession session, uint32_t formatCapacityInput,
                                     uint32_t* formatCountOutput, int64_t* formats) {
    return onSession(session, [&](Runtime&, SessionObject&) -> XrResult {
        return twoCall(formatCapacityInput, formatCountOutput,
                       static_cast<uint32_t>(std::size(kFormats)),
                       [&](uint32_t i) { formats[i] = kFormats[i]; });
    });
}

/// XR_ERROR_SWAPCHAIN_FORMAT_UNSUPPORTED for another format; XR_ERROR_FEATURE_UNSUPPORTED for
/// multisampling, cube faces, static images or protected content; XR_ERROR_VALIDATION_FAILURE
/// for a size of 0 or above the system's maximum. The textures are made in the GL context
/// current on the calling thread.
XrResult xrCreateSwapchain(XrSession session, const XrSwapchainCreateInfo* createInfo,
                           XrSwapchain* swapchain) {
    return onSession(session, [&](Runtime& rt, SessionObject&) -> XrResult {
        if (std::find(std::begin(kFormats), std::end(kFormats), createInfo->format) ==
            std::end(kFormats))
            return XR_ERROR_SWAPCHAIN_FORMAT_UNSUPPORTED;
        if (createInfo->sampleCount > 1 || createInfo->faceCount != 1 ||
            createInfo->createFlags != 0)
            return XR_ERROR_FEATURE_UNSUPPORTED;
        if (createInfo->width == 0 || createInfo->height == 0 || createInfo->arraySize == 0 ||
            createInfo->mipCount == 0 || createInfo->width > kMaxImageSize ||
            createInfo->height > kMaxImageSize)
            return XR_ERROR_VALIDATION_FAILURE;
        SwapchainObject sc;
        sc.session = session;
        sc.format = createInfo->format;
        sc.width = createInfo->width;
        sc.height = createInfo->height;
        sc.arraySize = createInfo->arraySize;
        sc.textures = createTextures(kSwapchainImages, sc.format, sc.width, sc.height, sc.arraySize,
                                     createInfo->mipCount);
        if (sc.textures.empty()) return XR_ERROR_GRAPHICS_DEVICE_INVALID;
        *swapchain = rt.add<XrSwapchain>(std::move(sc));
        return XR_SUCCESS;
    });
}

/// Deletes the textures too (in the current GL context).
XrResult xrDestroySwapchain(XrSwapchain swapchain) {
    Runtime& rt = runtime();
    std::lock_guard lock(rt.mutex);
    SwapchainObject* sc = rt.find<SwapchainObject>(swapchain);
    if (sc == nullptr) return XR_ERROR_HANDLE_INVALID;
    deleteTextures(sc->textures);
    rt.erase(swapchain);
    return XR_SUCCESS;
}

/// Fills XrSwapchainImageOpenGLKHR structures; XR_ERROR_VALIDATION_FAILURE for another type.
XrResult xrEnumerateSwapchainImages(XrSwapchain swapchain, uint32_t imageCapacityInput,
                                    uint32_t* imageCountOutput,
                                    XrSwapchainImageBaseHeader* images) {
    return onSwapchain(swapchain, [&](SwapchainObject& sc) -> XrResult {
        if (imageCapacityInput > 0 && images[0].type != XR_TYPE_SWAPCHAIN_IMAGE_OPENGL_KHR)
            return XR_ERROR_VALIDATION_FAILURE;
        auto* gl = reinterpret_cast<XrSwapchainImageOpenGLKHR*>(images);
        return twoCall(imageCapacityInput, imageCountOutput,
                       static_cast<uint32_t>(sc.textures.size()),
                       [&](uint32_t i) { gl[i].image = sc.textures[i]; });
    });
}

/// XR_ERROR_CALL_ORDER_INVALID when every image is already acquired and not released.
XrResult xrAcquireSwapchainImage(XrSwapchain swapchain, const XrSwapchainImageAcquireInfo*,
                                 uint32_t* index) {
    return onSwapchain(swapchain, [&](SwapchainObject& sc) -> XrResult {
        if (sc.acquired.size() == sc.textures.size()) return XR_ERROR_CALL_ORDER_INVALID;
        *index = sc.nextImage;
        sc.acquired.push_back(sc.nextImage);
        sc.nextImage = (sc.nextImage + 1) % static_cast<uint32_t>(sc.textures.size());
        return XR_SUCCESS;
    });
}

/// Waits (at once: the simulated compositor holds no image) on the oldest acquired image not
/// yet waited; XR_ERROR_CALL_ORDER_INVALID when there is none.
XrResult xrWaitSwapchainImage(XrSwapchain swapchain, const XrSwapchainImageWaitInfo*) {
    return onSwapchain(swapchain, [&](SwapchainObject& sc) -> XrResult {
        if (sc.waited == sc.acquired.size()) return XR_ERROR_CALL_ORDER_INVALID;
        ++sc.waited;
        return XR_SUCCESS;
    });
}

/// Releases the oldest acquired image; XR_ERROR_CALL_ORDER_INVALID when it was not waited on.
XrResult xrReleaseSwapchainImage(XrSwapchain swapchain, const XrSwapchainImageReleaseInfo*) {
    return onSwapchain(swapchain, [&](SwapchainObject& sc) -> XrResult {
        if (sc.waited == 0) return XR_ERROR_CALL_ORDER_INVALID;
        sc.lastReleased = sc.acquired.front();
        sc.acquired.pop_front();
        --sc.waited;
        return XR_SUCCESS;
    });
}

}  // namespace kizamu::xrsim
