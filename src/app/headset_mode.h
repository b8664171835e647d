// SPDX-License-Identifier: Apache-2.0
/// @file headset_mode.h
/// @brief `kizamu sculpt --xr`: the sculpting window's headset side. The OpenXR session drawing
/// the clay in stereo with the window's GL context, the controllers read each frame into what
/// the hands mean (xr/sculpt_controls.h), the panel on a quad in the world, vibration as the
/// contact cue, scripted controllers played into the runtime, and the desktop window showing
/// the left eye.
///
/// The frame: beginFrame() (xrWaitFrame paces the loop, the controllers are read), the
/// application acts on the intent, drawEyes(), the panel drawn between beginPanel() and
/// endPanel(), endFrame(), mirror(). Threading: the UI thread with the window's context current.
#pragma once

#include "interact/input_script.h"
#include "render/clay_renderer.h"
#include "ui/imgui_layer.h"
#include "xr/pose.h"
#include "xr/sculpt_controls.h"

#include <glm/vec2.hpp>

#include <memory>
#include <string>

namespace kizamu::app {

struct HeadsetModeOptions {
    xr::Hand dominant = xr::Hand::Right;
    bool validation = false;  ///< Khronos' core validation layer, when installed
    glm::dvec3 clayCentre{0.0};  ///< the clay world's point placed in front of the artist
    double domainSize = 0.2;     ///< m, the clay's domain (a big one first appears smaller)
};

class HeadsetMode {
public:
    /// Starts the session. @throw std::exception saying why there is no headset (no runtime,
    /// no system, no OpenGL), for the caller to report in one line and go on on the desktop.
    explicit HeadsetMode(const HeadsetModeOptions& options);
    ~HeadsetMode();
    HeadsetMode(const HeadsetMode&) = delete;
    HeadsetMode& operator=(const HeadsetMode&) = delete;

    /// The runtime's events; false once the session is over (the app then exits).
    bool alive();
    /// The frame loop runs (the session is between begin and end).
    bool running() const;
    bool focused() const;
    /// The runtime lost the session (LOSS_PENDING), rather than ending it.
    bool lost() const;
    void requestExit();
    /// Plays a scripted controller event into the runtime at the next frame, once the runtime
    /// has chosen the hand's interaction profile (so the event sets the inputs the actions are
    /// bound to). False (and nothing done) when the runtime cannot be driven (no
    /// XR_EXT_conformance_automation).
    bool play(const interact::ControllerInput& input);

    /// Waits for the runtime's frame, begins it and reads the hands: what they mean this frame.
    const xr::SculptIntent& beginFrame();
    const xr::SculptIntent& intent() const { return mIntent; }
    /// Clay world to the headset's reference space (moved by grabs).
    const xr::Similarity& placement() const { return mPlacement; }
    /// The panel's pointer for ImGuiLayer::begin.
    ui::PanelPointer panelPointer() const;
    /// Draws both eyes (when the runtime wants this frame shown).
    void drawEyes(const render::ClayRenderer& renderer, const render::RenderSettings& settings, const render::ToolMark* tool);
    /// Binds the panel's image, cleared transparent, for the ImGui frame to be drawn into.
    void beginPanel();
    void endPanel();
    /// Submits the frame (eyes, and the panel when shown).
    void endFrame();
    /// Shows the left eye in the window's framebuffer (width × height pixels), letterboxed.
    void mirror(int width, int height) const;
    /// Vibration on the tool hand: `depth` is how far the tool is into the clay (m, ≤ 0: out
    /// of contact), `radius` its size.
    void contact(double depth, double radius);

    /// "OpenXR: RUNTIME, PROFILE" for the panel.
    std::string describe() const;
    /// Frames submitted, and the median time from xrWaitFrame's return to xrEndFrame (ms).
    uint64_t frames() const { return mFrames; }
    double medianFrameMs() const;

private:
    struct Impl;
    std::unique_ptr<Impl> mImpl;
    xr::Similarity mPlacement;
    xr::SculptIntent mIntent;
    uint64_t mFrames = 0;
};

}  // namespace kizamu::app
