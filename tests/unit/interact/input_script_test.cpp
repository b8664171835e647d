// SPDX-License-Identifier: Apache-2.0
// Input scripts (docs/INPUT.md): every kind of event parses, round-trips, and each kind of
// mistake is a one-line error with the file and line.
#include "interact/input_script.h"

#include "util/file_error.h"

#include <gtest/gtest.h>

#include <string>

namespace kizamu {
namespace {

using interact::InputEventKind;

TEST(InputScript, ParsesEveryEventAndRoundTrips) {
    const std::string text = R"(# a groove, undone
{"kizamu_input": 1, "size": [640, 480]}
{"frame": 0, "move": [320, 200]}
{"frame": 2, "press": "left", "mods": ["ctrl"]}
{"frame": 3, "move": [330.5, 201], "pressure": 0.5}
{"frame": 9, "release": "left"}
{"frame": 10, "wheel": -2, "mods": ["shift"]}
{"frame": 11, "key": "z", "mods": ["ctrl", "shift"]}
{"frame": 11, "key": "f1"}
{"frame": 12, "drop": "meshes/bunny.stl"}
{"frame": 13, "text": "bunny/é.obj"}
)";
    const interact::InputScript s = interact::parseInputScript(text, "t.input.jsonl");
    EXPECT_EQ(s.width, 640);
    EXPECT_EQ(s.height, 480);
    ASSERT_EQ(s.events.size(), 9u);
    EXPECT_EQ(s.frames(), 14);
    EXPECT_EQ(s.events[1].kind, InputEventKind::Press);
    EXPECT_EQ(s.events[1].mods, interact::kModCtrl);
    EXPECT_EQ(s.events[2].x, 330.5);
    EXPECT_EQ(s.events[2].pressure, 0.5f);
    EXPECT_EQ(s.events[4].wheel, -2.0);
    EXPECT_EQ(s.events[5].key, "z");
    EXPECT_EQ(s.events[5].mods, interact::kModCtrl | interact::kModShift);
    EXPECT_EQ(s.events[7].path, "meshes/bunny.stl");
    EXPECT_EQ(s.events[8].kind, InputEventKind::Text);
    EXPECT_EQ(s.events[8].text, "bunny/é.obj");
    const std::string again = interact::formatInputScript(s);
    const interact::InputScript back = interact::parseInputScript(again, "again");
    EXPECT_EQ(interact::formatInputScript(back), again);
    ASSERT_EQ(back.events.size(), s.events.size());
    for (std::size_t i = 0; i < s.events.size(); ++i) {
        EXPECT_EQ(back.events[i].frame, s.events[i].frame);
        EXPECT_EQ(back.events[i].kind, s.events[i].kind);
        EXPECT_EQ(back.events[i].mods, s.events[i].mods);
    }
}

TEST(InputScript, MistakesAreOneLineErrorsWithFileAndLine) {
    const std::string header = "{\"kizamu_input\": 1}\n";
    const auto error = [&](const std::string& text) {
        try {
            interact::parseInputScript(text, "bad.input.jsonl");
        } catch (const FileError& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    EXPECT_EQ(error("{\"kizamu_hand\": 1}\n").find("bad.input.jsonl: line 1: not a Kizamu input script"), 0u);
    EXPECT_NE(error("{\"kizamu_input\": 2}\n").find("version"), std::string::npos);
    EXPECT_NE(error(header + "{\"frame\": 1, \"move\": [1, 2], \"press\": \"left\"}\n").find("line 2: an event is exactly one"),
              std::string::npos);
    EXPECT_NE(error(header + "{\"frame\": 5, \"key\": \"a\"}\n{\"frame\": 4, \"key\": \"b\"}\n").find("line 3: frame 4 comes after frame 5"),
              std::string::npos);
    EXPECT_NE(error(header + "{\"frame\": 1, \"press\": \"thumb\"}\n").find("button"), std::string::npos);
    EXPECT_NE(error(header + "{\"frame\": 1, \"key\": \"ctrl\"}\n").find("unknown key"), std::string::npos);
    EXPECT_NE(error(header + "{\"frame\": 1, \"key\": \"z\", \"mods\": [\"meta\"]}\n").find("unknown modifier"), std::string::npos);
    EXPECT_NE(error(header + "{\"frame\": 1, \"move\": [1]}\n").find("[x, y]"), std::string::npos);
    EXPECT_NE(error(header + "{\"frame\": 1, \"move\": [1, 2], \"pressure\": 2}\n").find("pressure"), std::string::npos);
    EXPECT_NE(error(header + "{\"frame\": 1, \"wheel\": 1, \"speed\": 2}\n").find("unknown key \"speed\""), std::string::npos);
    EXPECT_NE(error(header + "{\"frame\": 1, \"move\": [1, 2}\n").find("line 2:"), std::string::npos);
    EXPECT_NE(error("{\"kizamu_input\": 1, \"size\": [4, 4]}\n").find("size"), std::string::npos);
    EXPECT_EQ(error("").find("bad.input.jsonl: not a Kizamu input script"), 0u);
    for (const std::string& e : {error(header + "{\"frame\": 1, \"move\": [1, 2}\n")}) EXPECT_EQ(e.find('\n'), std::string::npos);
}

}  // namespace
}  // namespace kizamu
