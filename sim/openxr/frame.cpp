// SPDX-License-Identifier: Apache-2.0
/// @file frame.cpp
/// @brief The frame loop on the lock-step clock: xrWaitFrame (never sleeps; each call advances
/// the predicted display time by 1/90 s from 1 s), xrBeginFrame, xrEndFrame with its layer
/// checks and the read-back of projection views.
#include "sim/openxr/capture.h"
#include "sim/openxr/entry_points.h"
#include "sim/openxr/gl_objects.h"
#include "sim/openxr/runtime_state.h"

namespace kizamu::xrsim {
namespace {

/// Checks the swapchain sub-image of a layer: XR_ERROR_HANDLE_INVALID for a dead swapchain or
/// one of another session; XR_ERROR_LAYER_INVALID when it has no released image;
/// XR_ERROR_SWAPCHAIN_RECT_INVALID for a rectangle outside the image;
/// XR_ERROR_VALIDATION_FAILURE for an array index past its layers.
XrResult checkSubImage(Runtime& rt, XrSession session, const XrSwapchainSubImage& sub) {
    const SwapchainObject* sc = rt.find<SwapchainObject>(sub.swapchain);
    if (sc == nullptr || sc->session != session) return XR_ERROR_HANDLE_INVALID;
    if (sc->lastReleased < 0) return XR_ERROR_LAYER_INVALID;
    const XrRect2Di& r = sub.imageRect;
    if (r.offset.x < 0 || r.offset.y < 0 || r.extent.width <= 0 || r.extent.height <= 0 ||
        static_cast<uint32_t>(r.offset.x + r.extent.width) > sc->width ||
        static_cast<uint32_t>(r.offset.y + r.extent.height) > sc->height)
        return XR_ERROR_SWAPCHAIN_RECT_INVALID;
    if (sub.imageArrayIndex >= sc->arraySize) return XR_ERROR_VALIDATION_FAILURE;
    return XR_SUCCESS;
}

/// Checks one layer as the spec's xrEndFrame does.
XrResult checkLayer(Runtime& rt, XrSession session, const XrCompositionLayerBaseHeader* layer) {
    if (layer == nullptr) return XR_ERROR_LAYER_INVALID;
    const SpaceObject* space = rt.find<SpaceObject>(layer->space);
    if (space == nullptr || space->session != session) return XR_ERROR_HANDLE_INVALID;
    if (layer->type == XR_TYPE_COMPOSITION_LAYER_PROJECTION) {
        const auto* p = reinterpret_cast<const XrCompositionLayerProjection*>(layer);
        if (p->viewCount != 2) return XR_ERROR_VALIDATION_FAILURE;
        for (uint32_t i = 0; i < p->viewCount; ++i)
            if (const XrResult r = checkSubImage(rt, session, p->views[i].subImage);
                r != XR_SUCCESS)
                return r;
        return XR_SUCCESS;
    }
    if (layer->type == XR_TYPE_COMPOSITION_LAYER_QUAD)
        return checkSubImage(rt, session,
                             reinterpret_cast<const XrCompositionLayerQuad*>(layer)->subImage);
    return XR_ERROR_LAYER_INVALID;
}

/// Reads each view of a projection layer from its swapchain's last released image.
void readBack(Runtime& rt, const XrCompositionLayerProjection& layer) {
    for (uint32_t eye = 0; eye < 2; ++eye) {
        const XrSwapchainSubImage& sub = layer.views[eye].subImage;
        const SwapchainObject& sc = *rt.find<SwapchainObject>(sub.swapchain);
        ViewImage& view = rt.lastViews[eye];
        view.width = sub.imageRect.extent.width;
        view.height = sub.imageRect.extent.height;
        readTexture(sc.textures[static_cast<size_t>(sc.lastReleased)], sc.arraySize > 1,
                    sub.imageArrayIndex, sub.imageRect.offset.x, sub.imageRect.offset.y, view.width,
                    view.height, view.rgba);
    }
}

}  // namespace

/// XR_ERROR_SESSION_NOT_RUNNING when the session is not running. shouldRender is true in
/// VISIBLE and FOCUSED.
XrResult xrWaitFrame(XrSession session, const XrFrameWaitInfo*, XrFrameState* frameState) {
    return onSession(session, [&](Runtime&, SessionObject& s) -> XrResult {
        if (!s.running) return XR_ERROR_SESSION_NOT_RUNNING;
        s.now = kStartTime + static_cast<XrTime>(s.framesWaited) * kFramePeriod;
        ++s.framesWaited;
        ++s.pendingWaits;
        frameState->predictedDisplayTime = s.now;
        frameState->predictedDisplayPeriod = kFramePeriod;
        frameState->shouldRender =
            s.state == XR_SESSION_STATE_VISIBLE || s.state == XR_SESSION_STATE_FOCUSED ? XR_TRUE
                                                                                       : XR_FALSE;
        return XR_SUCCESS;
    });
}

/// XR_ERROR_SESSION_NOT_RUNNING when not running; XR_ERROR_CALL_ORDER_INVALID without a
/// preceding xrWaitFrame; XR_FRAME_DISCARDED when the previous frame was begun and not ended.
XrResult xrBeginFrame(XrSession session, const XrFrameBeginInfo*) {
    return onSession(session, [&](Runtime&, SessionObject& s) -> XrResult {
        if (!s.running) return XR_ERROR_SESSION_NOT_RUNNING;
        if (s.pendingWaits == 0) return XR_ERROR_CALL_ORDER_INVALID;
        --s.pendingWaits;
        if (s.frameBegun) return XR_FRAME_DISCARDED;
        s.frameBegun = true;
        return XR_SUCCESS;
    });
}

/// XR_ERROR_SESSION_NOT_RUNNING; XR_ERROR_CALL_ORDER_INVALID without xrBeginFrame;
/// XR_ERROR_TIME_INVALID for a display time <= 0; XR_ERROR_ENVIRONMENT_BLEND_MODE_UNSUPPORTED
/// for anything but OPAQUE; XR_ERROR_LAYER_LIMIT_EXCEEDED past 16 layers; the layer errors of
/// checkLayer (XR_ERROR_LAYER_INVALID for a swapchain with no released image). Reads back the
/// projection views; the first frame ended makes a SYNCHRONIZED session VISIBLE and FOCUSED.
XrResult xrEndFrame(XrSession session, const XrFrameEndInfo* frameEndInfo) {
    return onSession(session, [&](Runtime& rt, SessionObject& s) -> XrResult {
        if (!s.running) return XR_ERROR_SESSION_NOT_RUNNING;
        if (!s.frameBegun) return XR_ERROR_CALL_ORDER_INVALID;
        if (frameEndInfo->displayTime <= 0) return XR_ERROR_TIME_INVALID;
        if (frameEndInfo->environmentBlendMode != XR_ENVIRONMENT_BLEND_MODE_OPAQUE)
            return XR_ERROR_ENVIRONMENT_BLEND_MODE_UNSUPPORTED;
        if (frameEndInfo->layerCount > kMaxLayers) return XR_ERROR_LAYER_LIMIT_EXCEEDED;
        for (uint32_t i = 0; i < frameEndInfo->layerCount; ++i)
            if (const XrResult r = checkLayer(rt, session, frameEndInfo->layers[i]);
                r != XR_SUCCESS)
                return r;
        for (uint32_t i = 0; i < frameEndInfo->layerCount; ++i)
            if (frameEndInfo->layers[i]->type == XR_TYPE_COMPOSITION_LAYER_PROJECTION)
                readBack(rt, *reinterpret_cast<const XrCompositionLayerProjection*>(
                                 frameEndInfo->layers[i]));
        s.frameBegun = false;
        ++rt.framesEnded;
        if (rt.framesEnded % 90 == 0)
            captureEvent(rt, "{\"event\":\"frame\",\"n\":" + std::to_string(rt.framesEnded) +
                                 ",\"time\":" + std::to_string(s.now) + "}");
        if (s.state == XR_SESSION_STATE_SYNCHRONIZED) {
            setSessionState(rt, session, s, XR_SESSION_STATE_VISIBLE);
            setSessionState(rt, session, s, XR_SESSION_STATE_FOCUSED);
        }
        if (rt.stopAtFrame != 0 && rt.framesEnded == rt.stopAtFrame) stopSession(rt, session, s);
        if (rt.loseAtFrame != 0 && rt.framesEnded == rt.loseAtFrame) {
            setSessionState(rt, session, s, XR_SESSION_STATE_LOSS_PENDING);
            s.lost = true;
        }
        return XR_SUCCESS;
    });
}

}  // namespace kizamu::xrsim
