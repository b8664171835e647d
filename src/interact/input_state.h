// SPDX-License-Identifier: Apache-2.0
/// @file input_state.h
/// @brief What the input events of a frame add up to: where the cursor is, which buttons and
/// modifiers are held, how far the wheel turned, which keys were pressed and which files dropped.
///
/// The window (GLFW callbacks) and an input script (input_script.h) produce the same
/// InputEvents; the application folds each frame's events into an InputState and acts on that,
/// so a scripted session runs through exactly the code a person's hand does. Plain value, one
/// thread (the UI thread).
#pragma once

#include "interact/input_script.h"

#include <glm/vec2.hpp>

#include <string>
#include <vector>

namespace kizamu::interact {

/// A key pressed this frame with the modifiers held.
struct KeyPress {
    std::string key;
    uint32_t mods = 0;
    bool operator==(const KeyPress&) const = default;
};

class InputState {
public:
    /// Starts a frame: clears what happened in the last one (wheel, keys, drops, text, presses).
    void beginFrame() noexcept;
    /// Folds one event in (in order).
    void apply(const InputEvent& e);

    glm::dvec2 cursor() const noexcept { return mCursor; }  ///< pixels from the top left
    bool hasCursor() const noexcept { return mHasCursor; }   ///< a move has been seen
    float pressure() const noexcept { return mPressure; }
    bool held(MouseButton b) const noexcept { return mHeld[int(b)]; }
    /// Pressed during this frame (also when released again within it).
    bool pressed(MouseButton b) const noexcept { return mPressed[int(b)]; }
    /// The modifiers held: those of the newest press, key or wheel event with modifiers, while a
    /// button is held; the newest key or wheel event's otherwise.
    uint32_t mods() const noexcept { return mMods; }
    double wheel() const noexcept { return mWheel; }  ///< notches this frame
    const std::vector<KeyPress>& keys() const noexcept { return mKeys; }
    const std::vector<std::string>& drops() const noexcept { return mDrops; }
    /// The characters typed this frame (UTF-8), in order.
    const std::string& text() const noexcept { return mText; }
    /// Whether `key` with exactly `mods` was pressed this frame.
    bool keyPressed(const std::string& key, uint32_t mods = 0) const noexcept;

private:
    glm::dvec2 mCursor{0.0};
    bool mHasCursor = false;
    float mPressure = 1.0f;
    bool mHeld[3] = {false, false, false};
    bool mPressed[3] = {false, false, false};
    uint32_t mMods = 0;
    double mWheel = 0.0;
    std::vector<KeyPress> mKeys;
    std::vector<std::string> mDrops;
    std::string mText;
};

}  // namespace kizamu::interact
