// SPDX-License-Identifier: Apache-2.0
/// @file input_script.h
/// @brief Input scripts (`*.input.jsonl`, docs/INPUT.md): recorded or written mouse, keyboard
/// and drop events, frame by frame, that drive the real application (`kizamu sculpt --input
/// FILE --frames N`) so tests and demos script the app a person uses, through the same code.
///
/// A header {"kizamu_input": 1, "size": [w, h]} (the window's size in pixels the positions refer
/// to) and then one event per line, each at a frame: {"frame": 12, "move": [x, y]},
/// {"frame": 13, "press": "left", "mods": ["ctrl"]}, {"frame": 40, "release": "left"},
/// {"frame": 41, "key": "z", "mods": ["ctrl"]}, {"frame": 42, "wheel": -1},
/// {"frame": 50, "drop": "mesh.stl"}, {"frame": 51, "text": "name.obj"}. Events of one frame apply at its start, in file order.
/// Errors are one line, "file: line N: problem". Cold path: plain values, any thread.
#pragma once

#include <glm/ext/quaternion_double.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace kizamu::interact {

inline constexpr int kInputScriptVersion = 1;

enum class InputEventKind : uint8_t { Move, Press, Release, Wheel, Key, Drop, Text, Controller };
enum class MouseButton : uint8_t { Left, Right, Middle };

/// Modifier bits (the keys held with a press, a key or a wheel notch).
enum : uint32_t { kModShift = 1u << 0, kModCtrl = 1u << 1, kModAlt = 1u << 2 };

/// A hand controller's inputs as a script sets them (played into an OpenXR runtime that has
/// XR_EXT_conformance_automation): the fields given change, the others keep their last value.
struct ControllerInput {
    int hand = 1;  ///< 0 left, 1 right
    std::optional<glm::dvec3> position;     ///< m, the headset's reference space (Y up)
    std::optional<glm::dquat> orientation;  ///< unit
    std::optional<float> trigger, squeeze;  ///< 0..1
    std::optional<glm::vec2> thumbstick;    ///< −1..1 each
    std::optional<bool> primary, secondary, active;
};

struct InputEvent {
    int64_t frame = 0;  ///< the frame it applies at (>= 0, non-decreasing through the script)
    InputEventKind kind = InputEventKind::Move;
    double x = 0.0, y = 0.0;  ///< Move: pixels from the window's top left
    float pressure = 1.0f;    ///< Move: pen pressure 0..1 (1 for a mouse)
    MouseButton button = MouseButton::Left;  ///< Press, Release
    double wheel = 0.0;       ///< Wheel: notches, up positive
    std::string key;          ///< Key: "a".."z", "0".."9", or a name (keyNames())
    uint32_t mods = 0;        ///< Press, Key, Wheel: kMod* bits held
    std::string path;         ///< Drop: the file dropped on the window (relative: to the script's directory)
    std::string text;         ///< Text: the characters typed (UTF-8), into the text field that has the keyboard
    ControllerInput controller;  ///< Controller
};

struct InputScript {
    int width = 1280, height = 720;  ///< pixels
    std::vector<InputEvent> events;
    std::string baseDir;             ///< the script's directory (relative drop paths resolve against it)

    /// The last event's frame + 1 (0 when empty): the frames the script needs.
    int64_t frames() const { return events.empty() ? 0 : events.back().frame + 1; }
};

/// The named keys a script may use besides letters and digits.
const std::vector<std::string>& keyNames();

/// Parses script text; `name` starts every error.
/// @throw kizamu::FileError "name: line N: problem" for bad JSON, a missing or unknown header,
///        a bad size, an event that is not exactly one of move/press/release/wheel/key/drop/text, a
///        frame that goes backwards, an unknown button, key or modifier, a non-finite number.
InputScript parseInputScript(const std::string& text, const std::string& name);
/// Reads and parses `path` (baseDir: its directory). @throw kizamu::FileError
InputScript readInputScript(const std::string& path);
/// The text parseInputScript reads back to the same events.
std::string formatInputScript(const InputScript& script);

}  // namespace kizamu::interact
