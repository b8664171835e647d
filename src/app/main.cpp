// SPDX-License-Identifier: Apache-2.0
/// @file main.cpp
/// @brief The `kizamu` executable: one binary, one subcommand per job.
///
/// Only the app decides to end the process: library code reports errors by exception (cold
/// paths) or state (hot paths), and this file turns them into a one-line message and exit code.
#include "app/commands.h"
#include "util/file_error.h"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>
#ifdef __GLIBC__
#include <malloc.h>
#endif

namespace {

/// Keeps freed memory in the process. Meshing, points and edits free and allocate buffers of
/// megabytes every frame; by default glibc hands large ones back to the kernel (fresh mmap
/// above its threshold, heap trimming on free), so the next frame takes a page fault per 4 KiB
/// again, which on a virtual machine cost 800k points three quarters of their time
/// (docs/PERFORMANCE.md, "Eleventh session"). Blocks above 32 MiB (the ceiling of glibc's
/// own adaptive threshold) are still mapped, and more than 256 MiB free at an arena's top is
/// still returned: the price is that much resident memory kept per arena at most. A value
/// glibc refuses leaves its default (the calls report it; nothing else to do). Other C
/// libraries keep their own policy.
void keepFreedMemory() {
#ifdef __GLIBC__
    (void)mallopt(M_MMAP_THRESHOLD, 32 << 20);
    (void)mallopt(M_TRIM_THRESHOLD, 256 << 20);
#endif
}

}  // namespace

int main(int argc, char** argv) {
    keepFreedMemory();
    CLI::App app{"Kizamu: sculpt digital clay held in an adaptively sampled distance field.\n"
                 "Run `kizamu <command> --help` for the options of each command."};
    app.require_subcommand(1);
    kizamu::app::addInfoCommand(app);
    kizamu::app::addGenerateCommand(app);
    kizamu::app::addConvertCommand(app);
    kizamu::app::addRunCommand(app);
    kizamu::app::addBenchCommand(app);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    } catch (const kizamu::FileError& e) {
        std::fprintf(stderr, "kizamu: %s\n", e.what());
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "kizamu: error: %s\n", e.what());
        return 1;
    }
    return 0;
}
