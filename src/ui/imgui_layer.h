// SPDX-License-Identifier: Apache-2.0
/// @file imgui_layer.h
/// @brief Dear ImGui on the desktop window: its context and the GLFW and OpenGL 3 backends
/// (Debian's libimgui.a holds both), one frame at a time.
///
/// The backends chain the window's own callbacks (glfw_window.h installs them first), so input
/// reaches both the panel and the application; the application asks wantsMouse() /
/// wantsKeyboard() before it sculpts or acts on a key, so a click on the panel never carves.
/// Threading: the UI thread with the window's context current. One per window.
#pragma once

struct GLFWwindow;

namespace kizamu::ui {

class ImGuiLayer {
public:
    /// @throw std::runtime_error when a backend cannot start
    explicit ImGuiLayer(GLFWwindow* window);
    ~ImGuiLayer();
    ImGuiLayer(const ImGuiLayer&) = delete;
    ImGuiLayer& operator=(const ImGuiLayer&) = delete;

    /// Starts a frame (after the window's poll, before any ImGui:: call).
    void begin();
    /// Draws what this frame's ImGui:: calls built into the bound framebuffer.
    void end();
    /// Draws the last frame's panel again (after the scene was redrawn under it).
    void drawAgain();
    bool wantsMouse() const;
    bool wantsKeyboard() const;
};

}  // namespace kizamu::ui
