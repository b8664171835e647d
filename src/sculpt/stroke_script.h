// SPDX-License-Identifier: Apache-2.0
/// @file stroke_script.h
/// @brief Stroke scripts (Kizamu 4.3): every edit as a human-readable, versioned record.
///
/// JSON lines, documented in docs/STROKE-SCRIPT.md: a header line (format, version, domain,
/// level, start shape) and then one stroke per line. Lines starting with '#' and blank lines are
/// ignored. Replaying a script gives the same ADF bit for bit; at another level, the same shape
/// at that resolution. Parsing errors name the file and line. Plain values; any thread.
#pragma once

#include "adf/domain.h"
#include "sculpt/stroke.h"

#include <string>
#include <vector>

namespace kizamu::sculpt {

/// Version 2 added Bezier paths and constraints, version 3 live records (Stroke::live: how a
/// stroke was applied in segments) and starts from a file; version 1 and 2 scripts read unchanged.
inline constexpr int kScriptVersion = 3;

/// A whole script: the header (version, domain, start shape) and the steps after it.
struct Script {
    int version = kScriptVersion;
    adf::Domain domain;  ///< origin, size and default level
    /// The clay it starts from: a simple solid, or (version 3) a .kza file whose domain is
    /// `domain` ({"shape": "file", "file": "start.kza"}).
    Shape start;
    std::vector<Step> steps;
    /// The directory a file start's relative path is read from: the script's (readScript), the
    /// session's (Session::open). Not written; empty: the current directory.
    std::string baseDir;
    void add(const Stroke& s) { steps.push_back({Step::Kind::Stroke, s}); }
};

/// Parses script text; `name` appears in errors.
/// @throw kizamu::FileError "name: line N: problem" for anything malformed.
Script parseScript(const std::string& text, const std::string& name);
/// Parses one record line (a stroke, {"undo": 1} or {"redo": 1}) of a script of `version`
/// (a "live" record needs 3). @throw std::invalid_argument, nlohmann::json::exception.
Step parseStep(const std::string& line, int version = kScriptVersion);
/// Parses a header line alone (version, domain, start shape; no steps). Other formats that
/// start from a script's clay read their start with it. @throw std::invalid_argument,
/// nlohmann::json::exception.
Script parseHeaderLine(const std::string& line);
/// Reads and parses a file; baseDir is the file's directory. @throw kizamu::FileError.
Script readScript(const std::string& path);

/// The header line and one stroke line (no newline), as the reader expects them.
std::string headerLine(const Script& script);
std::string strokeLine(const Stroke& stroke);
std::string stepLine(const Step& step);
/// The whole script as text.
std::string formatScript(const Script& script);

}  // namespace kizamu::sculpt
