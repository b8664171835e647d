// SPDX-License-Identifier: Apache-2.0
#include "xr/sculpt_controls.h"

#include <cmath>

namespace kizamu::xr {

namespace {

constexpr float kPressed = 0.5f;        ///< squeeze and the panel's click
constexpr float kTriggerDown = 0.05f;   ///< a touch of the trigger already sculpts, lightly
constexpr double kClickMaxS = 1.0;      ///< a secondary press longer than this is not a click
constexpr float kFlick = 0.7f, kCentred = 0.3f, kDeadZone = 0.2f;

}  // namespace

std::optional<glm::dvec2> panelHit(const PanelQuad& panel, const glm::dvec3& origin, const glm::dvec3& direction) {
    const glm::dquat inv = glm::conjugate(panel.pose.orientation);
    const glm::dvec3 o = inv * (origin - panel.pose.position), d = inv * direction;
    if (o.z <= 0.0 || d.z >= -1e-9) return std::nullopt;  // behind the panel, or not towards it
    const double t = -o.z / d.z;
    const glm::dvec3 p = o + t * d;
    const double u = p.x / panel.sizeM.x + 0.5, v = 0.5 - p.y / panel.sizeM.y;
    if (u < 0.0 || u > 1.0 || v < 0.0 || v > 1.0) return std::nullopt;
    return glm::dvec2(u * panel.pixels.x, v * panel.pixels.y);
}

SculptIntent SculptControls::update(const ControllerFrame& frame, double dtS, const PanelQuad& panel, Similarity& placement) {
    SculptIntent out;
    const Hand toolHand = mSettings.dominant, otherHand = toolHand == Hand::Right ? Hand::Left : Hand::Right;
    const HandInput& tool = frame[toolHand];
    const HandInput& other = frame[otherHand];

    // The panel: the other hand's aim ray (its −Z).
    if (other.tracked) {
        out.pointer = panelHit(panel, other.aim.position, other.aim.orientation * glm::dvec3(0.0, 0.0, -1.0));
        out.pointerDown = out.pointer && other.trigger > kPressed;
    }

    std::array<std::optional<Pose>, 2> holding;
    for (const Hand h : {Hand::Left, Hand::Right}) {
        const HandInput& in = frame[h];
        if (in.tracked && in.squeeze > kPressed) holding[std::size_t(h)] = in.grip;
    }
    // The tool hand alone does not grab (its squeeze is a rest for the fingers); with the other
    // hand it does, for the two-handed move, turn and scale.
    if (!holding[std::size_t(otherHand)]) holding[std::size_t(toolHand)].reset();
    placement = mGrab.update(holding, placement);
    out.grabbing = mGrab.holding();

    if (tool.tracked) {
        out.hasTool = true;
        out.toolClay = placement.inverse().apply(tool.grip.position);
        out.sculpting = tool.trigger > kTriggerDown && !out.grabbing;
        out.strength = out.sculpting ? tool.trigger : 0.0f;
    }

    out.invert = tool.primary && !mPrimaryWas;
    mPrimaryWas = tool.primary;

    const glm::vec2 stick = tool.thumbstick;
    if (mStickCentred && std::abs(stick.x) > kFlick && std::abs(stick.x) > std::abs(stick.y)) {
        out.toolStep = stick.x > 0.0f ? 1 : -1;
        mStickCentred = false;
    } else if (glm::length(stick) < kCentred) {
        mStickCentred = true;
    }
    if (std::abs(stick.y) > kDeadZone && std::abs(stick.y) > std::abs(stick.x))
        out.sizeFactor = std::exp(mSettings.sizeRatePerS * double(stick.y) * dtS);

    for (std::size_t h = 0; h < 2; ++h) {
        const bool down = frame.hands[h].secondary;
        if (down && !mSecondaryWas[h]) {
            mSecondaryHeldS[h] = 0.0;
            mSecondarySpoilt[h] = false;
        }
        if (down) {
            mSecondaryHeldS[h] += dtS;
            mSecondarySpoilt[h] = mSecondarySpoilt[h] || out.sculpting || out.grabbing || mSecondaryHeldS[h] > kClickMaxS;
        }
        if (!down && mSecondaryWas[h] && !mSecondarySpoilt[h]) out.undo = true;
        mSecondaryWas[h] = down;
    }
    return out;
}

}  // namespace kizamu::xr
