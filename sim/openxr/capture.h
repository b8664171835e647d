// SPDX-License-Identifier: Apache-2.0
/// @file capture.h
/// @brief The capture files for tests that run the application as a subprocess: with
/// $KIZAMU_XRSIM_CAPTURE=DIR the runtime appends one JSON line per event to DIR/events.jsonl
/// and writes the last frame's views to DIR/left.png and DIR/right.png (docs/XR-SIM.md).
///
/// Threading: called with the runtime's lock held. Errors: a file that cannot be written is
/// skipped (the application must not fail because a test's directory is missing).
#pragma once

#include "sim/openxr/runtime_state.h"

#include <string>

namespace kizamu::xrsim {

/// Appends `jsonLine` (one object, no newline) to events.jsonl; nothing without a directory.
/// Complexity: one open/append/close. Memory: none kept.
void captureEvent(const Runtime& rt, const std::string& jsonLine);

/// Writes the last views as left.png and right.png (those that exist); nothing without a
/// directory. Complexity: O(pixels) PNG encoding.
void captureViews(const Runtime& rt);

/// The name of a session state without its prefix, e.g. "FOCUSED".
const char* sessionStateName(XrSessionState state);

}  // namespace kizamu::xrsim
