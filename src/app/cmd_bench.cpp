// SPDX-License-Identifier: Apache-2.0
/// @file cmd_bench.cpp
/// @brief `kizamu bench <area>`: the benchmarks, with the figure contract of the design brief.
#include "app/commands.h"
#include "bench/adf_bench.h"
#include "bench/edit_bench.h"
#include "bench/haptics_bench.h"
#if KIZAMU_BENCH_HAVE_RENDER
#include "bench/render_bench.h"
#if KIZAMU_HAVE_RENDER
#include "app/xr_bench.h"
#endif
#endif
#include "bench/live_bench.h"
#include "bench/mesh_bench.h"

#include <CLI/CLI.hpp>

#include <memory>
#include <stdexcept>

namespace kizamu::app {

void addBenchCommand(CLI::App& app) {
    auto* bench = app.add_subcommand("bench", "Run a benchmark: prints a table, or JSON lines with --json");
    bench->require_subcommand(1);

    auto* adfCmd = bench->add_subcommand(
        "adf", "ADF generation, memory, distance+gradient query latency and accuracy for the test part");
    auto adfOptions = std::make_shared<bench::AdfBenchOptions>();
    adfCmd->add_flag("--json", adfOptions->json, "One JSON object per figure per line, nothing else on stdout");
    adfCmd->add_flag("--vs-openvdb", adfOptions->vsOpenVdb,
                     "Also build the same part as an OpenVDB level set (levels >= 10) and compare");
    adfCmd->add_option("--levels", adfOptions->levels, "Maximum levels to run")
        ->delimiter(',')
        ->check(CLI::Range(1, 16))
        ->expected(1, 16)
        ->capture_default_str();
    adfCmd->add_option("--queries", adfOptions->queries, "Random points and walk steps per level")
        ->check(CLI::Range(std::size_t(1000), std::size_t(100'000'000)))
        ->capture_default_str();
    adfCmd->add_option("--error-points", adfOptions->errorPoints, "Band points for the accuracy figure")
        ->check(CLI::Range(std::size_t(100), std::size_t(100'000'000)))
        ->capture_default_str();
    adfCmd->add_option("--repeats", adfOptions->repeats, "Generation runs per level (median)")
        ->check(CLI::Range(1, 100))
        ->capture_default_str();
    adfCmd->add_option("--query-passes", adfOptions->queryPasses, "Timed passes over the query points (medians)")
        ->check(CLI::Range(1, 100))
        ->capture_default_str();
    adfCmd->add_option("--threads", adfOptions->threads, "Worker threads (0: one per CPU this process may use)")->capture_default_str();
    adfCmd->add_option("--tile-span", adfOptions->tileSpan, "Octree levels inside a stored tile (0: default)")
        ->check(CLI::Range(0, 8));
    adfCmd->callback([adfOptions] {
        const int rc = bench::runAdfBench(*adfOptions);
        if (rc != 0) throw CLI::RuntimeError(rc);
    });

    auto* meshCmd = bench->add_subcommand(
        "mesh", "SurfaceNets of the test part and real meshes, LOD, points, tile re-mesh, mesh import");
    auto meshOptions = std::make_shared<bench::MeshBenchOptions>();
    meshCmd->add_flag("--json", meshOptions->json, "One JSON object per figure per line, nothing else on stdout");
    meshCmd->add_flag("--vs-openvdb", meshOptions->vsOpenVdb,
                      "Also run OpenVDB's volumeToMesh and meshToLevelSet on the same inputs and compare");
    meshCmd->add_option("--level", meshOptions->level, "Finest level of the test part and the imported meshes")
        ->check(CLI::Range(4, 12))
        ->capture_default_str();
    meshCmd->add_option("--repeats", meshOptions->repeats, "Timed runs per figure (median)")->check(CLI::Range(1, 100))->capture_default_str();
    meshCmd->add_option("--points", meshOptions->points, "Point-cloud size")
        ->check(CLI::Range(std::size_t(1), std::size_t(100'000'000)))
        ->capture_default_str();
    meshCmd->add_option("--models", meshOptions->models, "Meshes from Debian's CGAL data (data/meshes/...), e.g. bunny00.off")
        ->delimiter(',')
        ->capture_default_str();
    meshCmd->add_option("--threads", meshOptions->threads, "Worker threads (0: one per CPU this process may use)")->capture_default_str();
    meshCmd->callback([meshOptions] {
        const int rc = bench::runMeshBench(*meshOptions);
        if (rc != 0) throw CLI::RuntimeError(rc);
    });

    auto* editCmd = bench->add_subcommand("edit", "Carve dabs with and without re-meshing, a long stroke, the chisel slab, undo");
    auto editOptions = std::make_shared<bench::EditBenchOptions>();
    editCmd->add_flag("--json", editOptions->json, "One JSON object per figure per line, nothing else on stdout");
    editCmd->add_flag("--vs-openvdb", editOptions->vsOpenVdb, "Also stamp the same dabs into an OpenVDB level set and mesh the region");
    editCmd->add_option("--levels", editOptions->levels, "Levels for the dabs")->delimiter(',')->check(CLI::Range(4, 14))->capture_default_str();
    editCmd->add_option("--dabs", editOptions->dabs, "Dabs per level")->check(CLI::Range(2, 10000))->capture_default_str();
    editCmd->add_option("--slab-level", editOptions->slabLevel, "Level of the slab replay")->check(CLI::Range(4, 14))->capture_default_str();
    editCmd->add_option("--slab-strokes", editOptions->slabStrokes, "Strokes of the slab to replay (0: skip)")->capture_default_str();
    editCmd->add_option("--slab-script", editOptions->slabScript, "The slab's stroke script")->capture_default_str();
    editCmd->add_option("--threads", editOptions->threads, "Worker threads (0: one per CPU this process may use)")->capture_default_str();
    editCmd->callback([editOptions] {
        const int rc = bench::runEditBench(*editOptions);
        if (rc != 0) throw CLI::RuntimeError(rc);
    });

    auto* liveCmd = bench->add_subcommand("live", "The live engine: tool-sample push cost; a 2 s carving stroke's latency to snapshot and mesh delta");
    auto liveOptions = std::make_shared<bench::LiveBenchOptions>();
    liveCmd->add_flag("--json", liveOptions->json, "One JSON object per figure per line, nothing else on stdout");
    liveCmd->add_option("--pushes", liveOptions->pushes, "Timed pushes with a draining consumer")
        ->check(CLI::Range(std::size_t(10'000), std::size_t(100'000'000)))
        ->capture_default_str();
    liveCmd->add_option("--full-pushes", liveOptions->fullPushes, "Timed pushes into a full ring")
        ->check(CLI::Range(std::size_t(1'000), std::size_t(100'000'000)))
        ->capture_default_str();
    liveCmd->add_option("--levels", liveOptions->levels, "Levels of the engine's carving stroke (none: only the queue)")
        ->expected(0, 4)
        ->check(CLI::Range(4, 14))
        ->capture_default_str();
    liveCmd->add_flag("!--no-placement", liveOptions->placement, "Skip the haptic-core and supersede comparisons");
    liveCmd->add_option("--repeats", liveOptions->repeats, "Runs of the engine's stroke per configuration (figures are medians)")
        ->check(CLI::Range(1, 99))
        ->capture_default_str();
    liveCmd->callback([liveOptions] {
        const int rc = bench::runLiveBench(*liveOptions);
        if (rc != 0) throw CLI::RuntimeError(rc);
    });

    auto* hapticsCmd = bench->add_subcommand(
        "haptics", "The real-time servo thread, bare and while the live engine carves: rate, period error, force time, missed deadlines");
    auto hapticsOptions = std::make_shared<bench::HapticsBenchOptions>();
    hapticsCmd->add_flag("--json", hapticsOptions->json, "One JSON object per figure per line, nothing else on stdout");
    hapticsCmd->add_option("--seconds", hapticsOptions->seconds, "Length of each run (s)")
        ->check(CLI::Range(0.05, 3600.0))
        ->capture_default_str();
    hapticsCmd->add_option("--rate", hapticsOptions->rateHz, "Servo rate of the main figures (Hz)")
        ->check(CLI::Range(1.0, 10000.0))
        ->capture_default_str();
    hapticsCmd->add_option("--high-rate", hapticsOptions->highRateHz, "Servo rate of the .4k figures (Hz; 0 skips them)")
        ->check(CLI::Range(0.0, 10000.0))
        ->capture_default_str();
    hapticsCmd->add_option("--level", hapticsOptions->level, "Finest level of the carved test part")
        ->check(CLI::Range(4, 14))
        ->capture_default_str();
    hapticsCmd->add_option("--repeats", hapticsOptions->repeats, "Bare and loaded runs per rate, interleaved (figures are medians)")
        ->check(CLI::Range(1, 99))
        ->capture_default_str();
    hapticsCmd->add_option("--spin-us", hapticsOptions->spinUs, "Busy-wait before each deadline (us; the loop spins at most a quarter of the period)")
        ->check(CLI::Range(0, 100))
        ->capture_default_str();
    hapticsCmd->add_option("--servo-cpu", hapticsOptions->servoCpu, "Pin the servo thread to this CPU (-1: share them all)")
        ->capture_default_str();
    hapticsCmd->add_option("--priority", hapticsOptions->priority, "SCHED_FIFO priority to ask for (0: none)")
        ->check(CLI::Range(0, 99))
        ->capture_default_str();
    hapticsCmd->callback([hapticsOptions] {
        int rc = 0;
        try {
            rc = bench::runHapticsBench(*hapticsOptions);
        } catch (const std::invalid_argument& e) {  // settings the servo loop refuses
            throw CLI::ValidationError("bench haptics", e.what());
        }
        if (rc != 0) throw CLI::RuntimeError(rc);
    });

#if KIZAMU_BENCH_HAVE_RENDER
    auto* renderCmd = bench->add_subcommand(
        "render", "The renderer off screen: frame times (level 10, about a million triangles), draw calls, sample to visible");
    auto renderOptions = std::make_shared<bench::RenderBenchOptions>();
    renderCmd->add_flag("--json", renderOptions->json, "One JSON object per figure per line, nothing else on stdout");
    renderCmd->add_option("--frames", renderOptions->frames, "Frames timed per mesh (figures are medians)")
        ->check(CLI::Range(1, 10000))
        ->capture_default_str();
    renderCmd->add_option("--edits", renderOptions->edits, "Dabs timed for the sample-to-visible latency")
        ->check(CLI::Range(1, 10000))
        ->capture_default_str();
    renderCmd->callback([renderOptions] {
        const int rc = bench::runRenderBench(*renderOptions);
        if (rc != 0) throw CLI::RuntimeError(rc);
    });
#endif
#if KIZAMU_HAVE_RENDER
    auto* xrCmd = bench->add_subcommand(
        "xr", "The headset's stereo frame against an OpenXR runtime (the simulated one by default) and the frames from a "
              "controller's carve to the headset showing it; needs an X display");
    auto xrOptions = std::make_shared<XrBenchOptions>();
    xrCmd->add_flag("--json", xrOptions->json, "One JSON object per figure per line, nothing else on stdout");
    xrCmd->add_option("--frames", xrOptions->frames, "Stereo frames timed (the figure is their median)")
        ->check(CLI::Range(1, 100000))
        ->capture_default_str();
    xrCmd->add_option("--edits", xrOptions->edits, "Carve dabs timed for the latency")->check(CLI::Range(1, 10000))->capture_default_str();
    xrCmd->callback([xrOptions] {
        const int rc = runXrBench(*xrOptions);
        if (rc != 0) throw CLI::RuntimeError(rc);
    });
#endif
}

}  // namespace kizamu::app
