// SPDX-License-Identifier: Apache-2.0
/// @file cmd_run.cpp
/// @brief `kizamu run SCRIPT`: replays a stroke script headless and writes the result.
#include "adf/adf_file.h"
#include "app/commands.h"
#include "app/progress.h"
#include "app/render_output.h"
#include "mesh/mesh_export.h"
#include "mesh/surface_nets.h"
#include "sculpt/script_start.h"
#include "sculpt/sculptor.h"
#include "sculpt/session.h"
#include "sculpt/stroke_script.h"
#include "util/file_error.h"
#include "util/thread_pool.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

namespace kizamu::app {

namespace {

struct RunOptions {
    std::string script, out, session;
    std::string render;  ///< a PNG of the result; empty: none
    RenderOptions picture;
    std::size_t checkpointEvery = 100;
    int level = 0;
    bool stats = false;
    bool quiet = false;
    std::string units;  ///< unit symbol of a mesh --out; empty: its format's default
    unsigned threads = 0;
};

mesh::ExportOptions exportOptions(const RunOptions& o) {
    mesh::ExportOptions e;
    e.unit = mesh::lengthUnitOf(o.units);
    return e;
}

void runScript(const RunOptions& o) {
    const sculpt::Script script = sculpt::readScript(o.script);
    util::ThreadPool pool(o.threads);
    const auto t0 = std::chrono::steady_clock::now();
    // With --session every step is journaled (fsynced) as it finishes, with checkpoints.
    std::unique_ptr<sculpt::Session> session;
    std::unique_ptr<sculpt::Sculptor> plain;
    if (!o.session.empty()) {
        session = sculpt::Session::create(o.session, script, o.level, &pool);
    } else {
        plain = sculpt::makeSculptor(script, o.level, &pool);
    }
    // The session may replace its sculptor (an undo reaching before a checkpoint): ask each time.
    auto sculptor = [&]() -> const sculpt::Sculptor& { return session ? session->sculptor() : *plain; };
    const double startMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    std::vector<double> ms;
    std::size_t tiles = 0;
    {
        auto isStroke = [](const sculpt::Step& s) { return s.kind == sculpt::Step::Kind::Stroke; };
        const auto strokes = std::count_if(script.steps.begin(), script.steps.end(), isStroke);
        std::atomic<uint64_t> strokesDone{0};
        const std::atomic<uint64_t> strokesTotal{uint64_t(strokes)};
        const ProgressReporter reporter("replay", "strokes", strokesDone, strokesTotal,
                                        progressWanted(o.quiet));
        for (const sculpt::Step& s : script.steps) {
            if (session) {
                session->record(s);
                if (session->steps() % o.checkpointEvery == 0) session->checkpoint();
            } else {
                plain->replay(s);
            }
            if (s.kind != sculpt::Step::Kind::Stroke) continue;
            strokesDone.fetch_add(1, std::memory_order_relaxed);
            ms.push_back(sculptor().lastEdit().ms);
            tiles += sculptor().lastEdit().tilesRebuilt;
        }
    }
    // The result is the field after every pending remote-field correction (Kizamu 5.4).
    {
        const ProgressReporter reporter("remote-field corrections", progressWanted(o.quiet));
        if (session) {
            session->checkpoint();
        } else {
            plain->finishCorrections();
        }
    }
    const double total = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    const adf::Adf& a = *sculptor().current();
    std::printf("replayed %zu steps at level %d in %.1f ms (start shape %.1f ms)\n", script.steps.size(),
                a.domain().maxLevel, total, startMs);
    if (o.stats) {
        const adf::Adf::Stats st = a.computeStats();
        std::vector<double> sorted = ms;
        std::sort(sorted.begin(), sorted.end());
        const double median = sorted.empty() ? 0.0 : sorted[sorted.size() / 2];
        const double p99 = sorted.empty() ? 0.0 : sorted[std::min(sorted.size() - 1, sorted.size() * 99 / 100)];
        std::printf("  strokes     median %.2f ms, p99 %.2f ms, %zu tiles rebuilt\n", median, p99, tiles);
        std::printf("  adf         %zu cells, %zu tiles, %.2f MB\n", st.cells, st.tiles, double(st.bytes()) / 1e6);
        std::printf("  undo        %zu records, %.2f MB of replaced tiles\n", sculptor().undoDepth(),
                    double(sculptor().historyBytes()) / 1e6);
    }
    mesh::MeshBuffers m;  // the result's mesh, made once for --out and --render
    if (!o.out.empty() && isAdfPath(o.out)) {
        adf::saveAdf(a, o.out);
        std::printf("wrote %s\n", o.out.c_str());
    } else if (!o.out.empty()) {
        mesh::UntangleReport untangled;
        {
            const ProgressReporter reporter("mesh and write", progressWanted(o.quiet));
            m = mesh::meshAdf(sculptor().current(), &pool);
            mesh::ExportOptions e = exportOptions(o);
            e.untangle = true;
            e.pool = &pool;
            e.untangled = &untangled;
            mesh::exportMesh(m, o.out, e);
        }
        std::printf("meshed: %zu vertices, %zu triangles\n", m.vertexCount(), m.triangleCount());
        printUntangled(untangled);
        std::printf("wrote %s\n", o.out.c_str());
    }
    if (o.render.empty()) return;
    if (m.positions.empty()) {
        const ProgressReporter reporter("mesh", progressWanted(o.quiet));
        m = mesh::meshAdf(sculptor().current(), &pool);
    }
    renderToPng(m, o.picture, o.render);
}

}  // namespace

void addRunCommand(CLI::App& app) {
    auto* cmd = app.add_subcommand("run", "Replay a stroke script (docs/STROKE-SCRIPT.md) headless and write the result");
    auto o = std::make_shared<RunOptions>();
    cmd->add_option("script", o->script, "Stroke script (.jsonl)")->required();
    cmd->add_option("--level", o->level, "Finest level to replay at (0: the script's own)")->check(CLI::Range(0, 16));
    cmd->add_option("--out", o->out, "Output: .kza, or a mesh (.obj .stl .ply .glb .3mf)");
    cmd->add_option("--render", o->render, "Also render the result to this PNG, off screen (no display needed)");
    addRenderOptions(cmd, o->picture);
    cmd->add_option("--units", o->units,
                    "Unit of a mesh --out's coordinates (default: mm; .3mf records it; .glb is "
                    "always m)")
        ->check(CLI::IsMember({"mm", "cm", "m"}));
    cmd->add_flag("--quiet", o->quiet, "No progress line on stderr (drawn only on a terminal)");
    cmd->add_flag("--stats", o->stats, "Print per-stroke timing, memory and undo figures");
    cmd->add_option("--session", o->session, "Journal into this new session directory as it goes (fsync per step)");
    cmd->add_option("--checkpoint-every", o->checkpointEvery, "Steps between checkpoints in the session")
        ->check(CLI::Range(std::size_t(1), std::size_t(1) << 30))
        ->capture_default_str();
    cmd->add_option("--threads", o->threads, "Worker threads (0: one per CPU this process may use)")->capture_default_str();
    cmd->callback([o] {
        if (!o->render.empty()) checkRendererBuilt(o->render);
        // A unit the output cannot take fails here, before the replay.
        if (!o->out.empty() && !isAdfPath(o->out))
            mesh::exportUnit(o->out, exportOptions(*o));
        else if (!o->units.empty())
            throw FileError(o->out.empty() ? o->script : o->out, "--units applies to a mesh --out");
        runScript(*o);
    });
}

}  // namespace kizamu::app
