// SPDX-License-Identifier: Apache-2.0
/// @file pose_math.cpp
/// @brief Quaternion and pose arithmetic for pose_math.h.
#include "sim/openxr/pose_math.h"

#include <cmath>

namespace kizamu::xrsim {
namespace {

XrQuaternionf multiply(const XrQuaternionf& a, const XrQuaternionf& b) {
    return {a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
            a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x,
            a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w,
            a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z};
}

XrVector3f rotate(const XrQuaternionf& q, const XrVector3f& v) {
    const XrQuaternionf p{v.x, v.y, v.z, 0.0f};
    const XrQuaternionf conj{-q.x, -q.y, -q.z, q.w};
    const XrQuaternionf r = multiply(multiply(q, p), conj);
    return {r.x, r.y, r.z};
}

}  // namespace

XrPosef identityPose() {
    return XrPosef{{0.0f, 0.0f, 0.0f, 1.0f}, {0.0f, 0.0f, 0.0f}};
}

XrPosef compose(const XrPosef& a, const XrPosef& b) {
    const XrVector3f r = rotate(a.orientation, b.position);
    return XrPosef{multiply(a.orientation, b.orientation),
                   {a.position.x + r.x, a.position.y + r.y, a.position.z + r.z}};
}

XrPosef inverse(const XrPosef& p) {
    const XrQuaternionf conj{-p.orientation.x, -p.orientation.y, -p.orientation.z, p.orientation.w};
    const XrVector3f t = rotate(conj, p.position);
    return XrPosef{conj, {-t.x, -t.y, -t.z}};
}

bool isValidPose(const XrPosef& p) {
    const XrQuaternionf& q = p.orientation;
    const float n = std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w);
    return std::fabs(n - 1.0f) <= 1e-3f;
}

}  // namespace kizamu::xrsim
