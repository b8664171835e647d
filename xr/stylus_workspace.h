// SPDX-License-Identifier: Apache-2.0
/// @file stylus_workspace.h
/// @brief A registered stylus in the headset: its workspace mapped into the clay as the headset
/// shows it (registration, then the clay's placement undone), and the registration kept in a
/// small JSON file so it is done once per desk, not once per session.
///
/// File (UTF-8 JSON): {"kizamu_stylus_registration": 1, "device": NAME, "scale": S,
/// "rotation": [w, x, y, z], "translation": [x, y, z], "rms_m": E}: the similarity from the
/// stylus's workspace (m) to the headset's reference space (m). Pure apart from the file I/O;
/// any thread.
#pragma once

#include "haptics/workspace.h"
#include "xr/stylus_registration.h"

#include <optional>
#include <string>

namespace kizamu::xr {

/// The stylus's map into the clay world when the clay is placed by `placement` (clay to
/// reference space): placement⁻¹ ∘ registration.
haptics::WorkspaceMapping stylusMapping(const Similarity& deviceToSpace, const Similarity& placement);

/// $XDG_CONFIG_HOME/kizamu/stylus-registration.json (~/.config/... without it).
std::string defaultRegistrationPath();

/// Writes `r` (atomically: a crash leaves the old file or the new, never half of one).
/// @throw kizamu::FileError naming the path and the system's reason
void saveStylusRegistration(const std::string& path, const StylusRegistration& r, const std::string& device);
/// Reads a registration; nothing when the file does not exist.
/// @throw kizamu::FileError "PATH: problem" for a file that is not a registration (bad JSON, a
///        missing or non-finite field, a zero rotation, a scale out of range)
std::optional<StylusRegistration> loadStylusRegistration(const std::string& path);

}  // namespace kizamu::xr
