// SPDX-License-Identifier: Apache-2.0
/// @file trajectory_player.h
/// @brief Feeds a recorded trajectory (trajectory.h) through a live Engine: in real time, as
/// a device would, or in lock step as fast as the engine goes, deterministically.
///
/// What `kizamu live` runs, and what tests and benchmarks use to drive the engine from a file.
/// The player is one producer: it pushes to one of the engine's sample queues from the calling
/// thread, and sends tool changes and commands as the UI would, each after the samples before
/// it have been applied (a barrier, Engine::sync), so a tool change always falls between the
/// strokes the recording has around it.
/// Lock step (rateHz 0): the samples of each millisecond of recording time are one push batch
/// followed by a barrier, so every segment is cut at the same samples on every run and
/// machine: the same file gives the same bits. That is the cut a 1 kHz device gets from an
/// engine that keeps up with it.
#pragma once

#include "engine/engine.h"
#include "engine/trajectory.h"

#include <cstddef>
#include <string>
#include <vector>

namespace kizamu::engine {

struct PlaybackOptions {
    /// Producer ticks per second: each tick pushes the samples due by then, time stamps moved
    /// onto steady_clock. 0: lock step, as fast as the engine goes, keeping the recording's
    /// time stamps.
    double rateHz = 1000.0;
    std::size_t producer = 0;  ///< the engine's sample queue to push to
};

struct PlaybackReport {
    std::size_t samples = 0;      ///< pushed
    std::size_t refusals = 0;     ///< pushes the queue refused and the player repeated
    std::size_t toolChanges = 0;
    std::size_t commands = 0;
    std::vector<std::string> errors;  ///< failed tool changes and commands, one line each
    double seconds = 0.0;             ///< wall time of the playback
};

/// Plays `trajectory` into `engine` and returns once every sample has been applied and meshed.
/// @throw std::invalid_argument for a negative or non-finite rate, or a producer the engine lacks
/// Threading: the calling thread is the producer of `options.producer` while this runs.
PlaybackReport play(Engine& engine, const Trajectory& trajectory, const PlaybackOptions& options = {});

/// The ToolSettings of a recorded tool change.
ToolSettings toolSettingsOf(const ToolChange& change);

}  // namespace kizamu::engine
