// SPDX-License-Identifier: Apache-2.0
/// @file imgui_layer.cpp
/// @brief ImGuiLayer: context, backends, frames.
#include "ui/imgui_layer.h"

#include <cfloat>

#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <stdexcept>

namespace kizamu::ui {

ImGuiLayer::ImGuiLayer(GLFWwindow* window) {
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGuiIO& io = ImGui::GetIO();
    io.IniFilename = nullptr;  // the panel's layout is the program's, not a file beside the user's work
    ImGui::StyleColorsDark();
    if (!ImGui_ImplGlfw_InitForOpenGL(window, true)) {
        ImGui::DestroyContext();
        throw std::runtime_error("the panel's GLFW backend did not start");
    }
    if (!ImGui_ImplOpenGL3_Init("#version 330 core")) {
        ImGui_ImplGlfw_Shutdown();
        ImGui::DestroyContext();
        throw std::runtime_error("the panel's OpenGL 3 backend did not start");
    }
}

ImGuiLayer::~ImGuiLayer() {
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
}

void ImGuiLayer::begin() {
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
}

void ImGuiLayer::begin(const PanelPointer& pointer) {
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();  // keyboard and time; the display and mouse are overridden next
    ImGuiIO& io = ImGui::GetIO();
    io.DisplaySize = ImVec2(pointer.displaySize.x, pointer.displaySize.y);
    io.DisplayFramebufferScale = ImVec2(1.0f, 1.0f);
    io.MousePos = pointer.position ? ImVec2(pointer.position->x, pointer.position->y) : ImVec2(-FLT_MAX, -FLT_MAX);
    io.MouseDown[0] = pointer.position && pointer.down;
    for (int b = 1; b < 5; ++b) io.MouseDown[b] = false;
    io.MouseWheel = io.MouseWheelH = 0.0f;
    ImGui::NewFrame();
}

void ImGuiLayer::end() {
    ImGui::Render();
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
}

void ImGuiLayer::drawAgain() { ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData()); }

bool ImGuiLayer::wantsMouse() const { return ImGui::GetIO().WantCaptureMouse; }
bool ImGuiLayer::wantsKeyboard() const { return ImGui::GetIO().WantCaptureKeyboard; }

}  // namespace kizamu::ui
