// SPDX-License-Identifier: Apache-2.0
/// @file cmd_generate.cpp
/// @brief `kizamu generate`: build the test part's ADF and write it as .kza.
#include "adf/adf_file.h"
#include "adf/generate.h"
#include "adf/test_part.h"
#include "app/commands.h"
#include "app/progress.h"
#include "util/thread_pool.h"

#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>
#include <memory>
#include <string>

namespace kizamu::app {

namespace {

struct GenerateOptions {
    int level = 10;
    int tileSpan = adf::Domain{}.tileSpanLevels;
    unsigned threads = 0;
    bool quiet = false;
    std::string out = "test_part.kza";
};

void runGenerate(const GenerateOptions& o) {
    adf::Domain d = adf::testPartDomain(o.level);
    d.tileSpanLevels = o.tileSpan;
    if (!d.valid()) throw std::invalid_argument("level must be 1..16 and tile span 1..8");
    util::ThreadPool pool(o.threads);
    adf::GenerationStats gen;
    const auto t0 = std::chrono::steady_clock::now();
    adf::AdfPtr a;
    {
        adf::GenerationProgress progress;
        const ProgressReporter reporter("generate", "tiles", progress.tilesDone,
                                        progress.tilesTotal, progressWanted(o.quiet));
        a = adf::generate(*adf::makeTestPart(d), d, adf::testPartSettings(), &pool, &gen,
                          &progress);
    }
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    const adf::Adf::Stats st = a->computeStats();
    std::printf("generated the test part at level %d in %.1f ms on %u threads: %zu cells, %llu distance samples, "
                "%.2f MB (%.1f B/cell)\n",
                o.level, ms, pool.threadCount(), st.cells, static_cast<unsigned long long>(gen.samples),
                double(st.bytes()) / 1e6, st.bytesPerCell());
    adf::saveAdf(*a, o.out);
    std::printf("wrote %s\n", o.out.c_str());
}

}  // namespace

void addGenerateCommand(CLI::App& app) {
    auto* cmd = app.add_subcommand("generate", "Generate the ADF of the fixed test part (docs/TEST-PART.md) into a .kza file");
    auto o = std::make_shared<GenerateOptions>();
    cmd->add_option("--level", o->level, "Maximum octree level (finest cell = domain / 2^level)")
        ->check(CLI::Range(1, 16))
        ->capture_default_str();
    cmd->add_option("--tile-span", o->tileSpan, "Octree levels inside one stored tile")
        ->check(CLI::Range(1, adf::kMaxTileSpan))
        ->capture_default_str();
    cmd->add_option("--threads", o->threads, "Worker threads (0: one per CPU this process may use)")->capture_default_str();
    cmd->add_option("-o,--out", o->out, "Output file")->capture_default_str();
    cmd->add_flag("--quiet", o->quiet, "No progress line on stderr (drawn only on a terminal)");
    cmd->callback([o] { runGenerate(*o); });
}

}  // namespace kizamu::app
