// SPDX-License-Identifier: Apache-2.0
/// @file glfw_window.cpp
/// @brief GlfwWindow: the GLFW window, its context and its callbacks as InputEvents.
#include "ui/glfw_window.h"

#include <GLFW/glfw3.h>

#include <stdexcept>

namespace kizamu::ui {

namespace {

/// GLFW is initialised once per process, on the first window, and stays up (terminating it while
/// another window might be made later costs a display round trip and buys nothing).
void ensureGlfw() {
    static const bool ok = [] {
        glfwSetErrorCallback([](int, const char*) {});  // errors are reported by the calls that fail
        return glfwInit() == GLFW_TRUE;
    }();
    if (!ok) {
        const char* why = nullptr;
        glfwGetError(&why);
        throw std::runtime_error(std::string("no display: the window system cannot start (") + (why ? why : "glfwInit failed") +
                                 "); set DISPLAY, or run headless (kizamu live, kizamu render)");
    }
}

GlfwWindow* self(GLFWwindow* w) { return static_cast<GlfwWindow*>(glfwGetWindowUserPointer(w)); }

}  // namespace

struct GlfwCallbacks {
    static void push(GLFWwindow* w, interact::InputEvent e) {
        GlfwWindow* win = self(w);
        e.frame = win->mFrame;
        win->mPending.push_back(std::move(e));
    }
    static uint32_t heldMods(GLFWwindow* w) {
        uint32_t m = 0;
        if (glfwGetKey(w, GLFW_KEY_LEFT_CONTROL) == GLFW_PRESS || glfwGetKey(w, GLFW_KEY_RIGHT_CONTROL) == GLFW_PRESS)
            m |= interact::kModCtrl;
        if (glfwGetKey(w, GLFW_KEY_LEFT_SHIFT) == GLFW_PRESS || glfwGetKey(w, GLFW_KEY_RIGHT_SHIFT) == GLFW_PRESS)
            m |= interact::kModShift;
        if (glfwGetKey(w, GLFW_KEY_LEFT_ALT) == GLFW_PRESS || glfwGetKey(w, GLFW_KEY_RIGHT_ALT) == GLFW_PRESS)
            m |= interact::kModAlt;
        return m;
    }
    static void cursor(GLFWwindow* w, double x, double y) {
        interact::InputEvent e;
        e.kind = interact::InputEventKind::Move;
        e.x = x;
        e.y = y;
        push(w, e);
    }
    static void button(GLFWwindow* w, int button, int action, int mods) {
        interact::InputEvent e;
        e.kind = action == GLFW_PRESS ? interact::InputEventKind::Press : interact::InputEventKind::Release;
        if (button == GLFW_MOUSE_BUTTON_LEFT) e.button = interact::MouseButton::Left;
        else if (button == GLFW_MOUSE_BUTTON_RIGHT) e.button = interact::MouseButton::Right;
        else if (button == GLFW_MOUSE_BUTTON_MIDDLE) e.button = interact::MouseButton::Middle;
        else return;
        e.mods = GlfwWindow::modsOf(mods);
        push(w, e);
    }
    static void scroll(GLFWwindow* w, double, double dy) {
        interact::InputEvent e;
        e.kind = interact::InputEventKind::Wheel;
        e.wheel = dy;
        e.mods = heldMods(w);
        push(w, e);
    }
    static void key(GLFWwindow* w, int key, int, int action, int mods) {
        if (action != GLFW_PRESS && action != GLFW_REPEAT) return;
        const std::string name = GlfwWindow::keyName(key);
        if (name.empty()) return;
        interact::InputEvent e;
        e.kind = interact::InputEventKind::Key;
        e.key = name;
        e.mods = GlfwWindow::modsOf(mods);
        push(w, e);
    }
    static void drop(GLFWwindow* w, int count, const char** paths) {
        for (int i = 0; i < count; ++i) {
            interact::InputEvent e;
            e.kind = interact::InputEventKind::Drop;
            e.path = paths[i];
            push(w, e);
        }
    }
};

GlfwWindow::GlfwWindow(const WindowSettings& s) {
    ensureGlfw();
    glfwDefaultWindowHints();
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    glfwWindowHint(GLFW_VISIBLE, s.visible ? GLFW_TRUE : GLFW_FALSE);
    glfwWindowHint(GLFW_SAMPLES, s.samples);
    mWindow = glfwCreateWindow(s.width, s.height, s.title.c_str(), nullptr, nullptr);
    if (!mWindow) {
        const char* why = nullptr;
        glfwGetError(&why);
        throw std::runtime_error(std::string("cannot open an OpenGL 3.3 core window: ") + (why ? why : "unknown reason"));
    }
    glfwSetWindowUserPointer(mWindow, this);
    glfwMakeContextCurrent(mWindow);
    glfwSwapInterval(s.vsync ? 1 : 0);
    glfwSetCursorPosCallback(mWindow, &GlfwCallbacks::cursor);
    glfwSetMouseButtonCallback(mWindow, &GlfwCallbacks::button);
    glfwSetScrollCallback(mWindow, &GlfwCallbacks::scroll);
    glfwSetKeyCallback(mWindow, &GlfwCallbacks::key);
    glfwSetDropCallback(mWindow, &GlfwCallbacks::drop);
}

GlfwWindow::~GlfwWindow() {
    if (mWindow) glfwDestroyWindow(mWindow);
}

void GlfwWindow::poll(std::vector<interact::InputEvent>& events, int64_t frame) {
    mFrame = frame;
    glfwPollEvents();
    for (interact::InputEvent& e : mPending) events.push_back(std::move(e));
    mPending.clear();
}

void GlfwWindow::swap() { glfwSwapBuffers(mWindow); }
bool GlfwWindow::shouldClose() const { return glfwWindowShouldClose(mWindow) == GLFW_TRUE; }
void GlfwWindow::requestClose() { glfwSetWindowShouldClose(mWindow, GLFW_TRUE); }
void GlfwWindow::setTitle(const std::string& title) { glfwSetWindowTitle(mWindow, title.c_str()); }

glm::ivec2 GlfwWindow::windowSize() const {
    glm::ivec2 s;
    glfwGetWindowSize(mWindow, &s.x, &s.y);
    return s;
}

glm::ivec2 GlfwWindow::framebufferSize() const {
    glm::ivec2 s;
    glfwGetFramebufferSize(mWindow, &s.x, &s.y);
    return s;
}

std::string GlfwWindow::keyName(int k) {
    if (k >= GLFW_KEY_A && k <= GLFW_KEY_Z) return std::string(1, char('a' + (k - GLFW_KEY_A)));
    if (k >= GLFW_KEY_0 && k <= GLFW_KEY_9) return std::string(1, char('0' + (k - GLFW_KEY_0)));
    if (k >= GLFW_KEY_F1 && k <= GLFW_KEY_F12) return "f" + std::to_string(k - GLFW_KEY_F1 + 1);
    if (k >= GLFW_KEY_KP_0 && k <= GLFW_KEY_KP_9) return "kp" + std::to_string(k - GLFW_KEY_KP_0);
    switch (k) {
    case GLFW_KEY_ESCAPE: return "escape";
    case GLFW_KEY_ENTER: return "enter";
    case GLFW_KEY_SPACE: return "space";
    case GLFW_KEY_TAB: return "tab";
    case GLFW_KEY_BACKSPACE: return "backspace";
    case GLFW_KEY_DELETE: return "delete";
    case GLFW_KEY_LEFT: return "left";
    case GLFW_KEY_RIGHT: return "right";
    case GLFW_KEY_UP: return "up";
    case GLFW_KEY_DOWN: return "down";
    case GLFW_KEY_HOME: return "home";
    case GLFW_KEY_END: return "end";
    case GLFW_KEY_PAGE_UP: return "pageup";
    case GLFW_KEY_PAGE_DOWN: return "pagedown";
    case GLFW_KEY_KP_DECIMAL: return "kpdecimal";
    case GLFW_KEY_LEFT_BRACKET: return "[";
    case GLFW_KEY_RIGHT_BRACKET: return "]";
    case GLFW_KEY_MINUS: return "minus";
    case GLFW_KEY_EQUAL: return "equal";
    default: return {};
    }
}

uint32_t GlfwWindow::modsOf(int m) {
    uint32_t out = 0;
    if (m & GLFW_MOD_CONTROL) out |= interact::kModCtrl;
    if (m & GLFW_MOD_SHIFT) out |= interact::kModShift;
    if (m & GLFW_MOD_ALT) out |= interact::kModAlt;
    return out;
}

}  // namespace kizamu::ui
