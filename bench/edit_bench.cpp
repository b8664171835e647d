// SPDX-License-Identifier: Apache-2.0
/// @file edit_bench.cpp
/// @brief runEditBench: per level, carve dabs (edit, re-mesh, their correction), undo and redo
/// and a 500-sample stroke; then the chisel slab replayed from its script.
#include "bench/edit_bench.h"

#include "adf/generate.h"
#include "adf/test_part.h"
#include "bench/figures.h"
#include "bench/timing.h"
#include "mesh/surface_nets.h"
#include "sculpt/script_start.h"
#include "sculpt/sculptor.h"
#include "sculpt/stroke_script.h"
#include "util/thread_pool.h"
#ifdef KIZAMU_HAVE_OPENVDB
#include "bench/openvdb_peer.h"
#endif

#include <glm/gtc/constants.hpp>

#include <cmath>
#include <cstdio>

namespace kizamu::bench {

namespace {

using namespace sculpt;

const glm::dquat kIdentity(1.0, 0.0, 0.0, 0.0);

}  // namespace

int runEditBench(const EditBenchOptions& opt) {
    FigureSink out(opt.json);
    util::ThreadPool pool(opt.threads);
    if (!opt.json)
        std::printf("kizamu bench edit: %u threads; carve dabs on the test part (sphere, radius 1 %% of the domain)\n",
                    pool.threadCount());
    for (const int level : opt.levels) {
        const std::string levelSuffix = ".level" + std::to_string(level);
        out.section("dabs, level " + std::to_string(level));
        out.progress("level " + std::to_string(level) + ": generating the test part");
        const adf::Domain d = adf::testPartDomain(level);
        const adf::AdfPtr part = adf::generate(*adf::makeTestPart(d), d, adf::testPartSettings(), &pool);
        mesh::SurfaceMesher mesher(&pool);
        mesher.build(part);
        const mesh::MeshBuffers surface = mesher.mesh();
        if (surface.vertexCount() == 0) {
            out.progress("the test part has no surface at this level: no dab figures");
            continue;
        }
        std::vector<double> edit, remesh, total;
        std::vector<double> crossingMs, vertexMs, relaxMs;  // the re-mesh's phases (SurfaceNetsStats)
        Sculptor sculptor(part, &pool);
        for (int i = 0; i < opt.dabs + 1; ++i) {  // the first is a warm-up
            Stroke dab;
            dab.tool.radius = 0.01 * d.sizeWorld;
            dab.samples = {{glm::dvec3(surface.positions[(std::size_t(i) * 7919) % surface.vertexCount()]), kIdentity}};
            const double t0 = nowSeconds();
            sculptor.apply(dab);
            const double t1 = nowSeconds();
            mesher.update(sculptor.current());
            const double t2 = nowSeconds();
            if (i == 0) continue;
            edit.push_back((t1 - t0) * 1e3);
            remesh.push_back((t2 - t1) * 1e3);
            total.push_back((t2 - t0) * 1e3);
            crossingMs.push_back(mesher.stats().crossingMs);
            vertexMs.push_back(mesher.stats().vertexMs);
            relaxMs.push_back(mesher.stats().relaxMs);
        }
        out.add("edit.dab_ms" + levelSuffix + ".p50", median(edit), "ms", "regenerate the dab's tiles");
        out.add("edit.dab_remesh_ms" + levelSuffix + ".p50", median(total), "ms", "edit + incremental re-mesh");
        out.add("edit.dab_remesh_ms" + levelSuffix + ".p99", quantile(total, 0.99), "ms");
        // Idle work a dab leaves: correcting the remote field in its zone (Kizamu 5.4).
        std::vector<double> correct;
        for (int i = 0; i < std::min(opt.dabs, 20); ++i) {
            const double t0 = nowSeconds();
            if (!sculptor.correctOne()) break;
            correct.push_back((nowSeconds() - t0) * 1e3);
        }
        if (!correct.empty()) out.add("edit.correct_ms" + levelSuffix + ".p50", median(correct), "ms", "one dab's remote-field zone");
        out.add("edit.remesh_ms" + levelSuffix + ".p50", median(remesh), "ms", "the re-mesh alone");
        out.add("edit.remesh_phase_ms.crossings" + levelSuffix + ".p50", median(crossingMs), "ms", "changed cells, scan, cells to re-mesh");
        out.add("edit.remesh_phase_ms.vertices" + levelSuffix + ".p50", median(vertexMs), "ms", "cycles, vertices, first projection");
        out.add("edit.remesh_phase_ms.relax" + levelSuffix + ".p50", median(relaxMs), "ms", "split edges, relaxation, clean-up");
        out.add("edit.dab_tiles" + levelSuffix, double(sculptor.lastEdit().tilesRebuilt), "tiles", "tiles rebuilt by the last dab");
#ifdef KIZAMU_HAVE_OPENVDB
        if (opt.vsOpenVdb) {
            // The same dab positions in an OpenVDB level set of the part at the same resolution.
            out.progress("level " + std::to_string(level) + ": OpenVDB level set");
            OpenVdbPeer peer(*adf::makeTestPart(d), d, 3.0f);
            std::vector<double> vdbTotal, vdbStamp, ratio;
            for (int i = 0; i < opt.dabs + 1; ++i) {
                const glm::dvec3 c(surface.positions[(std::size_t(i) * 7919) % surface.vertexCount()]);
                const OpenVdbPeer::DabResult r = peer.carveSphereAndMeshRegion(c, 0.01 * d.sizeWorld);
                if (i == 0) continue;
                vdbStamp.push_back(r.stampSeconds * 1e3);
                vdbTotal.push_back((r.stampSeconds + r.meshSeconds) * 1e3);
                ratio.push_back(vdbTotal.back() / total[std::size_t(i - 1)]);
            }
            out.add("edit.openvdb.dab_stamp_ms" + levelSuffix + ".p50", median(vdbStamp), "ms", "write the sphere into the band voxels");
            out.add("edit.openvdb.dab_remesh_ms" + levelSuffix + ".p50", median(vdbTotal), "ms", "stamp + copy the region + volumeToMesh");
            if (level == opt.levels.front())
                out.add("edit.vs_openvdb.dab_speedup", median(ratio), "ratio", "OpenVDB stamp + region mesh / our edit + re-mesh");
        }
#else
        if (opt.vsOpenVdb) out.progress("OpenVDB was not found at build time: no comparison");
#endif

        // Undo and redo of one stroke: a pointer swap each (the re-mesh is the mesher's).
        std::vector<double> undoMs, redoMs;
        for (int i = 0; i < 10; ++i) {
            double t0 = nowSeconds();
            sculptor.undo();
            undoMs.push_back((nowSeconds() - t0) * 1e3);
            t0 = nowSeconds();
            sculptor.redo();
            redoMs.push_back((nowSeconds() - t0) * 1e3);
        }
        if (level == opt.levels.front()) {
            out.add("edit.undo_ms", median(undoMs), "ms", "one stroke (swap to the snapshot before it)");
            out.add("edit.redo_ms", median(redoMs), "ms");
        }

        if (level == 10 || level == opt.levels.front()) {
            // A 500-sample stroke: a sphere along a circle over the part's top face.
            Stroke stroke;
            stroke.tool.radius = 0.01 * d.sizeWorld;
            const glm::dvec3 c(surface.positions[0]);
            for (int k = 0; k < 500; ++k) {
                const double a = 2.0 * glm::pi<double>() * k / 499.0;
                stroke.samples.push_back({c + 0.1 * d.sizeWorld * glm::dvec3(std::cos(a) - 1.0, std::sin(a), 0.0), kIdentity});
            }
            Sculptor s(part, &pool);
            const double t0 = nowSeconds();
            s.apply(stroke);
            out.add("edit.stroke500_ms" + levelSuffix, (nowSeconds() - t0) * 1e3, "ms",
                    "500 samples, one swept volume, " + std::to_string(s.lastEdit().tilesRebuilt) + " tiles");
        }
    }

    if (opt.slabStrokes > 0) {
        out.section("the chisel slab");
        Script script = readScript(opt.slabScript);
        if (script.steps.size() > opt.slabStrokes) script.steps.resize(opt.slabStrokes);
        out.progress("slab: " + std::to_string(script.steps.size()) + " strokes at level " + std::to_string(opt.slabLevel));
        const double t0 = nowSeconds();
        // No undo history: the figure is the clay's own memory.
        Sculptor s(startAdf(script, opt.slabLevel, &pool), &pool, 0);
        for (const Step& st : script.steps) s.replay(st);
        const std::size_t zones = s.pendingCorrections().size();
        const double t1 = nowSeconds();
        s.finishCorrections();  // the replay's result is the field after its pending corrections
        const double seconds = nowSeconds() - t0;
        const adf::Adf::Stats st = s.current()->computeStats();
        const std::string n = script.steps.size() == 2000 ? "2000" : std::to_string(script.steps.size());
        out.add("edit.slab" + n + "_s", seconds, "s",
                "level " + std::to_string(opt.slabLevel) + ", start shape and remote-field corrections included");
        out.add("edit.slab" + n + "_correction_s", nowSeconds() - t1, "s", std::to_string(zones) + " pending zones, merged");
        out.add("edit.slab" + n + "_bytes", double(st.bytes()), "B", std::to_string(st.cells) + " cells");
    }
    return 0;
}

}  // namespace kizamu::bench
