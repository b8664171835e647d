// SPDX-License-Identifier: Apache-2.0
/// @file json_lines.h
/// @brief The JSON Lines reading every Kizamu text format shares (stroke scripts, hand files,
/// input scripts): the line loop with its comments and one-line errors, and the number check.
///
/// A file is one JSON object per line; blank lines and lines whose first non-blank character
/// is `#` are comments; lines may end in LF or CRLF. An error is one line, "NAME: line N:
/// problem". Cold path: file reading, any thread.
#pragma once

#include <nlohmann/json.hpp>

#include <functional>
#include <string>
#include <string_view>

namespace kizamu::util {

/// Calls `record(line)` for each line of `text` that is not blank or a comment, in order (a
/// trailing CR removed). An exception out
/// of `record` other than a FileError or std::bad_alloc (a JSON parse or type error,
/// std::invalid_argument for a bad value) becomes FileError(name, "line N: " + its message on
/// one line), N counting every line from 1.
/// Complexity: O(text) plus the records. Threading: any thread. Memory: none of its own.
/// @throw kizamu::FileError
void forEachJsonLine(std::string_view text, const std::string& name,
                     const std::function<void(std::string_view line)>& record);

/// forEachJsonLine with each line parsed: `header` gets the first record, `record` every later
/// one. Returns whether there was a header (false: no record at all). Errors as forEachJsonLine.
/// Complexity: O(text) plus the callbacks. Threading: any thread. Memory: one parsed line at a time.
/// @throw kizamu::FileError
bool forEachJsonRecord(std::string_view text, const std::string& name, const std::function<void(const nlohmann::json&)>& header,
                       const std::function<void(const nlohmann::json&)>& record);

/// `j` as a finite double. @throw std::invalid_argument ("\"what\" must be a number", "\"what\"
/// is not finite"). Complexity: O(1). Threading: any thread.
double finiteNumber(const nlohmann::json& j, const char* what);

/// `text` with every CR and LF replaced by a space: an error message on one line.
/// Complexity: O(text). Threading: any thread.
std::string oneLine(std::string text);

}  // namespace kizamu::util
