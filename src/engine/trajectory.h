// SPDX-License-Identifier: Apache-2.0
/// @file trajectory.h
/// @brief Tool trajectories (`.trajectory.jsonl`): a recording of tool samples, tool changes
/// and commands, in time order, that `kizamu live --trajectory` feeds through the live engine.
///
/// Where it sits: the headless driver's input (issue 31) and what the haptics issue records from
/// devices. The format is JSON lines, versioned and documented in docs/TRAJECTORY.md: a header
/// (version, units, optionally the clay to start from) and then one sample, tool change or
/// command per line. Tool changes use the stroke script's tool vocabulary and are read by the
/// stroke script's own reader (sculpt/stroke_script.h), so the words and their checks are one.
/// Writing and reading back gives the same Trajectory bit for bit. Units SI (m, s); a sample's
/// time stamp is integer ns (ToolSample). Cold path: plain values, any thread, never the haptic
/// thread.
#pragma once

#include "adf/domain.h"
#include "engine/tool_sample.h"
#include "sculpt/stroke.h"

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace kizamu::engine {

/// The format version this build reads and writes.
inline constexpr int kTrajectoryVersion = 1;
/// Largest time stamp a trajectory may hold, s (about 11.6 days): below it a time in seconds,
/// read as a double, converts to the exact nanosecond.
inline constexpr double kTrajectoryMaxSeconds = 1.0e6;

/// The clay a trajectory starts from: a stroke script header's domain and start shape.
struct TrajectoryStart {
    adf::Domain domain;  ///< origin, size, default level (the driver's --level overrides it)
    sculpt::Shape shape;
};

/// A tool change: the tool every stroke (press of kButtonPrimary) started after it uses, with
/// its symmetry and constraints, as in a stroke script record without its path.
struct ToolChange {
    int64_t timeNs = 0;  ///< ns from the start of the recording
    sculpt::Tool tool;
    uint8_t mirror = 0;  ///< sculpt::Stroke::mirror bits (x 1, y 2, z 4)
    sculpt::StrokeConstraints constraints;
};

/// What a command line asks of the engine (docs/TRAJECTORY.md, "Commands").
enum class TrajectoryCommand : uint8_t { Undo, Redo, Cancel };

struct CommandEvent {
    int64_t timeNs = 0;  ///< ns from the start of the recording
    TrajectoryCommand command = TrajectoryCommand::Undo;
};

/// One record after the header, in file (= time) order: which list it is in and where.
struct TrajectoryEvent {
    enum class Kind : uint8_t { Sample, ToolChange, Command } kind = Kind::Sample;
    uint32_t index = 0;  ///< into Trajectory::samples, toolChanges or commands
};

/// A whole trajectory. Samples are kept apart from the rare tool changes and commands so that a
/// 4 kHz recording is one flat array of ToolSample; `events` interleaves the three in order.
/// Invariant (what the reader guarantees and the writer expects): event times do not decrease.
/// Owned by the caller; a plain value.
struct Trajectory {
    int version = kTrajectoryVersion;
    std::optional<TrajectoryStart> start;  ///< absent: the consumer's clay (kizamu live: --session)
    std::string device;                    ///< optional: what recorded it (free text)
    std::vector<ToolSample> samples;
    std::vector<ToolChange> toolChanges;
    std::vector<CommandEvent> commands;
    std::vector<TrajectoryEvent> events;

    void add(const ToolSample& s);
    void add(const ToolChange& c);
    void add(const CommandEvent& c);
    /// The time stamp of `e`, ns.
    int64_t timeNs(const TrajectoryEvent& e) const;
};

/// Parses trajectory text.
/// @param text      the whole file (UTF-8 JSON lines)
/// @param name      prefixes errors and warnings (the file's path)
/// @param warnings  where what was stepped over is appended, one line each ("name: line N:
///                  unknown key 'k' ignored", once per key and kind of record); may be null
/// @throw kizamu::FileError "name: line N: problem" for anything malformed: bad JSON, an unknown
///        version or unit, a missing or non-finite number, a time going backwards or out of
///        [0, kTrajectoryMaxSeconds], strength outside [0, 1], an invalid tool, an unknown command.
/// Complexity: O(size of text). Threading: any thread. Memory: allocates the result.
Trajectory parseTrajectory(std::string_view text, const std::string& name, std::vector<std::string>* warnings = nullptr);

/// Reads and parses a file. @throw kizamu::FileError (also when it cannot be read).
Trajectory readTrajectory(const std::string& path, std::vector<std::string>* warnings = nullptr);

/// The trajectory as text that parseTrajectory reads back to the same values bit for bit
/// (times as exact decimal seconds, doubles and floats in their shortest round-trip form, q, s
/// and b left out where they repeat the previous sample's). Quaternions must be unit (within
/// 1e-6; the reader normalises others). @throw std::invalid_argument when the times decrease
/// or lie outside [0, kTrajectoryMaxSeconds], or a tool change is invalid.
/// Complexity: O(events). Threading: any thread.
std::string formatTrajectory(const Trajectory& trajectory);

/// Writes formatTrajectory's text to `path` atomically (util::writeFileAtomically).
/// @throw kizamu::FileError naming the failing step; std::invalid_argument as formatTrajectory.
void writeTrajectory(const Trajectory& trajectory, const std::string& path);

/// The name a command has in the file: "undo", "redo", "cancel".
const char* commandName(TrajectoryCommand c);

}  // namespace kizamu::engine
