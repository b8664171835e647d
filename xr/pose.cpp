// SPDX-License-Identifier: Apache-2.0
#include "xr/pose.h"

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>

namespace kizamu::xr {

Pose fromXr(const XrPosef& p) {
    Pose out;
    out.position = glm::dvec3(p.position.x, p.position.y, p.position.z);
    out.orientation = glm::normalize(glm::dquat(p.orientation.w, p.orientation.x, p.orientation.y, p.orientation.z));
    return out;
}

XrPosef toXr(const Pose& p) {
    XrPosef out;
    out.position = {float(p.position.x), float(p.position.y), float(p.position.z)};
    out.orientation = {float(p.orientation.x), float(p.orientation.y), float(p.orientation.z), float(p.orientation.w)};
    return out;
}

Similarity Similarity::inverse() const {
    Similarity inv;
    inv.rotation = glm::conjugate(rotation);
    inv.scale = 1.0 / scale;
    inv.translation = -(inv.scale * (inv.rotation * translation));
    return inv;
}

Similarity Similarity::operator*(const Similarity& inner) const {
    Similarity out;
    out.rotation = glm::normalize(rotation * inner.rotation);
    out.scale = scale * inner.scale;
    out.translation = apply(inner.translation);
    return out;
}

glm::dmat4 Similarity::matrix() const {
    glm::dmat4 m = glm::mat4_cast(rotation) * scale;
    m[3] = glm::dvec4(translation, 1.0);
    return m;
}

Similarity defaultClayPlacement(const glm::dvec3& centre, double domainSize) {
    Similarity s;
    s.scale = domainSize > 0.25 ? 0.25 / domainSize : 1.0;
    // Z up (clay) to Y up (OpenXR): a quarter turn about +X takes +Z to +Y and +Y to −Z.
    s.rotation = glm::angleAxis(-0.5 * M_PI, glm::dvec3(1.0, 0.0, 0.0));
    s.translation = glm::dvec3(0.0, -0.15, -0.35) - s.scale * (s.rotation * centre);
    return s;
}

glm::mat4 viewMatrix(const Pose& eye) {
    const glm::dmat4 eyeToSpace = Similarity::of(eye).matrix();
    return glm::mat4(glm::inverse(eyeToSpace));
}

glm::mat4 projectionMatrix(const XrFovf& fov, float nearM, float farM) {
    const float left = std::tan(fov.angleLeft) * nearM, right = std::tan(fov.angleRight) * nearM;
    const float down = std::tan(fov.angleDown) * nearM, up = std::tan(fov.angleUp) * nearM;
    return glm::frustum(left, right, down, up, nearM, farM);
}

}  // namespace kizamu::xr
