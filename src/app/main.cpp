// SPDX-License-Identifier: Apache-2.0
/// @file main.cpp
/// @brief The `kizamu` executable: one binary, one subcommand per job.
///
/// Only the app decides to end the process: library code reports errors by exception (cold
/// paths) or state (hot paths), and this file turns them into a one-line message and exit code.
#include "app/commands.h"
#include "app/memory_policy.h"
#include "util/file_error.h"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>
#include <system_error>
#include <thread>

namespace {

/// Parses the command line and runs the command; no exception leaves it (a thread's body).
int runCommand(int argc, char** argv) {
    CLI::App app{"Kizamu: sculpt digital clay held in an adaptively sampled distance field.\n"
                 "Run `kizamu <command> --help` for the options of each command."};
    try {
        app.require_subcommand(1);
        app.set_version_flag("--version",
                             [] { return "kizamu " KIZAMU_VERSION "\n" + kizamu::app::memoryPolicySummary(); });
        kizamu::app::addInfoCommand(app);
        kizamu::app::addGenerateCommand(app);
        kizamu::app::addConvertCommand(app);
        kizamu::app::addRunCommand(app);
#if KIZAMU_HAVE_RENDER
        kizamu::app::addRenderCommand(app);
        kizamu::app::addSculptCommand(app);
#endif
        kizamu::app::addLiveCommand(app);
        kizamu::app::addDevicesCommand(app);
#if KIZAMU_HAVE_BENCH
        kizamu::app::addBenchCommand(app);
#endif
#if KIZAMU_HAVE_RENDER
        // `kizamu` alone opens the sculpting window on a new block of clay (`kizamu sculpt`).
        if (argc == 1) {
            const char* alone[] = {argv[0], "sculpt"};
            app.parse(2, const_cast<char**>(alone));
            return 0;
        }
#endif
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    } catch (const kizamu::FileError& e) {
        std::fprintf(stderr, "kizamu: %s\n", e.what());
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "kizamu: error: %s\n", e.what());
        return 1;
    } catch (...) {
        std::fprintf(stderr, "kizamu: error: an unknown exception\n");
        return 1;
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    kizamu::app::applyMemoryPolicy();
    // The command runs on a thread started after the policy. The main thread's heap began
    // before it (the C++ runtime allocates while it starts) in 4 KiB pages, which an edit's
    // growth would touch one at a time (docs/decisions/0007-mimalloc-huge-pages.md). The
    // command's thread gets the default stack of new threads (the main thread's limit, or 2 MiB
    // without one); a command that must own the main thread (a window, on some platforms) will
    // have to run here instead.
    int code = 0;
    try {
        std::thread([&] { code = runCommand(argc, argv); }).join();
    } catch (const std::system_error&) {  // no thread to be had: the main thread does
        code = runCommand(argc, argv);
    }
    return code;
}
