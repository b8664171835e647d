// SPDX-License-Identifier: Apache-2.0
/// @file progress.h
/// @brief A progress line with the time left for long commands: on stderr, on terminals only.
///
/// The work counts what it has done in atomics (a replay's strokes, a generation's tiles:
/// adf::GenerationProgress); a reporter thread reads them a few times a second and rewrites one
/// line with `\r`, so the work never waits for the display. Nothing is drawn when stderr is not
/// a terminal (a log, a pipe, a test) or with `--quiet`. ProgressMeter is the clock-free core
/// (what to draw, and when) that the unit test drives with a fake clock.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <thread>

namespace kizamu::app {

/// Seconds left at the average rate since the start; empty while unknown (nothing done yet,
/// no total, or under half a second of history to go by).
std::optional<double> secondsLeft(uint64_t done, uint64_t total, double elapsedS);

/// `seconds` as m:ss, or h:mm:ss from an hour (rounded to the second; negatives as 0).
std::string formatDuration(double seconds);

/// One line: "replay: 1234/2000 strokes (61%), 2:10 elapsed, 1:23 left"; before there is a
/// rate "..., estimating"; with no total (not known yet, or work that has no count)
/// "mesh: 0:02 elapsed".
std::string progressText(std::string_view label, std::string_view unit, uint64_t done,
                         uint64_t total, double elapsedS);

/// Decides what to draw and when: a line at most every `intervalS`, the first one `intervalS`
/// after the start (a command shorter than that draws nothing). One per progress line; not
/// thread-safe (the reporter thread owns it).
class ProgressMeter {
public:
    ProgressMeter(std::string label, std::string unit, double startS, double intervalS = 0.25);

    /// The line to draw at `nowS` (seconds on the clock `startS` was read from), or empty while
    /// the last one drawn is more recent than the interval.
    std::optional<std::string> poll(uint64_t done, uint64_t total, double nowS);

private:
    std::string mLabel, mUnit;
    double mStartS, mIntervalS, mLastS;
};

/// True when progress should be drawn: stderr is a terminal and the user did not ask for quiet.
bool progressWanted(bool quiet);

/// Draws a progress line on stderr from its own thread while it lives, reading `done` and
/// `total` (which the work updates, from any thread); erases the line when destroyed. Disabled
/// (no thread, nothing drawn) when `enabled` is false. Owned by the command on the stack, around
/// the work it reports; the counters must outlive it.
class ProgressReporter {
public:
    ProgressReporter(std::string label, std::string unit, const std::atomic<uint64_t>& done,
                     const std::atomic<uint64_t>& total, bool enabled);
    /// For work with no count: the label and the time elapsed.
    ProgressReporter(std::string label, bool enabled);
    ~ProgressReporter();
    ProgressReporter(const ProgressReporter&) = delete;
    ProgressReporter& operator=(const ProgressReporter&) = delete;

private:
    void start(std::string label, std::string unit, bool enabled);
    void loop(ProgressMeter meter);

    const std::atomic<uint64_t> mNone{0};  ///< done and total of work with no count
    const std::atomic<uint64_t>* mDone;
    const std::atomic<uint64_t>* mTotal;
    std::mutex mMutex;
    std::condition_variable mWake;
    bool mStop = false;
    std::size_t mDrawnWidth = 0;  ///< characters of the line on screen (reporter thread only)
    std::thread mThread;
};

}  // namespace kizamu::app
