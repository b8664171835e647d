// SPDX-License-Identifier: Apache-2.0
/// @file input_state.cpp
/// @brief InputState: events folded into a frame's state.
#include "interact/input_state.h"

#include <algorithm>

namespace kizamu::interact {

void InputState::beginFrame() noexcept {
    std::fill(std::begin(mPressed), std::end(mPressed), false);
    mWheel = 0.0;
    mKeys.clear();
    mDrops.clear();
    mText.clear();
}

void InputState::apply(const InputEvent& e) {
    switch (e.kind) {
    case InputEventKind::Move:
        mCursor = {e.x, e.y};
        mHasCursor = true;
        mPressure = e.pressure;
        break;
    case InputEventKind::Press:
        mHeld[int(e.button)] = true;
        mPressed[int(e.button)] = true;
        mMods = e.mods;
        break;
    case InputEventKind::Release:
        mHeld[int(e.button)] = false;
        break;
    case InputEventKind::Wheel:
        mWheel += e.wheel;
        mMods = e.mods;
        break;
    case InputEventKind::Key:
        mKeys.push_back({e.key, e.mods});
        mMods = e.mods;
        break;
    case InputEventKind::Drop: mDrops.push_back(e.path); break;
    case InputEventKind::Text: mText += e.text; break;
    case InputEventKind::Controller: break;  // the headset's, played into the XR runtime (xr/controller_automation.h)
    }
}

bool InputState::keyPressed(const std::string& key, uint32_t mods) const noexcept {
    return std::find(mKeys.begin(), mKeys.end(), KeyPress{key, mods}) != mKeys.end();
}

}  // namespace kizamu::interact
