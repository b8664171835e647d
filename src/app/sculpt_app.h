// SPDX-License-Identifier: Apache-2.0
/// @file sculpt_app.h
/// @brief `kizamu sculpt`: the desktop sculpting window. The live engine's clay drawn as it
/// changes, a panel of tools and figures, the mouse as the stylus's hand (through a haptic
/// device's servo loop when one is chosen), Blender's navigation and shortcuts.
///
/// One UI thread owns the window, the GL context and the panel; it never waits on the edit
/// thread: commands run while frames go on (a stroke's press waits, a frame or two, for its tool
/// change; a scripted run's last frame waits for everything, to show it). The edit
/// thread (engine/engine.h) applies the samples and posts mesh deltas; the servo thread
/// (haptics/servo_loop.h), when a device is chosen, renders the force and pushes the proxy.
/// Scripted runs (`--input FILE --frames N --screenshot PNG`) feed recorded input events
/// (docs/INPUT.md) through the same path as the window's own.
/// Files: one browser (ui/file_browser.h) opens (Ctrl+O; a drop opens the same way), saves the
/// session as another directory (Ctrl+Shift+S; later strokes journal there) and exports (with
/// an optional decimated copy). With a device the servo thread has a CPU of its own and every
/// other thread, the GL driver's included, keeps to the rest (util::splitCpusForServo).
/// On exit it prints the session in use, its strokes and the median sample-to-visible latency
/// (a tool sample's time stamp to the swap of the first frame that shows its effect).
/// With `xr`, an OpenXR session (headset_mode.h) paces the loop with xrWaitFrame, the
/// controllers sculpt, the panel floats in the world, and the window shows the left eye; when
/// the session ends the app exits. Without a runtime the window opens as usual.
#pragma once

#include <cstdint>
#include <string>

namespace kizamu::app {

struct SculptOptions {
    std::string open;              ///< a session directory to open, or a mesh or .kza to import; empty: a new block of clay
    std::string session;           ///< where a new session is journaled; empty: an untitled one under sessionRoot
    std::string sessionRoot;       ///< empty: $XDG_DATA_HOME/kizamu/sessions (~/.local/share/kizamu/sessions)
    std::string device = "auto";   ///< none (the mouse alone), sim, falcon[:BUS:ADDR], hid[:PATH], auto
    std::string firmware;          ///< the Falcon's firmware file
    int level = 0;                 ///< a new session's finest level (0: 9)
    std::string input;             ///< an input script to replay (docs/INPUT.md)
    int64_t frames = 0;            ///< exit after this many frames (0: when the window closes)
    std::string screenshot;        ///< write the last frame here (PNG)
    int width = 1280, height = 720;
    std::string restore = "ask";   ///< an interrupted session found at start: ask, yes, no
    bool xr = false;               ///< sculpt in a headset (OpenXR); the window mirrors the left eye
    std::string hand = "right";    ///< with xr: the tool's hand (left or right)
    bool xrValidation = false;     ///< with xr: Khronos' core validation layer
    bool registerStylus = false;   ///< with xr and a device: start by registering the stylus in the headset's space
};

/// Runs the window until it closes or `frames` have been drawn. Returns the exit code.
/// @throw std::runtime_error (no display, no OpenGL 3.3, a shader that does not compile, ...)
int runSculptApp(const SculptOptions& options);

}  // namespace kizamu::app
