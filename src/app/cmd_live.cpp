// SPDX-License-Identifier: Apache-2.0
/// @file cmd_live.cpp
/// @brief `kizamu live --trajectory FILE`: a recorded trajectory through the live engine,
/// headless, and the result written; `kizamu live --device sim --hand FILE`: the servo thread
/// and the simulated stylus carving through the live engine (live_device.h).
#include "app/commands.h"
#include "app/live_device.h"
#include "engine/engine.h"
#include "engine/trajectory.h"
#include "engine/trajectory_player.h"
#include "sculpt/session.h"
#include "util/file_error.h"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <memory>
#include <string>

namespace kizamu::app {

namespace {

struct LiveOptions {
    std::string trajectory, session, out, units;
    double rate = 1000.0;
    int level = 0;
    unsigned threads = 0;
    DeviceLiveOptions device;  ///< used when --hand is given (the device's own fields)
};

void runLive(const LiveOptions& o) {
    const bool device = !o.device.hand.empty() || o.device.device != "sim";
    if (device) {
        if (!o.trajectory.empty()) throw std::runtime_error("give --trajectory or a --device, not both");
        DeviceLiveOptions d = o.device;
        d.rate = o.rate;
        d.session = o.session;
        d.out = o.out;
        d.units = o.units;
        d.level = o.level;
        d.threads = o.threads;
        runDeviceLive(d);
        return;
    }
    if (o.trajectory.empty()) throw std::runtime_error("give --trajectory FILE, or --device sim --hand FILE");
    std::vector<std::string> warnings;
    const engine::Trajectory t = engine::readTrajectory(o.trajectory, &warnings);
    for (const std::string& w : warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
    engine::EngineSettings settings;
    settings.sessionDir = o.session;
    settings.level = o.level;
    settings.threads = o.threads;
    const bool resume = !o.session.empty() && sculpt::isSessionDir(o.session);
    if (resume) {
        if (t.start) std::fprintf(stderr, "warning: %s: the session's clay is used, not the trajectory's start\n", o.trajectory.c_str());
        if (o.level != 0) throw FileError(o.session, "--level applies to a new session, not one reopened");
    } else if (t.start) {
        settings.start.domain = t.start->domain;
        settings.start.start = t.start->shape;
    } else {
        throw FileError(o.trajectory, "the trajectory names no start clay: give --session with an existing session");
    }
    engine::Engine engine(std::move(settings));
    engine::PlaybackOptions playback;
    playback.rateHz = o.rate;
    const engine::PlaybackReport r = engine::play(engine, t, playback);
    for (const std::string& e : r.errors) std::fprintf(stderr, "error: %s\n", e.c_str());
    for (const std::string& n : engine.takeNotices()) std::fprintf(stderr, "warning: %s\n", n.c_str());
    const engine::EngineStats st = engine.stats();
    std::printf("live: %zu samples, %zu tool changes, %zu commands in %.2f s: %llu strokes, %llu segments, %llu mesh updates\n",
                r.samples, r.toolChanges, r.commands, r.seconds, (unsigned long long)st.strokes,
                (unsigned long long)st.segments, (unsigned long long)st.meshUpdates);
    if (!o.out.empty()) {
        const engine::CommandResult w = isAdfPath(o.out) ? engine.save(o.out).get() : engine.exportMesh(o.out, o.units).get();
        if (!w.ok) throw std::runtime_error(w.message);
        std::printf("wrote %s\n", o.out.c_str());
    }
    if (!r.errors.empty()) throw std::runtime_error(std::to_string(r.errors.size()) + " tool changes or commands failed");
}

}  // namespace

void addLiveCommand(CLI::App& app) {
    auto* cmd = app.add_subcommand("live",
                                   "Feed a recorded tool trajectory (docs/TRAJECTORY.md), or a haptic device with the servo "
                                   "thread, through the live engine and write the result");
    auto o = std::make_shared<LiveOptions>();
    cmd->add_option("--trajectory", o->trajectory, "Tool trajectory (.trajectory.jsonl)");
    cmd->add_option("--device", o->device.device,
                    "Haptic device driving the tool: sim (the simulated stylus, with --hand), falcon[:BUS:ADDR], "
                    "hid[:/dev/hidrawN] or auto (kizamu devices lists them)")
        ->capture_default_str();
    cmd->add_option("--firmware", o->device.firmware, "The Novint Falcon's firmware file (Novint's; docs/DEVICES.md)");
    cmd->add_option("--seconds", o->device.seconds, "How long a real device runs, s (default 10)")->check(CLI::Range(0.0, 86400.0));
    cmd->add_option("--hand", o->device.hand, "Hand file scripting the simulated stylus (docs/HAND.md, examples/*hand*)");
    cmd->add_option("--record", o->device.record, "With --hand: write every servo tick to this trace (docs/HAPTIC-TRACE.md)");
    cmd->add_option("--record-trajectory", o->device.recordTrajectory,
                    "With --hand: write the tool samples the engine got as a trajectory (docs/TRAJECTORY.md)");
    cmd->add_option("--tool-radius", o->device.toolRadius, "With --hand: the carving sphere's radius, m")
        ->check(CLI::Range(1e-5, 1.0))
        ->capture_default_str();
    cmd->add_option("--stiffness", o->device.stiffness, "With --hand: wall stiffness asked for, N/m (0: the stiffest passive)")
        ->check(CLI::Range(0.0, 1e7))
        ->capture_default_str();
    cmd->add_option("--force-scale", o->device.forceScale, "With --hand: force scale, 0..1 (0: haptics off)")
        ->check(CLI::Range(0.0, 1.0))
        ->capture_default_str();
    cmd->add_option("--rate", o->rate,
                    "Producer (with --hand: servo) rate in Hz, in real time; 0: lock step, as fast as the engine goes "
                    "(the same file gives the same bits)")
        ->check(CLI::Range(0.0, 100000.0))
        ->capture_default_str();
    cmd->add_option("--level", o->level, "Finest level of a new session (0: the trajectory's own)")->check(CLI::Range(0, 16));
    cmd->add_option("--session", o->session, "Session directory: journaled as it goes; reopened when it holds one");
    cmd->add_option("--out", o->out, "Output: .kza, or a mesh (.obj .stl .ply .glb .3mf)");
    cmd->add_option("--units", o->units, "Unit of a mesh --out's coordinates (default: the format's)")
        ->check(CLI::IsMember({"mm", "cm", "m"}));
    cmd->add_option("--threads", o->threads, "Edit threads (0: the CPUs this process may use)")->capture_default_str();
    cmd->callback([o] { runLive(*o); });
}

}  // namespace kizamu::app
