// SPDX-License-Identifier: Apache-2.0
/// @file camera.h
/// @brief The orbit camera: a target, a distance, yaw and pitch; perspective or orthographic;
/// framing a model and the named axis views.
///
/// World frame: metres, Z up, as Blender. Axis views follow Blender's numpad views:
///   front  looks along +Y (the eye on -Y), X to the right, Z up;
///   back   looks along -Y (the eye on +Y);
///   right  looks along -X (the eye on +X), Y to the right;
///   left   looks along +X (the eye on -X);
///   top    looks along -Z (the eye on +Z), X right, Y up the screen;
///   bottom looks along +Z (the eye on -Z), X right, Y down the screen;
///   iso    the eye front-right-above (-Y, +X, +Z), 45° around from front and 35.26° up: the
///          three axes foreshortened equally.
/// Yaw is the angle around +Z from the front view towards the right view; pitch the elevation
/// of the eye above the target's horizontal plane, within ±90°.
///
/// Plain value type; one owner, no synchronisation.
#pragma once

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include <optional>
#include <string_view>

namespace kizamu::render {

enum class Projection { Perspective, Orthographic };

enum class ViewAxis { Front, Back, Left, Right, Top, Bottom, Iso };

/// "front", "back", "left", "right", "top", "bottom", "iso" (lower case); nullopt otherwise.
std::optional<ViewAxis> viewAxisOf(std::string_view name);
/// The name viewAxisOf reads.
const char* nameOf(ViewAxis v);

class OrbitCamera {
public:
    glm::vec3 target{0.0f};      ///< m, world: the point orbited and looked at
    float distance = 1.0f;       ///< m, eye to target, > 0
    float yawRad = 0.0f;         ///< around +Z; 0: front view (eye on -Y)
    float pitchRad = 0.0f;       ///< eye elevation, clamped to [-π/2, π/2]
    float fovYRad = 0.6108652f;  ///< vertical field of view, perspective (35°)
    Projection projection = Projection::Perspective;
    /// Radius (m) of the scene about the target the clip planes must hold; frame() sets it.
    float sceneRadius = 1.0f;

    /// Sets yaw and pitch for an axis view (target and distance unchanged).
    void setView(ViewAxis v);
    /// Aims at the centre of the box and sets the distance so its bounding sphere fills the
    /// smaller of the view's width and height (with `margin` ≥ 1 of room), in either projection.
    /// @param boundsMin, boundsMax  m, world; an empty or inverted box frames a unit sphere
    /// @param aspect  width / height of the image
    void frame(const glm::vec3& boundsMin, const glm::vec3& boundsMax, float aspect,
               float margin = 1.1f);

    /// Turns the view: yaw by dYaw, pitch by dPitch (clamped), radians.
    void orbit(float dYawRad, float dPitchRad);
    /// Moves the eye towards the target: distance × factor (factor > 0; < 1 zooms in).
    void zoom(float factor);

    /// Eye position, m, world.
    glm::vec3 eye() const;
    /// Unit direction from the eye to the target.
    glm::vec3 forward() const;
    /// Unit screen-up direction, orthogonal to forward(); at ±90° pitch it follows the yaw.
    glm::vec3 up() const;
    /// World to eye (right-handed, looking down -Z of the eye frame).
    glm::mat4 viewMatrix() const;
    /// Eye to clip (GL's -1..1 depth). Orthographic: half height = distance × tan(fovY / 2),
    /// so switching projection keeps the target plane's scale.
    glm::mat4 projectionMatrix(float aspect) const;
};

}  // namespace kizamu::render
