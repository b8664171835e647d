// SPDX-License-Identifier: Apache-2.0
/// @file cmd_sculpt.cpp
/// @brief `kizamu sculpt [SESSION|MESH]`: the sculpting window (sculpt_app.h).
#include "app/commands.h"
#include "app/sculpt_app.h"

#include <CLI/CLI.hpp>

#include <memory>

namespace kizamu::app {

void addSculptCommand(CLI::App& app) {
    auto* cmd = app.add_subcommand("sculpt", "Open the sculpting window (a new block of clay, a session, or a mesh to sculpt)");
    auto o = std::make_shared<SculptOptions>();
    cmd->add_option("open", o->open, "A session directory to reopen, or a mesh or .kza to start from");
    cmd->add_option("--device", o->device,
                    "What the mouse drives: sim (the simulated stylus, felt through the servo loop), falcon[:BUS:ADDR], "
                    "hid[:/dev/hidrawN], auto (a real device if one is found, else sim), or none (the mouse alone)")
        ->capture_default_str();
    cmd->add_option("--firmware", o->firmware, "The Novint Falcon's firmware file (docs/DEVICES.md)");
    cmd->add_option("--level", o->level, "Finest level of a new block or an import (0: 9)")->check(CLI::Range(0, 14));
    cmd->add_option("--session", o->session, "Journal a new session here (default: untitled, under --session-root)");
    cmd->add_option("--session-root", o->sessionRoot,
                    "Where untitled sessions go and where interrupted ones are looked for (default "
                    "$XDG_DATA_HOME/kizamu/sessions)");
    cmd->add_option("--restore", o->restore, "A session a crash left open: ask, yes (reopen it), no")
        ->check(CLI::IsMember({"ask", "yes", "no"}))
        ->capture_default_str();
    cmd->add_option("--input", o->input, "Replay this input script (docs/INPUT.md) as if typed and moved by hand");
    cmd->add_option("--frames", o->frames, "Exit after this many frames (0: when the window closes)")->check(CLI::Range(int64_t(0), int64_t(1) << 40));
    cmd->add_option("--screenshot", o->screenshot, "Write the last frame to this PNG (with --frames)");
    cmd->add_flag("--xr", o->xr,
                  "Sculpt in a headset through OpenXR (XR_RUNTIME_JSON or the system's active runtime); without one, "
                  "say why and open the desktop window");
    cmd->add_option("--hand", o->hand, "With --xr: the hand that holds the tool (the other grabs and points)")
        ->check(CLI::IsMember({"left", "right"}))
        ->capture_default_str();
    cmd->add_flag("--xr-validation", o->xrValidation, "With --xr: enable Khronos' OpenXR core validation layer");
    cmd->add_flag("--register-stylus", o->registerStylus,
                  "With --xr and a device: start by registering the stylus in the headset (touch its tip to the "
                  "controller's at four places, pulling the trigger each time); kept in "
                  "$XDG_CONFIG_HOME/kizamu/stylus-registration.json");
    cmd->add_option("--width", o->width, "Window width")->check(CLI::Range(64, 16384))->capture_default_str();
    cmd->add_option("--height", o->height, "Window height")->check(CLI::Range(64, 16384))->capture_default_str();
    cmd->callback([o] {
        const int rc = runSculptApp(*o);
        if (rc != 0) throw CLI::RuntimeError(rc);
    });
}

}  // namespace kizamu::app
