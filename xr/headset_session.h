// SPDX-License-Identifier: Apache-2.0
/// @file headset_session.h
/// @brief An XrSession drawing with the desktop window's OpenGL context: the instance
/// (XR_KHR_opengl_enable; XR_EXT_conformance_automation where the runtime has it), the head-
/// mounted system, the XrSession bound to the desktop window's GLX context, a reference space, one
/// swapchain per eye and one for the panel quad, the XrSession's state machine and the frame loop.
///
/// Lifecycle (the specification's): created → IDLE → READY (this begins the XrSession) →
/// SYNCHRONIZED → VISIBLE → FOCUSED; STOPPING (this ends the XrSession) → IDLE → EXITING, or
/// LOSS_PENDING: pollEvents() then returns false and the caller stops using it. Frames are
/// paced by xrWaitFrame: beginFrame() blocks until the runtime wants the next one.
/// Threading: the UI thread, with the window's GL context current, for every call. Not copyable.
#pragma once

#include "xr/pose.h"
#include "xr/swapchain.h"
#include "xr/xr_platform.h"

#include <glm/mat4x4.hpp>

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace kizamu::xr {

struct HeadsetOptions {
    /// Enable Khronos' core validation layer (XR_APILAYER_LUNARG_core_validation) when installed.
    bool validation = false;
    /// The panel's swapchain, pixels (its quad is panelSizeM wide in the world).
    int panelWidth = 480, panelHeight = 560;
    double panelWidthM = 0.30;
};

/// One eye of the frame being drawn.
struct EyeView {
    Pose pose;            ///< the eye, reference space
    glm::mat4 view{1.0f};  ///< reference space to eye
    glm::mat4 projection{1.0f};
    glm::ivec2 size{0};   ///< pixels
};

struct FrameTiming {
    XrTime displayTime = 0;       ///< when this frame will be shown (the runtime's clock, ns)
    XrDuration displayPeriod = 0;  ///< ns between frames
    bool shouldRender = false;    ///< false: submit nothing this frame (not visible)
};

class HeadsetSession {
public:
    /// Starts the instance, system and XrSession with the GLX context current on this thread (the
    /// desktop window's).
    /// @throw XrFailure ("xrCreateInstance: XR_ERROR_RUNTIME_UNAVAILABLE" where no runtime is
    ///        installed, and so on), std::runtime_error when the runtime lacks OpenGL
    explicit HeadsetSession(const HeadsetOptions& options);
    ~HeadsetSession();
    HeadsetSession(const HeadsetSession&) = delete;
    HeadsetSession& operator=(const HeadsetSession&) = delete;

    /// Handles the runtime's events (state changes begin and end the XrSession). Returns false
    /// once the XrSession is over (EXITING, LOSS_PENDING, or the instance lost).
    bool pollEvents();
    /// Between xrBeginSession and xrEndSession: the frame loop runs.
    bool running() const { return mRunning; }
    XrSessionState state() const { return mState; }
    bool focused() const { return mState == XR_SESSION_STATE_FOCUSED; }
    /// Asks the runtime to stop (it answers with STOPPING, then EXITING).
    void requestExit();

    /// xrWaitFrame (blocks: the runtime's pacing), xrBeginFrame, and the eyes' views for the
    /// frame's display time. Precondition: running(). @throw XrFailure
    FrameTiming beginFrame();
    const std::array<EyeView, 2>& eyes() const { return mEyes; }
    /// Binds eye `i`'s next image for drawing (viewport set); drawEye..., then releaseEye(i).
    void acquireEye(int i) { mEyeSwapchains[std::size_t(i)]->acquire(); }
    void releaseEye(int i) { mEyeSwapchains[std::size_t(i)]->release(); }
    /// The framebuffer of eye `i`'s image acquired last (a desktop mirror blits it).
    GLuint eyeFramebuffer(int i) const { return mEyeSwapchains[std::size_t(i)]->framebuffer(); }
    /// The panel's quad: where it is (reference space) and its image.
    Pose panelPose;
    glm::dvec2 panelSizeM() const;
    glm::ivec2 panelPixels() const { return mPanel->size(); }
    void acquirePanel() { mPanel->acquire(); }
    void releasePanel() { mPanel->release(); }
    /// xrEndFrame with the projection layer (the eyes drawn this frame) and, when `showPanel`,
    /// the panel's quad. A frame with shouldRender false submits no layer. @throw XrFailure
    void endFrame(bool showPanel);

    XrInstance instance() const { return mInstance; }
    XrSession session() const { return mSession; }
    XrSpace space() const { return mSpace; }
    /// The runtime offers XR_EXT_conformance_automation (and it is enabled).
    bool hasAutomation() const { return mAutomation; }
    /// "runtime name version", for the panel and logs.
    const std::string& runtimeName() const { return mRuntimeName; }

private:
    void handleStateChange(XrSessionState next);
    XrInstance mInstance = XR_NULL_HANDLE;
    XrSystemId mSystem = XR_NULL_SYSTEM_ID;
    XrSession mSession = XR_NULL_HANDLE;
    XrSpace mSpace = XR_NULL_HANDLE;
    XrSessionState mState = XR_SESSION_STATE_UNKNOWN;
    bool mRunning = false, mExited = false, mAutomation = false;
    std::string mRuntimeName;
    std::array<std::unique_ptr<ColourSwapchain>, 2> mEyeSwapchains;
    std::unique_ptr<ColourSwapchain> mPanel;
    double mPanelWidthM = 0.3;
    std::array<EyeView, 2> mEyes{};
    std::array<XrView, 2> mViews{};
    FrameTiming mFrame;
};

}  // namespace kizamu::xr
