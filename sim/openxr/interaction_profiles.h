// SPDX-License-Identifier: Apache-2.0
/// @file interaction_profiles.h
/// @brief The interaction profiles the runtime knows (khr/simple_controller,
/// oculus/touch_controller, valve/index_controller), their input and output paths, and the
/// spec's shorthand rules for a binding that names an identifier without its component.
///
/// Pure functions over constant tables: any thread; O(table) per call; small allocations.
#pragma once

#include "sim/openxr/xr_headers.h"

#include <string>
#include <string_view>

namespace kizamu::xrsim {

inline constexpr char kHandLeft[] = "/user/hand/left";
inline constexpr char kHandRight[] = "/user/hand/right";

/// Whether `profile` (a full path, /interaction_profiles/...) is known.
bool isKnownProfile(std::string_view profile);

/// The known profiles, most capable first: valve/index, oculus/touch, khr/simple.
inline constexpr const char* kProfilesByPreference[] = {
    "/interaction_profiles/valve/index_controller",
    "/interaction_profiles/oculus/touch_controller",
    "/interaction_profiles/khr/simple_controller",
};

/// Whether `path` may be bound in `profile`: a full input path (identifier and component), an
/// identifier alone (the spec's shorthand), or an output path.
bool isValidBinding(std::string_view profile, std::string_view path);

/// The source an action of `type` bound to `path` reads in `profile`: `path` when it names a
/// component; for an identifier, the component the shorthand rules pick (booleans: click, else
/// value, else force; floats: value, else click, else force; poses: pose; 2D vectors: the
/// identifier itself, whose x and y are read). `path` unchanged when nothing fits.
std::string resolveBinding(std::string_view profile, std::string_view path, XrActionType type);

/// The top-level user path of a full path ("/user/hand/left" of ".../input/trigger/value");
/// empty when `path` is not under /user/.
std::string topLevelPath(std::string_view path);

/// Whether `path` is a top-level user path the spec defines (hands, head, gamepad, treadmill).
bool isTopLevelUserPath(std::string_view path);

/// Human-readable pieces for xrGetInputSourceLocalizedName: "Left Hand", "Index Controller",
/// "Trigger Value" (each capitalised from the path).
std::string userPathName(std::string_view path);
std::string profileName(std::string_view profile);
std::string componentName(std::string_view path);

}  // namespace kizamu::xrsim
