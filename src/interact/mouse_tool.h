// SPDX-License-Identifier: Apache-2.0
/// @file mouse_tool.h
/// @brief The mouse as the stylus's hand: each frame, the ray under the cursor is traced into
/// the clay, and the surface point it meets (with the wheel's depth, the modifier keys and an
/// optional lazy-mouse stabiliser) becomes the tool's target and its stroke.
///
/// Where it sits: the UI thread calls update() once per frame with the cursor's ray (from the
/// camera) and the buttons; what it returns drives the tool, either straight into the engine's
/// sample queue (no haptic device) or as the target of the simulated stylus's hand, which the
/// servo thread then renders and carves with (issue 33, "the mouse is the stylus's hand").
///
/// Conventions (Blender's sculpt mode): the primary button strokes; Ctrl held at the press
/// inverts the tool (carve and add swap, build and heat gun swap), Shift held at the press
/// smooths; the wheel moves the tool's centre along the surface normal in steps of a tenth of its
/// radius (0: the centre on the surface, a carve then cuts a groove as deep as the radius).
/// While a stroke is held the tool rides the surface the ray meets now; the stroke carries a
/// surface-following constraint (StrokeConstraints::followOffset, the depth below the surface
/// as it was when the stroke began), so the engine keeps the tool on the original surface and a
/// cursor held still does not dig ever deeper into the groove it cuts.
/// Lazy mouse: with a stabiliser radius L > 0 the tool trails the cursor's surface point on a
/// string of length L and moves only when the string is taut, which smooths a shaky hand.
/// Threading: one thread (the UI thread). Not real-time: update() allocates nothing but traces
/// a ray (O(ray steps) samples).
#pragma once

#include "adf/adf.h"
#include "interact/surface_ray.h"
#include "sculpt/tool.h"

#include <glm/vec3.hpp>

#include <optional>

namespace kizamu::interact {

/// One frame's input.
struct MouseInput {
    double timeS = 0.0;                ///< s, the frame's time
    bool hasRay = false;               ///< the cursor is over the view
    glm::dvec3 rayOrigin{0.0};         ///< m, world
    glm::dvec3 rayDirection{0.0, 0.0, -1.0};
    bool primary = false;              ///< the stroke button is held
    bool ctrl = false, shift = false;  ///< modifier keys held
    double wheel = 0.0;                ///< wheel notches since the last frame (up: positive)
    float pressure = 1.0f;             ///< pen pressure 0..1 where the window system reports it
};

struct MouseToolSettings {
    double lazyRadius = 0.0;   ///< m, the stabiliser's string; 0: off
    double depthStep = 0.1;    ///< radii per wheel notch
    double minDepth = -1.0;    ///< radii: the deepest the centre may go below the surface
    double maxDepth = 1.0;     ///< radii above it
};

/// What the tool does this frame.
struct MouseToolFrame {
    bool hasTarget = false;      ///< false: the cursor is off the clay and no stroke is held
    glm::dvec3 target{0.0};      ///< m, world: the tool's centre
    glm::dvec3 normal{0.0, 0.0, 1.0};  ///< the surface normal under it
    bool stroking = false;       ///< the primary button is held on the clay
    bool strokeBegan = false;    ///< this frame pressed it (set the stroke's tool first)
    bool strokeEnded = false;    ///< this frame released it
    sculpt::ToolOp op = sculpt::ToolOp::Carve;  ///< the op of the stroke held or begun
    double followOffset = 0.0;   ///< m: the stroke's StrokeConstraints::followOffset
    float pressure = 1.0f;
};

class MouseTool {
public:
    explicit MouseTool(const MouseToolSettings& settings = {});

    /// The tool the app has selected (the op strokes use when no modifier is held, and the radius
    /// the depth is measured in). Takes effect at the next press.
    void setTool(const sculpt::Tool& tool) noexcept { mTool = tool; }
    const sculpt::Tool& tool() const noexcept { return mTool; }
    /// Radii (clamped to [minDepth, maxDepth]): the tool's centre above the surface.
    void setDepth(double radii) noexcept;
    double depth() const noexcept { return mDepth; }
    /// m (>= 0): the lazy mouse's string; 0 turns it off. Takes effect at the next stroke.
    void setLazyRadius(double m) noexcept { mSettings.lazyRadius = m > 0.0 ? m : 0.0; }
    double lazyRadius() const noexcept { return mSettings.lazyRadius; }

    /// One frame: traces the ray into `clay` (its domain `domain`) and returns the tool's frame.
    MouseToolFrame update(const MouseInput& in, adf::AdfAccessor& clay, const adf::Domain& domain) noexcept;

    /// The op a stroke begun with these modifiers uses (Ctrl inverts, Shift smooths).
    static sculpt::ToolOp strokeOp(sculpt::ToolOp selected, bool ctrl, bool shift) noexcept;

private:
    MouseToolSettings mSettings;
    sculpt::Tool mTool;
    double mDepth = 0.0;
    bool mStroking = false;
    sculpt::ToolOp mStrokeOp = sculpt::ToolOp::Carve;
    double mStrokeOffset = 0.0;
    std::optional<glm::dvec3> mLazy;  ///< the stabilised surface point (while stroking)
    glm::dvec3 mLastTarget{0.0}, mLastNormal{0.0, 0.0, 1.0};
};

}  // namespace kizamu::interact
