// SPDX-License-Identifier: Apache-2.0
/// @file trajectory_player.cpp
/// @brief play(): trajectory events in time order into an Engine (trajectory_player.h).
#include "engine/trajectory_player.h"

#include <chrono>
#include <cmath>
#include <stdexcept>
#include <thread>

namespace kizamu::engine {

namespace {

using Clock = std::chrono::steady_clock;

int64_t nowNs() { return std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now().time_since_epoch()).count(); }

/// One producer's side of the playback.
class Player {
public:
    Player(Engine& engine, const PlaybackOptions& o) : mEngine(engine), mQueue(engine.samples(o.producer)) {}

    void push(const ToolSample& s) {
        while (!mQueue.push(s)) {  // the pending buffer is full of button edges: let the engine catch up
            ++report.refusals;
            std::this_thread::yield();
        }
        ++report.samples;
    }
    /// Everything pushed so far applied and meshed.
    void barrier() {
        while (!mQueue.flush()) std::this_thread::yield();
        mEngine.sync().get();
    }
    void check(std::future<CommandResult> f, const char* what) {
        const CommandResult r = f.get();
        if (!r.ok) report.errors.push_back(std::string(what) + ": " + r.message);
    }
    void toolChange(const ToolChange& c) {
        barrier();
        ++report.toolChanges;
        check(mEngine.setTool(toolSettingsOf(c)), "tool change");
    }
    void command(const CommandEvent& c) {
        barrier();
        ++report.commands;
        switch (c.command) {
        case TrajectoryCommand::Undo: check(mEngine.undo(), "undo"); break;
        case TrajectoryCommand::Redo: check(mEngine.redo(), "redo"); break;
        case TrajectoryCommand::Cancel: check(mEngine.cancelStroke(), "cancel"); break;
        }
    }

    PlaybackReport report;

private:
    Engine& mEngine;
    SampleQueue& mQueue;
};

}  // namespace

ToolSettings toolSettingsOf(const ToolChange& change) { return {change.tool, change.mirror, change.constraints}; }

PlaybackReport play(Engine& engine, const Trajectory& t, const PlaybackOptions& o) {
    if (!(o.rateHz >= 0.0) || !std::isfinite(o.rateHz)) throw std::invalid_argument("playback rate must be a finite number of Hz >= 0");
    const auto t0 = Clock::now();
    Player player(engine, o);
    const bool lockStep = o.rateHz == 0.0;
    const int64_t tickNs = lockStep ? 1'000'000 : std::max<int64_t>(1, int64_t(std::llround(1e9 / o.rateHz)));
    const int64_t first = t.events.empty() ? 0 : t.timeNs(t.events.front());
    const int64_t startNs = nowNs();
    int64_t tick = 0;  // the tick whose samples are being pushed
    for (const TrajectoryEvent& e : t.events) {
        const int64_t at = t.timeNs(e) - first;
        if (e.kind != TrajectoryEvent::Kind::Sample) {
            if (e.kind == TrajectoryEvent::Kind::ToolChange)
                player.toolChange(t.toolChanges[e.index]);
            else
                player.command(t.commands[e.index]);
            continue;
        }
        ToolSample s = t.samples[e.index];
        const int64_t due = at / tickNs;
        if (due != tick) {
            if (lockStep) {
                player.barrier();
            } else {
                // The producer wakes once per tick and pushes what is due: a device at rateHz.
                std::this_thread::sleep_until(Clock::time_point(std::chrono::nanoseconds(startNs + due * tickNs)));
            }
            tick = due;
        }
        if (!lockStep) s.timeNs = startNs + at;
        player.push(s);
    }
    player.barrier();
    player.report.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    return player.report;
}

}  // namespace kizamu::engine
