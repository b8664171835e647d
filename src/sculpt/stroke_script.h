// SPDX-License-Identifier: Apache-2.0
/// @file stroke_script.h
/// @brief Stroke scripts (Kizamu 4.3): every edit as a human-readable, versioned record.
///
/// JSON lines, documented in docs/STROKE-SCRIPT.md: a header line (format, version, domain,
/// level, start shape) and then one stroke per line. Lines starting with '#' and blank lines are
/// ignored. Replaying a script gives the same ADF bit for bit; at another level, the same shape
/// at that resolution. Parsing errors name the file and line. Plain values; any thread.
#pragma once

#include "adf/distance_source.h"
#include "adf/domain.h"
#include "sculpt/tool.h"

#include <iosfwd>
#include <string>
#include <vector>

namespace kizamu::sculpt {

inline constexpr int kScriptVersion = 1;

/// What sculpting starts from.
struct StartShape {
    enum class Kind { Box, Sphere, TestPart } kind = Kind::Box;
    glm::dvec3 centre{0.5};      ///< m
    glm::dvec3 halfSize{0.3};    ///< m (box)
    double radius = 0.3;         ///< m (sphere)
    double rounding = 0.0;       ///< m (box edges)
    /// The start shape's distance source for `domain` (the test part scales with it).
    adf::SourcePtr source(const adf::Domain& domain) const;
};

struct Stroke {
    Tool tool;
    std::vector<ToolSample> samples;  ///< at least one
    /// Symmetry: also apply the stroke mirrored across the domain's mid planes normal to x (bit
    /// 0), y (bit 1) and/or z (bit 2), and every combination of them.
    uint8_t mirror = 0;
    double dwell = 0.0;  ///< s the tool dwelt along the path (heat gun: melts rate × dwell)
};

/// One record after the header: a stroke, or an undo or redo of the latest one.
struct Step {
    enum class Kind : uint8_t { Stroke, Undo, Redo } kind = Kind::Stroke;
    Stroke stroke;  ///< for Kind::Stroke
    static Step undo() { return {Kind::Undo, {}}; }
    static Step redo() { return {Kind::Redo, {}}; }
};

struct Script {
    int version = kScriptVersion;
    adf::Domain domain;  ///< origin, size and default level
    StartShape start;
    std::vector<Step> steps;
    void add(const Stroke& s) { steps.push_back({Step::Kind::Stroke, s}); }
};

/// Parses script text; `name` appears in errors.
/// @throw kizamu::FileError "name: line N: problem" for anything malformed.
Script parseScript(const std::string& text, const std::string& name);
/// Parses one record line (a stroke, {"undo": 1} or {"redo": 1}). @throw std::invalid_argument,
/// nlohmann::json::exception.
Step parseStep(const std::string& line);
/// Reads and parses a file. @throw kizamu::FileError.
Script readScript(const std::string& path);

/// The header line and one stroke line (no newline), as the reader expects them.
std::string headerLine(const Script& script);
std::string strokeLine(const Stroke& stroke);
std::string stepLine(const Step& step);
/// The whole script as text.
std::string formatScript(const Script& script);

}  // namespace kizamu::sculpt
