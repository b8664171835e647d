// SPDX-License-Identifier: Apache-2.0
/// @file hand_file.h
/// @brief Hand files (`*.hand.jsonl`): the scripted hand of the simulated stylus as JSON
/// lines, documented in docs/HAND.md.
///
/// A header {"kizamu_hand": 1, "units": "m"} and then one waypoint per line,
/// {"t": s, "p": [x, y, z], "b": buttons}. Errors are one line, "file: line N: problem". Cold
/// path: plain values, any thread, never the servo thread. Units SI (m, s).
#pragma once

#include "sim/hand.h"

#include <string>

namespace kizamu::sim {

/// The format version this build reads and writes.
inline constexpr int kHandVersion = 1;

/// Parses hand-file text; `name` starts every error.
/// @throw kizamu::FileError "name: line N: problem" for bad JSON, a missing or unknown header,
///        units other than "m", a missing or malformed field, a non-finite number, a time that
///        goes backwards or is negative; "name: no waypoints" for a file without any.
/// Complexity: O(lines).
Hand parseHand(const std::string& text, const std::string& name);
/// Reads and parses `path`. @throw kizamu::FileError (also when it cannot be read).
Hand readHand(const std::string& path);
/// The text parseHand reads back to the same waypoints (numbers written to round-trip).
std::string formatHand(const Hand& hand);

}  // namespace kizamu::sim
