// SPDX-License-Identifier: Apache-2.0
/// @file pose_math.h
/// @brief Rigid transforms on XrPosef (a unit quaternion plus a position in m) for the spaces.
///
/// A pose A_from_B maps coordinates in frame B to frame A; compose(A_from_B, B_from_C) is
/// A_from_C. Pure functions: any thread; O(1); no allocation.
#pragma once

#include "sim/openxr/xr_headers.h"

namespace kizamu::xrsim {

/// The identity pose.
XrPosef identityPose();
/// a * b (apply b, then a).
XrPosef compose(const XrPosef& a, const XrPosef& b);
/// The inverse transform.
XrPosef inverse(const XrPosef& p);
/// Whether the orientation is a unit quaternion within 1e-3 (the spec's XR_ERROR_POSE_INVALID).
bool isValidPose(const XrPosef& p);

}  // namespace kizamu::xrsim
