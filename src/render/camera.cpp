// SPDX-License-Identifier: Apache-2.0
/// @file camera.cpp
/// @brief Orbit camera maths (see camera.h).
#include "render/camera.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>

namespace kizamu::render {

namespace {
constexpr float kHalfPi = 1.5707963267948966f;
constexpr float kQuarterPi = 0.7853981633974483f;
/// atan(1/√2): the elevation of a cube's corner diagonal, where all three axes look alike.
constexpr float kIsoPitch = 0.6154797086703874f;
}  // namespace

std::optional<ViewAxis> viewAxisOf(std::string_view name) {
    for (ViewAxis v : {ViewAxis::Front, ViewAxis::Back, ViewAxis::Left, ViewAxis::Right,
                       ViewAxis::Top, ViewAxis::Bottom, ViewAxis::Iso})
        if (name == nameOf(v)) return v;
    return std::nullopt;
}

const char* nameOf(ViewAxis v) {
    switch (v) {
        case ViewAxis::Front:
            return "front";
        case ViewAxis::Back:
            return "back";
        case ViewAxis::Left:
            return "left";
        case ViewAxis::Right:
            return "right";
        case ViewAxis::Top:
            return "top";
        case ViewAxis::Bottom:
            return "bottom";
        case ViewAxis::Iso:
            return "iso";
    }
    return "?";
}

void OrbitCamera::setView(ViewAxis v) {
    switch (v) {
        case ViewAxis::Front:
            yawRad = 0.0f, pitchRad = 0.0f;
            break;
        case ViewAxis::Back:
            yawRad = 2.0f * kHalfPi, pitchRad = 0.0f;
            break;
        case ViewAxis::Right:
            yawRad = kHalfPi, pitchRad = 0.0f;
            break;
        case ViewAxis::Left:
            yawRad = -kHalfPi, pitchRad = 0.0f;
            break;
        case ViewAxis::Top:
            yawRad = 0.0f, pitchRad = kHalfPi;
            break;
        case ViewAxis::Bottom:
            yawRad = 0.0f, pitchRad = -kHalfPi;
            break;
        case ViewAxis::Iso:
            yawRad = kQuarterPi, pitchRad = kIsoPitch;
            break;
    }
}

void OrbitCamera::frame(const glm::vec3& boundsMin, const glm::vec3& boundsMax, float aspect,
                        float margin) {
    float radius = 0.5f * glm::length(boundsMax - boundsMin);
    target = 0.5f * (boundsMin + boundsMax);
    if (!(radius > 0.0f) || glm::any(glm::lessThan(boundsMax, boundsMin))) {
        radius = 1.0f;
        target = glm::vec3(0.0f);
    }
    radius *= std::max(margin, 1.0f);
    // The narrower of the two fields of view must hold the sphere.
    const float halfY = 0.5f * fovYRad;
    const float halfX = std::atan(std::tan(halfY) * aspect);
    const float half = std::min(halfX, halfY);
    // Perspective: the cone from the eye touching the sphere has half-angle asin(r / d).
    // Orthographic: the half extent d·tan(half) must reach r; the larger distance serves both.
    distance =
        projection == Projection::Perspective ? radius / std::sin(half) : radius / std::tan(half);
    sceneRadius = radius;
}

void OrbitCamera::orbit(float dYawRad, float dPitchRad) {
    yawRad = std::remainder(yawRad + dYawRad, 4.0f * kHalfPi);
    pitchRad = std::clamp(pitchRad + dPitchRad, -kHalfPi, kHalfPi);
}

void OrbitCamera::zoom(float factor) {
    if (factor > 0.0f) distance *= factor;
}

glm::vec3 OrbitCamera::eye() const {
    const float cp = std::cos(pitchRad), sp = std::sin(pitchRad);
    const float cy = std::cos(yawRad), sy = std::sin(yawRad);
    return target + distance * glm::vec3(sy * cp, -cy * cp, sp);
}

glm::vec3 OrbitCamera::forward() const {
    return glm::normalize(target - eye());
}

glm::vec3 OrbitCamera::up() const {
    // The derivative of the eye direction with pitch: orthogonal to it at every pitch, so the
    // top and bottom views keep a defined screen-up.
    const float cp = std::cos(pitchRad), sp = std::sin(pitchRad);
    const float cy = std::cos(yawRad), sy = std::sin(yawRad);
    return glm::vec3(-sy * sp, cy * sp, cp);
}

glm::mat4 OrbitCamera::viewMatrix() const {
    return glm::lookAt(eye(), target, up());
}

glm::mat4 OrbitCamera::projectionMatrix(float aspect) const {
    // Clip planes hold the scene sphere about the target with room; near never reaches zero.
    const float r = std::max(sceneRadius, 1e-6f);
    const float farZ = distance + 2.0f * r;
    if (projection == Projection::Orthographic) {
        // No perspective divide: the near plane may lie behind the eye.
        const float halfH = distance * std::tan(0.5f * fovYRad);
        const float halfW = halfH * aspect;
        return glm::ortho(-halfW, halfW, -halfH, halfH, distance - 2.0f * r, farZ);
    }
    const float nearZ = std::max(distance - 2.0f * r, 1e-3f * farZ);
    return glm::perspective(fovYRad, aspect, nearZ, farZ);
}

}  // namespace kizamu::render
