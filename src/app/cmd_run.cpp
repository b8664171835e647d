// SPDX-License-Identifier: Apache-2.0
/// @file cmd_run.cpp
/// @brief `kizamu run SCRIPT`: replays a stroke script headless and writes the result.
#include "adf/adf_file.h"
#include "app/commands.h"
#include "mesh/mesh_export.h"
#include "mesh/surface_nets.h"
#include "sculpt/sculptor.h"
#include "sculpt/stroke_script.h"
#include "util/thread_pool.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

namespace kizamu::app {

namespace {

struct RunOptions {
    std::string script, out;
    int level = 0;
    bool stats = false;
    unsigned threads = 0;
};

bool endsWith(std::string s, const std::string& ext) {
    for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
    return s.size() >= ext.size() && s.compare(s.size() - ext.size(), ext.size(), ext) == 0;
}

void runScript(const RunOptions& o) {
    const sculpt::Script script = sculpt::readScript(o.script);
    util::ThreadPool pool(o.threads);
    const auto t0 = std::chrono::steady_clock::now();
    sculpt::Sculptor sculptor(sculpt::startAdf(script, o.level, &pool), &pool);
    const double startMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    std::vector<double> ms;
    std::size_t tiles = 0;
    for (const sculpt::Stroke& s : script.strokes) {
        sculptor.apply(s);
        ms.push_back(sculptor.lastEdit().ms);
        tiles += sculptor.lastEdit().tilesRebuilt;
    }
    const double total = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    const adf::Adf& a = *sculptor.current();
    std::printf("replayed %zu strokes at level %d in %.1f ms (start shape %.1f ms)\n", script.strokes.size(),
                a.domain().maxLevel, total, startMs);
    if (o.stats) {
        const adf::Adf::Stats st = a.computeStats();
        std::vector<double> sorted = ms;
        std::sort(sorted.begin(), sorted.end());
        const double median = sorted.empty() ? 0.0 : sorted[sorted.size() / 2];
        const double p99 = sorted.empty() ? 0.0 : sorted[std::min(sorted.size() - 1, sorted.size() * 99 / 100)];
        std::printf("  strokes     median %.2f ms, p99 %.2f ms, %zu tiles rebuilt\n", median, p99, tiles);
        std::printf("  adf         %zu cells, %zu tiles, %.2f MB\n", st.cells, st.tiles, double(st.bytes()) / 1e6);
        std::printf("  undo        %zu records, %.2f MB of replaced tiles\n", sculptor.undoDepth(),
                    double(sculptor.historyBytes()) / 1e6);
    }
    if (o.out.empty()) return;
    if (endsWith(o.out, ".kza")) {
        adf::saveAdf(a, o.out);
    } else {
        const mesh::MeshBuffers m = mesh::meshAdf(sculptor.current(), &pool);
        mesh::exportMesh(m, o.out);
        std::printf("meshed: %zu vertices, %zu triangles\n", m.vertexCount(), m.triangleCount());
    }
    std::printf("wrote %s\n", o.out.c_str());
}

}  // namespace

void addRunCommand(CLI::App& app) {
    auto* cmd = app.add_subcommand("run", "Replay a stroke script (docs/STROKE-SCRIPT.md) headless and write the result");
    auto o = std::make_shared<RunOptions>();
    cmd->add_option("script", o->script, "Stroke script (.jsonl)")->required();
    cmd->add_option("--level", o->level, "Finest level to replay at (0: the script's own)")->check(CLI::Range(0, 16));
    cmd->add_option("--out", o->out, "Output: .kza, or a mesh (.obj .stl .ply .glb)");
    cmd->add_flag("--stats", o->stats, "Print per-stroke timing, memory and undo figures");
    cmd->add_option("--threads", o->threads, "Worker threads (0: all cores)")->capture_default_str();
    cmd->callback([o] { runScript(*o); });
}

}  // namespace kizamu::app
