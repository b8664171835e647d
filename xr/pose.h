// SPDX-License-Identifier: Apache-2.0
/// @file pose.h
/// @brief Poses and similarities between OpenXR's spaces and the clay's, and the eye matrices
/// of an XrView.
///
/// Conventions: OpenXR spaces are right-handed, Y up, metres; the clay's world is Z up, metres.
/// A `Similarity` maps points p ↦ translation + scale · rotation(p); the clay's placement in
/// the headset's reference space is one (the artist moves, turns and scales the clay with it).
/// Pure value types and functions; any thread.
#pragma once

#include <openxr/openxr.h>

#include <glm/ext/quaternion_double.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

namespace kizamu::xr {

/// A rigid pose: where a frame's origin is and how it is turned.
struct Pose {
    glm::dvec3 position{0.0};
    glm::dquat orientation{1.0, 0.0, 0.0, 0.0};  ///< unit (w, x, y, z)
};

Pose fromXr(const XrPosef& p);
XrPosef toXr(const Pose& p);

/// p ↦ translation + scale · rotation(p), scale > 0.
struct Similarity {
    glm::dvec3 translation{0.0};
    glm::dquat rotation{1.0, 0.0, 0.0, 0.0};
    double scale = 1.0;

    glm::dvec3 apply(const glm::dvec3& p) const { return translation + scale * (rotation * p); }
    /// Directions: rotated only.
    glm::dvec3 applyDirection(const glm::dvec3& d) const { return rotation * d; }
    Similarity inverse() const;
    /// (this ∘ inner)(p) = this(inner(p)).
    Similarity operator*(const Similarity& inner) const;
    glm::dmat4 matrix() const;
    static Similarity of(const Pose& pose) { return {pose.position, pose.orientation, 1.0}; }
};

/// Where the clay first appears: its domain centre `centre` (clay world, m) 0.35 m in front of
/// and 0.15 m below the reference space's origin, its +Z turned to the space's +Y (up), at real
/// size, or smaller so that a domain of `domainSize` metres appears at most 0.25 m across (a
/// big model comes within arm's reach; two hands scale it back up).
Similarity defaultClayPlacement(const glm::dvec3& centre, double domainSize);

/// The view matrix of an eye at `eye` (reference space), as OpenGL wants it (eye looking down −Z).
glm::mat4 viewMatrix(const Pose& eye);
/// OpenGL's projection (clip z in −w..w) for an XrFovf's four angles (radians; left and down
/// negative), near and far in metres.
glm::mat4 projectionMatrix(const XrFovf& fov, float nearM, float farM);

}  // namespace kizamu::xr
