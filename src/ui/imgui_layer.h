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

#include <glm/vec2.hpp>

#include <optional>

struct GLFWwindow;

namespace kizamu::ui {

/// A pointer other than the window's mouse (the headset's ray on the panel's quad) and the
/// image the panel is drawn into.
struct PanelPointer {
    glm::vec2 displaySize{480.0f, 560.0f};  ///< pixels of the image the panel is drawn into
    std::optional<glm::vec2> position;      ///< pixels from the top left; none: off the panel
    bool down = false;                      ///< the click is held
};

class ImGuiLayer {
public:
    /// @throw std::runtime_error when a backend cannot start
    explicit ImGuiLayer(GLFWwindow* window);
    ~ImGuiLayer();
    ImGuiLayer(const ImGuiLayer&) = delete;
    ImGuiLayer& operator=(const ImGuiLayer&) = delete;

    /// Starts a frame (after the window's poll, before any ImGui:: call).
    void begin();
    /// Starts a frame whose panel is drawn into an image of pointer.displaySize and operated by
    /// `pointer` instead of the window's mouse (the keyboard stays the window's).
    void begin(const PanelPointer& pointer);
    /// Draws what this frame's ImGui:: calls built into the bound framebuffer.
    void end();
    /// Draws the last frame's panel again (after the scene was redrawn under it).
    void drawAgain();
    bool wantsMouse() const;
    bool wantsKeyboard() const;
};

}  // namespace kizamu::ui
