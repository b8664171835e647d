// SPDX-License-Identifier: Apache-2.0
/// @file progress.cpp
/// @brief The progress line: its text, its throttle and the thread that draws it.
#include "app/progress.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>

namespace kizamu::app {

namespace {

double steadySeconds() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
        .count();
}

/// How often the reporter thread looks at the counters; the meter draws at most every 0.25 s.
constexpr std::chrono::milliseconds kPollPeriod{50};

}  // namespace

std::optional<double> secondsLeft(uint64_t done, uint64_t total, double elapsedS) {
    if (done == 0 || total == 0 || elapsedS < 0.5) return std::nullopt;
    if (done >= total) return 0.0;
    return elapsedS * double(total - done) / double(done);
}

std::string formatDuration(double seconds) {
    const long s = std::lround(std::max(0.0, seconds));
    char text[32];
    if (s >= 3600)
        std::snprintf(text, sizeof text, "%ld:%02ld:%02ld", s / 3600, s / 60 % 60, s % 60);
    else
        std::snprintf(text, sizeof text, "%ld:%02ld", s / 60, s % 60);
    return text;
}

std::string progressText(std::string_view label, std::string_view unit, uint64_t done,
                         uint64_t total, double elapsedS) {
    std::string line(label);
    line += ": ";
    if (total == 0) return line + formatDuration(elapsedS) + " elapsed";
    const unsigned percent = unsigned(std::min<uint64_t>(done, total) * 100 / total);
    line += std::to_string(done) + "/" + std::to_string(total) + " " + std::string(unit) + " (" +
            std::to_string(percent) + "%), " + formatDuration(elapsedS) + " elapsed, ";
    const std::optional<double> left = secondsLeft(done, total, elapsedS);
    return line + (left ? formatDuration(*left) + " left" : std::string("estimating"));
}

ProgressMeter::ProgressMeter(std::string label, std::string unit, double startS, double intervalS)
    : mLabel(std::move(label)),
      mUnit(std::move(unit)),
      mStartS(startS),
      mIntervalS(intervalS),
      mLastS(startS) {}

std::optional<std::string> ProgressMeter::poll(uint64_t done, uint64_t total, double nowS) {
    if (nowS - mLastS < mIntervalS) return std::nullopt;
    mLastS = nowS;
    return progressText(mLabel, mUnit, done, total, nowS - mStartS);
}

bool progressWanted(bool quiet) {
    return !quiet && ::isatty(STDERR_FILENO) == 1;
}

ProgressReporter::ProgressReporter(std::string label, std::string unit,
                                   const std::atomic<uint64_t>& done,
                                   const std::atomic<uint64_t>& total, bool enabled)
    : mDone(&done), mTotal(&total) {
    start(std::move(label), std::move(unit), enabled);
}

ProgressReporter::ProgressReporter(std::string label, bool enabled)
    : mDone(&mNone), mTotal(&mNone) {
    start(std::move(label), "", enabled);
}

void ProgressReporter::start(std::string label, std::string unit, bool enabled) {
    if (!enabled) return;
    ProgressMeter meter(std::move(label), std::move(unit), steadySeconds());
    mThread = std::thread([this, meter = std::move(meter)]() mutable { loop(std::move(meter)); });
}

ProgressReporter::~ProgressReporter() {
    if (!mThread.joinable()) return;
    {
        std::lock_guard lock(mMutex);
        mStop = true;
    }
    mWake.notify_one();
    mThread.join();
}

void ProgressReporter::loop(ProgressMeter meter) {
    std::unique_lock lock(mMutex);
    while (!mWake.wait_for(lock, kPollPeriod, [this] { return mStop; })) {
        const std::optional<std::string> line =
            meter.poll(mDone->load(std::memory_order_relaxed),
                       mTotal->load(std::memory_order_relaxed), steadySeconds());
        if (!line) continue;
        // Spaces over what is left of a longer previous line: no terminal escape codes needed.
        const std::size_t pad = mDrawnWidth > line->size() ? mDrawnWidth - line->size() : 0;
        std::fprintf(stderr, "\r%s%*s", line->c_str(), int(pad), "");
        std::fflush(stderr);
        mDrawnWidth = line->size();
    }
    if (mDrawnWidth > 0) {  // leave the terminal as it was: the command's own output follows
        std::fprintf(stderr, "\r%*s\r", int(mDrawnWidth), "");
        std::fflush(stderr);
    }
}

}  // namespace kizamu::app
