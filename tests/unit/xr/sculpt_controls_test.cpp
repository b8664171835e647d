// SPDX-License-Identifier: Apache-2.0
#include "xr/sculpt_controls.h"

#include <gtest/gtest.h>

namespace kizamu::xr {
namespace {

constexpr double kDt = 1.0 / 90.0;

ControllerFrame frameWith(HandInput right, HandInput left = {}) {
    ControllerFrame f;
    f.hands[0] = left;
    f.hands[1] = right;
    return f;
}

HandInput handAt(glm::dvec3 p) {
    HandInput h;
    h.tracked = true;
    h.grip.position = p;
    h.aim.position = p;
    return h;
}

TEST(SculptControls, TheDominantTriggerSculptsWithItsPressureAtTheGripInClayCoordinates) {
    SculptControls controls;
    PanelQuad panel;
    Similarity placement;
    placement.translation = {0.0, 0.0, -0.4};
    placement.scale = 2.0;
    HandInput right = handAt({0.02, 0.0, -0.4});
    right.trigger = 0.6f;
    const SculptIntent i = controls.update(frameWith(right), kDt, panel, placement);
    ASSERT_TRUE(i.hasTool);
    EXPECT_TRUE(i.sculpting);
    EXPECT_FLOAT_EQ(i.strength, 0.6f);
    EXPECT_LT(glm::length(i.toolClay - glm::dvec3(0.01, 0.0, 0.0)), 1e-12);  // 2 cm seen is 1 cm of clay at twice the size

    // Left-handed: the right trigger no longer sculpts.
    SculptControls leftHanded(ControlsSettings{Hand::Left});
    EXPECT_FALSE(leftHanded.update(frameWith(right), kDt, panel, placement).sculpting);
}

TEST(SculptControls, UndoIsADeliberateClickNeverAHeldButtonOrAGrab) {
    SculptControls controls;
    PanelQuad panel;
    Similarity placement;
    HandInput left = handAt({-0.2, 0.0, -0.3});
    const HandInput right = handAt({0.2, 0.0, -0.3});
    // A click: pressed three frames, let go.
    left.secondary = true;
    for (int i = 0; i < 3; ++i) EXPECT_FALSE(controls.update(frameWith(right, left), kDt, panel, placement).undo);
    left.secondary = false;
    EXPECT_TRUE(controls.update(frameWith(right, left), kDt, panel, placement).undo);
    EXPECT_FALSE(controls.update(frameWith(right, left), kDt, panel, placement).undo);  // once

    // Held past a second (a thumb resting on it): no undo on release.
    left.secondary = true;
    for (int i = 0; i < 120; ++i) controls.update(frameWith(right, left), kDt, panel, placement);
    left.secondary = false;
    EXPECT_FALSE(controls.update(frameWith(right, left), kDt, panel, placement).undo);

    // Clicked while grabbing the clay: no undo.
    left.squeeze = 1.0f;
    left.secondary = true;
    controls.update(frameWith(right, left), kDt, panel, placement);
    left.secondary = false;
    EXPECT_FALSE(controls.update(frameWith(right, left), kDt, panel, placement).undo);
}

TEST(SculptControls, TheOtherHandsSqueezeGrabsAndTheToolHandsAloneDoesNot) {
    SculptControls controls;
    PanelQuad panel;
    Similarity placement;
    HandInput right = handAt({0.2, 0.0, -0.3});
    right.squeeze = 1.0f;
    right.trigger = 0.5f;
    SculptIntent i = controls.update(frameWith(right), kDt, panel, placement);
    EXPECT_FALSE(i.grabbing);
    EXPECT_TRUE(i.sculpting);
    HandInput left = handAt({-0.2, 0.0, -0.3});
    left.squeeze = 1.0f;
    i = controls.update(frameWith(right, left), kDt, panel, placement);
    EXPECT_TRUE(i.grabbing);
    EXPECT_FALSE(i.sculpting);  // no stroke while the clay is held
    left.grip.position.y += 0.1;
    right.grip.position.y += 0.1;
    controls.update(frameWith(right, left), kDt, panel, placement);
    EXPECT_NEAR(placement.translation.y, 0.1, 1e-9);
}

TEST(SculptControls, TheThumbstickFlicksToolsOnceAndScalesTheSize) {
    SculptControls controls;
    PanelQuad panel;
    Similarity placement;
    HandInput right = handAt({0.0, 0.0, -0.3});
    right.thumbstick = {0.9f, 0.0f};
    EXPECT_EQ(controls.update(frameWith(right), kDt, panel, placement).toolStep, 1);
    EXPECT_EQ(controls.update(frameWith(right), kDt, panel, placement).toolStep, 0);  // held: one step
    right.thumbstick = {0.0f, 0.0f};
    controls.update(frameWith(right), kDt, panel, placement);
    right.thumbstick = {-0.9f, 0.0f};
    EXPECT_EQ(controls.update(frameWith(right), kDt, panel, placement).toolStep, -1);
    right.thumbstick = {0.0f, 1.0f};
    EXPECT_GT(controls.update(frameWith(right), kDt, panel, placement).sizeFactor, 1.0);
    right.thumbstick = {0.0f, -1.0f};
    EXPECT_LT(controls.update(frameWith(right), kDt, panel, placement).sizeFactor, 1.0);
}

TEST(SculptControls, TheOtherHandPointsAtThePanel) {
    PanelQuad panel;
    panel.pose.position = {0.0, 0.0, -0.5};
    panel.sizeM = {0.4, 0.2};
    panel.pixels = {400, 200};
    // Straight at the centre from in front: the middle pixel.
    auto hit = panelHit(panel, {0.0, 0.0, 0.0}, {0.0, 0.0, -1.0});
    ASSERT_TRUE(hit);
    EXPECT_NEAR(hit->x, 200.0, 1e-9);
    EXPECT_NEAR(hit->y, 100.0, 1e-9);
    // Up and to the left: towards the top-left pixel.
    hit = panelHit(panel, {-0.15, 0.05, 0.0}, {0.0, 0.0, -1.0});
    ASSERT_TRUE(hit);
    EXPECT_NEAR(hit->x, 50.0, 1e-9);
    EXPECT_NEAR(hit->y, 50.0, 1e-9);
    EXPECT_FALSE(panelHit(panel, {0.5, 0.0, 0.0}, {0.0, 0.0, -1.0}));   // beside it
    EXPECT_FALSE(panelHit(panel, {0.0, 0.0, -1.0}, {0.0, 0.0, 1.0}));   // from behind

    SculptControls controls;
    Similarity placement;
    HandInput left = handAt({0.0, 0.0, 0.0});
    left.trigger = 1.0f;
    const SculptIntent i = controls.update(frameWith(handAt({0.3, 0, 0}), left), kDt, panel, placement);
    ASSERT_TRUE(i.pointer);
    EXPECT_TRUE(i.pointerDown);
}

}  // namespace
}  // namespace kizamu::xr
