// SPDX-License-Identifier: Apache-2.0
/// @file sculpt_controls.h
/// @brief What the artist's hands mean, frame by frame: the dominant hand's grip is the tool and
/// its trigger sculpts with its pressure as strength; the other hand's squeeze grabs the clay
/// (both squeezes: move, turn and scale it, clay_grab.h); the other hand's aim ray is the
/// panel's pointer and its trigger the click; the dominant thumbstick flicks through tools
/// (left, right) and grows or shrinks the tool (up, down); the primary button (A / X) inverts the
/// tool; a click of the secondary button (B / Y / menu), pressed and let go within a second
/// while nothing is sculpting or grabbing, undoes. Resting a finger, gripping the controller or
/// holding a button down never undoes.
///
/// Pure (no OpenXR calls): ControllerFrame in, SculptIntent out; owned by the UI thread.
#pragma once

#include "xr/clay_grab.h"
#include "xr/controllers.h"
#include "xr/pose.h"

#include <glm/vec2.hpp>

#include <array>
#include <optional>

namespace kizamu::xr {

/// A flat panel in the world: centred at pose.position, facing its +Z, x right, y up.
struct PanelQuad {
    Pose pose;
    glm::dvec2 sizeM{0.3, 0.35};
    glm::ivec2 pixels{480, 560};
};

/// Where a ray meets the panel, in its pixels from the top left; nothing when it misses or
/// comes from behind.
std::optional<glm::dvec2> panelHit(const PanelQuad& panel, const glm::dvec3& origin, const glm::dvec3& direction);

struct SculptIntent {
    bool hasTool = false;
    glm::dvec3 toolClay{0.0};  ///< the tool's centre, clay world (m)
    bool sculpting = false;    ///< the trigger is down (and the hand is not on the panel)
    float strength = 0.0f;     ///< the trigger's pressure, 0..1
    bool invert = false;       ///< the primary button was pressed this frame: flip carve and add
    int toolStep = 0;          ///< −1 or +1: a thumbstick flick to the previous or next tool
    double sizeFactor = 1.0;   ///< multiply the tool's radius by this (thumbstick up or down)
    bool undo = false;         ///< a deliberate secondary click finished this frame
    bool grabbing = false;     ///< a hand holds the clay
    std::optional<glm::dvec2> pointer;  ///< the other hand's ray on the panel, pixels
    bool pointerDown = false;           ///< its trigger, while it points at the panel
};

struct ControlsSettings {
    Hand dominant = Hand::Right;
    double sizeRatePerS = 1.2;  ///< the tool's radius grows by e^(rate · stick) per second
};

class SculptControls {
public:
    explicit SculptControls(const ControlsSettings& settings = {}) : mSettings(settings) {}

    /// One frame: `dtS` seconds since the last; `placement` (clay to reference space) is moved
    /// by a grab. Complexity O(1).
    SculptIntent update(const ControllerFrame& frame, double dtS, const PanelQuad& panel, Similarity& placement);
    const ControlsSettings& settings() const { return mSettings; }
    void setDominant(Hand h) { mSettings.dominant = h; }

private:
    ControlsSettings mSettings;
    ClayGrab mGrab;
    bool mPrimaryWas = false, mStickCentred = true;
    std::array<bool, 2> mSecondaryWas{};
    std::array<double, 2> mSecondaryHeldS{};
    std::array<bool, 2> mSecondarySpoilt{};  ///< something else happened during the press
};

}  // namespace kizamu::xr
