// SPDX-License-Identifier: Apache-2.0
/// @file actions.h
/// @brief What actions read, shared by actions.cpp (states), spaces.cpp (action spaces) and
/// automation.cpp (the input state it sets).
///
/// Threading: call with the runtime's lock held. Complexity: O(bindings) per call.
#pragma once

#include "sim/openxr/runtime_state.h"

#include <string>
#include <vector>

namespace kizamu::xrsim {

/// The input component `path` of the XrSession's devices (bool as 0/1; 0 when never set). A
/// click never set reads its sibling value as value > 0.5, and a value never set reads its
/// sibling click.
float readInput(const SessionObject& session, const std::string& path);

/// XR_ERROR_PATH_INVALID for a path that is not an atom, XR_ERROR_PATH_UNSUPPORTED for one
/// that is not among the action's subaction paths; XR_SUCCESS for XR_NULL_PATH.
XrResult checkSubactionPath(const Runtime& rt, const ActionObject& action, XrPath path);

/// The sources `action` is bound to in the XrSession's current interaction profile, resolved
/// by the shorthand rules (interaction_profiles.h), whose top-level path is `subactionPath`
/// (any with XR_NULL_PATH).
std::vector<std::string> boundSources(Runtime& rt, const SessionObject& session, XrAction action,
                                      XrPath subactionPath);

/// The pose in LOCAL of an action space's source, composed with the space's offset; false when
/// the action is not active (not synced, device off, no pose bound).
bool actionSpacePose(Runtime& rt, const SessionObject& session, const SpaceObject& space,
                     XrPosef* poseLocal);

}  // namespace kizamu::xrsim
