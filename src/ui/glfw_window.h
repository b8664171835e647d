// SPDX-License-Identifier: Apache-2.0
/// @file glfw_window.h
/// @brief The desktop window: a GLFW window with an OpenGL 3.3 core context, whose mouse,
/// keyboard, wheel and drop callbacks become interact::InputEvents (the same events an input
/// script holds, docs/INPUT.md), so the application reads a person's hand and a script alike.
///
/// Needs a display (an X server; Xvfb in tests and CI). Owned by the UI thread, which is also
/// the thread that renders (the context is current on it). Not copyable.
#pragma once

#include "interact/input_script.h"

#include <glm/vec2.hpp>

#include <string>
#include <vector>

struct GLFWwindow;

namespace kizamu::ui {

struct WindowSettings {
    int width = 1280, height = 720;  ///< screen coordinates
    std::string title = "Kizamu";
    bool visible = true;             ///< false: a hidden window (off-screen use under a display)
    bool vsync = true;
    int samples = 4;                 ///< multisampling of the default framebuffer
};

class GlfwWindow {
public:
    /// Opens the window and makes its context current.
    /// @throw std::runtime_error "no display ..." when GLFW cannot start (no X server), or when
    ///        no OpenGL 3.3 core context can be made
    explicit GlfwWindow(const WindowSettings& settings = {});
    ~GlfwWindow();
    GlfwWindow(const GlfwWindow&) = delete;
    GlfwWindow& operator=(const GlfwWindow&) = delete;

    /// Processes the window system's events and appends those since the last call to `events`,
    /// stamped with `frame` (positions in screen coordinates from the top left).
    void poll(std::vector<interact::InputEvent>& events, int64_t frame);
    void swap();
    bool shouldClose() const;
    void requestClose();
    void setTitle(const std::string& title);
    glm::ivec2 windowSize() const;       ///< screen coordinates (what events' positions use)
    glm::ivec2 framebufferSize() const;  ///< pixels (what the renderer draws)
    GLFWwindow* handle() const noexcept { return mWindow; }

    /// The input script key name of a GLFW key code ("a", "7", "escape", ...), empty for keys
    /// scripts do not name. Pure.
    static std::string keyName(int glfwKey);
    /// interact::kMod* bits of GLFW modifier bits. Pure.
    static uint32_t modsOf(int glfwMods);

private:
    GLFWwindow* mWindow = nullptr;
    std::vector<interact::InputEvent> mPending;  ///< filled by the callbacks during poll()
    int64_t mFrame = 0;
    friend struct GlfwCallbacks;
};

}  // namespace kizamu::ui
