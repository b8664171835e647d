// SPDX-License-Identifier: Apache-2.0
/// @file stroke.h
/// @brief The stroke types of the sculpting engine: a stroke (tool, path, constraints,
/// symmetry), the simple solids a stroke or a session starts from or protects, and the steps a
/// session replays (a stroke, undo, redo, a remote-field correction).
///
/// The Sculptor applies these; the stroke script format (stroke_script.h) reads and writes
/// them as JSON lines. Units: m and s. Plain values; any thread.
#pragma once

#include "adf/adf.h"
#include "adf/distance_source.h"
#include "adf/domain.h"
#include "sculpt/tool.h"

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace kizamu::sculpt {

/// A simple solid: what sculpting starts from, and the regions masks and force fields protect.
/// Kind::File is a start only (a script header's start: clay stored in a .kza file, such as an
/// imported mesh's ADF); masks and keep-out regions are the simple solids.
struct Shape {
    enum class Kind { Box, Sphere, TestPart, File } kind = Kind::Box;
    glm::dvec3 centre{0.5};      ///< m
    glm::dvec3 halfSize{0.3};    ///< m (box)
    double radius = 0.3;         ///< m (sphere)
    double rounding = 0.0;       ///< m (box edges)
    /// File: the .kza file, relative to the script's directory (Script::baseDir) or absolute.
    std::string file;
    /// File: its clay once loaded (startAdf's caller may keep it here so that it is read once;
    /// a session in memory holds only this). Not written; not compared.
    adf::AdfPtr clay;
    /// The shape's distance source for `domain` (the test part scales with it; a file start is
    /// its loaded clay, std::logic_error when `clay` is not set).
    adf::SourcePtr source(const adf::Domain& domain) const;
    /// Throws std::invalid_argument unless the sizes are positive and everything is finite (a
    /// file start: its name is not empty).
    void validate() const;
};

/// Distance-based constraints on a stroke (Kizamu 4.4). Empty by default.
struct StrokeConstraints {
    /// Surface following (Kizamu 4.1): each pose is moved along the gradient onto the offset
    /// surface `followOffset` (m, negative below the surface) of the clay before the stroke.
    std::optional<double> followOffset;
    /// Carve: remove nothing deeper than this below the original surface (m). Add and build:
    /// raise nothing higher than this above it. The original surface is the Sculptor's reference
    /// (the script's start shape).
    std::optional<double> depthLimit;
    std::optional<double> heightLimit;
    /// Regions the stroke must not change (cut-out masks).
    std::vector<Shape> masks;
    /// Force fields: regions the tool is kept out of (its poses pushed out by its bounding radius).
    std::vector<Shape> keepOut;
};

/// How a stroke was applied live (Sculptor::beginStroke ... endStroke), which replay repeats
/// to reach the live result bit for bit. Absent for a stroke applied whole.
///
/// A live stroke is applied in segments, and each segment regenerates the clay from the one
/// before: the bits depend on where the path was cut and on the dwell each segment added, not
/// only on the whole path. Segment i applies samples [cuts[i-1], cuts[i]) (cuts[-1] = 0) and
/// dwells[i]; a segment with no new samples is a dwell alone (the heat gun melts further).
/// `timesNs` and `strengths` are what the producer measured per sample (the live engine fills
/// them; replay does not read them): kept so a journal loses nothing the device reported.
struct LiveRecord {
    std::vector<uint32_t> cuts;     ///< samples applied after each segment: non-decreasing, cuts[0] >= 1, back() == samples.size()
    std::vector<double> dwells;     ///< per segment, s (>= 0, finite; one per cut)
    std::vector<int64_t> timesNs;   ///< per sample: producer time stamp, ns (non-decreasing), or empty
    std::vector<float> strengths;   ///< per sample: 0..1, or empty
};

/// One stroke: a tool moved along a path, with its constraints and symmetry.
struct Stroke {
    Tool tool;
    /// The path: a polyline of poses (at least one), or with `bezier` exactly four control
    /// points of a cubic Bezier curve (Kizamu 4.2), orientation interpolated between them.
    std::vector<ToolSample> samples;
    bool bezier = false;
    StrokeConstraints constraints;
    /// Symmetry: also apply the stroke mirrored across the domain's mid planes normal to x (bit
    /// 0), y (bit 1) and/or z (bit 2), and every combination of them.
    uint8_t mirror = 0;
    double dwell = 0.0;  ///< s the tool dwelt along the path (heat gun: melts rate × dwell)
    /// Set for a stroke applied live: its segments, which replay repeats (Sculptor::replay). Then
    /// `dwell` is the sum of `live->dwells`, added left to right from 0 as the Sculptor does.
    std::optional<LiveRecord> live;
};

/// Throws std::invalid_argument (readable) unless `stroke` can be applied and written back as
/// it is: the tool, the path, a Bezier's four controls, the constraints (depth for carving,
/// height for add and build, finite offsets, valid shapes), and a live record (LiveRecord's
/// rules; not with a Bezier curve; `dwell` the sum of its dwells). Parsing, journaling and
/// applying all check with this one function.
void validate(const Stroke& stroke);

/// One step of a sculpting history (one record after a script's header): a stroke, an undo or
/// redo of the latest one, or a remote-field correction (Kizamu 5.4) of pending zones, which
/// sessions record when they correct (before each checkpoint) so that replay corrects at the
/// same points.
struct Step {
    enum class Kind : uint8_t { Stroke, Undo, Redo, Correct } kind = Kind::Stroke;
    Stroke stroke;           ///< for Kind::Stroke
    std::size_t zones = 0;   ///< for Kind::Correct: the oldest pending zones to correct, 0 = all
    static Step undo() { return {Kind::Undo, {}, 0}; }
    static Step redo() { return {Kind::Redo, {}, 0}; }
    static Step correct(std::size_t zones = 0) { return {Kind::Correct, {}, zones}; }
};

}  // namespace kizamu::sculpt
