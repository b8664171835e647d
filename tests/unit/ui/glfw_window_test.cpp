// SPDX-License-Identifier: Apache-2.0
// The desktop window under a display (scripts/test starts Xvfb when there is none): it opens
// with an OpenGL 3.3 core context, polls, resizes its title, and its key and modifier mapping is
// the input scripts' vocabulary. Without a display the tests skip, unless
// KIZAMU_REQUIRE_DISPLAY is set (scripts/test sets it), when they fail.
#include "ui/glfw_window.h"

#include "interact/input_script.h"
#include "interact/input_state.h"

#include <GLFW/glfw3.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>

namespace kizamu {
namespace {

bool haveDisplay() {
    if (std::getenv("DISPLAY")) return true;
    if (std::getenv("KIZAMU_REQUIRE_DISPLAY")) ADD_FAILURE() << "no DISPLAY, and KIZAMU_REQUIRE_DISPLAY is set";
    return false;
}

TEST(GlfwWindow, KeyNamesAreTheInputScriptsVocabulary) {
    EXPECT_EQ(ui::GlfwWindow::keyName(GLFW_KEY_Z), "z");
    EXPECT_EQ(ui::GlfwWindow::keyName(GLFW_KEY_7), "7");
    EXPECT_EQ(ui::GlfwWindow::keyName(GLFW_KEY_F5), "f5");
    EXPECT_EQ(ui::GlfwWindow::keyName(GLFW_KEY_KP_1), "kp1");
    EXPECT_EQ(ui::GlfwWindow::keyName(GLFW_KEY_ESCAPE), "escape");
    EXPECT_EQ(ui::GlfwWindow::keyName(GLFW_KEY_LEFT_SHIFT), "") << "modifiers are not keys of their own";
    // Every named key a script may use has a GLFW key.
    for (const std::string& name : interact::keyNames()) {
        bool found = false;
        for (int k = GLFW_KEY_SPACE; k <= GLFW_KEY_LAST && !found; ++k) found = ui::GlfwWindow::keyName(k) == name;
        EXPECT_TRUE(found) << name;
    }
    EXPECT_EQ(ui::GlfwWindow::modsOf(GLFW_MOD_CONTROL | GLFW_MOD_SHIFT), interact::kModCtrl | interact::kModShift);
}

TEST(GlfwWindow, OpensWithAnOpenGl33CoreContextAndPolls) {
    if (!haveDisplay()) GTEST_SKIP() << "no display";
    ui::WindowSettings ws;
    ws.width = 320;
    ws.height = 240;
    ws.vsync = false;
    ui::GlfwWindow window(ws);
    EXPECT_EQ(window.windowSize(), glm::ivec2(320, 240));
    EXPECT_GE(window.framebufferSize().x, 320);
    EXPECT_GE(glfwGetWindowAttrib(window.handle(), GLFW_CONTEXT_VERSION_MAJOR) * 10 +
                  glfwGetWindowAttrib(window.handle(), GLFW_CONTEXT_VERSION_MINOR),
              33);
    EXPECT_EQ(glfwGetWindowAttrib(window.handle(), GLFW_OPENGL_PROFILE), GLFW_OPENGL_CORE_PROFILE);
    std::vector<interact::InputEvent> events;
    for (int frame = 0; frame < 3; ++frame) {
        window.poll(events, frame);
        window.swap();
    }
    for (const interact::InputEvent& e : events) EXPECT_LT(e.frame, 3);
    window.setTitle("Kizamu - untitled");
    EXPECT_FALSE(window.shouldClose());
    window.requestClose();
    EXPECT_TRUE(window.shouldClose());
}

TEST(InputState, FoldsAFramesEvents) {
    interact::InputState s;
    interact::InputEvent move;
    move.kind = interact::InputEventKind::Move;
    move.x = 10;
    move.y = 20;
    interact::InputEvent press;
    press.kind = interact::InputEventKind::Press;
    press.mods = interact::kModCtrl;
    interact::InputEvent wheel;
    wheel.kind = interact::InputEventKind::Wheel;
    wheel.wheel = -1;
    interact::InputEvent key;
    key.kind = interact::InputEventKind::Key;
    key.key = "z";
    key.mods = interact::kModCtrl;
    s.beginFrame();
    for (const auto& e : {move, press, wheel, wheel, key}) s.apply(e);
    EXPECT_EQ(s.cursor(), glm::dvec2(10, 20));
    EXPECT_TRUE(s.held(interact::MouseButton::Left));
    EXPECT_TRUE(s.pressed(interact::MouseButton::Left));
    EXPECT_EQ(s.wheel(), -2.0);
    EXPECT_TRUE(s.keyPressed("z", interact::kModCtrl));
    EXPECT_FALSE(s.keyPressed("z"));
    s.beginFrame();
    EXPECT_TRUE(s.held(interact::MouseButton::Left)) << "held across frames";
    EXPECT_FALSE(s.pressed(interact::MouseButton::Left));
    EXPECT_EQ(s.wheel(), 0.0);
    EXPECT_TRUE(s.keys().empty());
}

}  // namespace
}  // namespace kizamu
