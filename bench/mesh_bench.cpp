// SPDX-License-Identifier: Apache-2.0
/// @file mesh_bench.cpp
/// @brief runMeshBench: the test part's full mesh, LOD meshes, points, one-tile re-mesh, the
/// OpenVDB comparison and the imported models, one function each, in that order.
#include "bench/mesh_bench.h"

#include "adf/adf_source.h"
#include "adf/generate.h"
#include "adf/test_part.h"
#include "bench/figures.h"
#include "bench/timing.h"
#include "mesh/lod.h"
#include "mesh/mesh_import.h"
#include "mesh/mesh_orientation.h"
#include "mesh/mesh_source.h"
#include "mesh/mesh_untangle.h"
#include "mesh/point_cloud.h"
#include "mesh/surface_nets.h"
#include "util/thread_pool.h"
#ifdef KIZAMU_HAVE_OPENVDB
#include "bench/openvdb_peer.h"
#endif

#include <glm/common.hpp>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <unistd.h>

namespace kizamu::bench {

namespace {

using namespace adf;

constexpr const char* kCgalData = "/usr/share/doc/libcgal-dev/data.tar.gz";

/// Median wall time (ms) of `repeats` runs of `fn` after one warm-up run.
double medianMs(int repeats, const std::function<void()>& fn) {
    fn();
    std::vector<double> ms;
    for (int r = 0; r < repeats; ++r) {
        const double t0 = nowSeconds();
        fn();
        ms.push_back((nowSeconds() - t0) * 1e3);
    }
    return median(ms);
}

/// Extracts data/meshes/NAME from Debian's CGAL data archive into `dir`.
std::string extractModel(const std::filesystem::path& dir, const std::string& name) {
    const std::string cmd = std::string("tar -xzf ") + kCgalData + " -C '" + dir.string() + "' 'data/meshes/" + name + "'";
    if (std::system(cmd.c_str()) != 0)
        throw std::runtime_error("cannot extract " + name + " from " + kCgalData + " (install libcgal-demo)");
    return (dir / "data" / "meshes" / name).string();
}

std::string stem(const std::string& file) {
    std::string s = std::filesystem::path(file).stem().string();
    while (!s.empty() && std::isdigit(static_cast<unsigned char>(s.back()))) s.pop_back();  // bunny00 -> bunny
    return s;
}

/// The export's contact pass (mesh_untangle.h) over a copy of `m`: its time and what it found.
void benchUntangle(FigureSink& out, util::ThreadPool& pool, const mesh::MeshBuffers& m, int repeats,
                   const std::string& suffix) {
    mesh::UntangleReport r;
    mesh::MeshBuffers work;
    std::vector<double> ms;
    for (int i = 0; i < std::max(1, repeats); ++i) {
        work = m;
        const double t0 = nowSeconds();
        r = mesh::untangle(work, &pool);
        ms.push_back((nowSeconds() - t0) * 1e3);
    }
    out.add("mesh.untangle_ms" + suffix, median(ms), "ms", "exports: contacts and coincident vertices found and removed");
    out.add("mesh.untangle_contacts" + suffix, double(r.contacts + r.coincidentVertices), "contacts",
            std::to_string(r.verticesMoved) + " vertices moved in " + std::to_string(r.rounds) + " rounds");
}

/// The full mesh of the test part, with its phases from the same runs; returns the mesh (the
/// re-mesh figure dabs at its vertices).
mesh::MeshBuffers benchFullMesh(FigureSink& out, util::ThreadPool& pool, const AdfPtr& part, int repeats,
                                const std::string& levelSuffix) {
    out.progress("full mesh");
    mesh::MeshBuffers full;
    // meshAdf's two steps, so the phases can be reported from the same runs.
    std::vector<double> crossingMs, vertexMs, relaxMs, assemblyMs;
    const double fullMs = medianMs(repeats, [&] {
        mesh::SurfaceMesher mesher(&pool);
        mesher.build(part);
        const double t0 = nowSeconds();
        full = mesher.mesh();
        assemblyMs.push_back((nowSeconds() - t0) * 1e3);
        crossingMs.push_back(mesher.stats().crossingMs);
        vertexMs.push_back(mesher.stats().vertexMs);
        relaxMs.push_back(mesher.stats().relaxMs);
    });
    out.add("mesh.full_ms" + levelSuffix, fullMs, "ms", "SurfaceNets of every boundary cell, into flat buffers");
    auto timed = [](std::vector<double> v) {  // the first run was medianMs's warm-up
        v.erase(v.begin());
        return median(std::move(v));
    };
    out.add("mesh.full_phase_ms.crossings" + levelSuffix, timed(crossingMs), "ms", "boundary leaves and crossings (median)");
    out.add("mesh.full_phase_ms.vertices" + levelSuffix, timed(vertexMs), "ms", "cycles, vertices, first projection");
    out.add("mesh.full_phase_ms.relax" + levelSuffix, timed(relaxMs), "ms", "split edges, relaxation, normals");
    out.add("mesh.full_phase_ms.assembly" + levelSuffix, timed(assemblyMs), "ms", "numbering and flat buffers (mesh())");
    out.add("mesh.full_triangles" + levelSuffix, double(full.triangleCount()), "triangles");
    out.add("mesh.full_vertices" + levelSuffix, double(full.vertexCount()), "vertices");
    out.add("mesh.triangles_per_s", double(full.triangleCount()) / (fullMs * 1e-3), "triangles/s", "test part" + levelSuffix);
    benchUntangle(out, pool, full, std::min(repeats, 5), levelSuffix);
    return full;
}

/// LOD meshes of about 2k and 20k triangles, whole and in their two halves.
void benchLod(FigureSink& out, util::ThreadPool& pool, const AdfPtr& part, const Domain& d, int repeats) {
    out.progress("LOD meshes");
    for (const std::size_t target : {std::size_t(2000), std::size_t(20000)}) {
        const double e = mesh::lodErrorForTriangles(part, target, &pool);
        mesh::MeshBuffers lod;
        const double ms = medianMs(repeats, [&] { lod = mesh::meshLod(part, e, &pool); });
        const std::string k = target == 2000 ? "2k" : "20k";
        out.add("mesh.lod" + k + "_ms", ms, "ms", "error " + std::to_string(e / d.finestCellSize()) + " cells");
        out.add("mesh.lod" + k + "_triangles", double(lod.triangleCount()), "triangles");
        // Its two halves (the part is unpainted: meshLod is exactly these), timed apart.
        AdfPtr coarse;
        out.add("mesh.lod" + k + "_phase_ms.coarsen", medianMs(repeats, [&] { coarse = mesh::coarsenAdf(part, e, &pool); }),
                "ms", "re-sample the coarse ADF");
        out.add("mesh.lod" + k + "_phase_ms.mesh", medianMs(repeats, [&] { lod = mesh::meshAdf(coarse, &pool); }), "ms",
                "SurfaceNets of the coarse ADF");
    }
}

/// The surface point cloud of `points` points.
void benchPoints(FigureSink& out, util::ThreadPool& pool, const AdfPtr& part, std::size_t points, int repeats) {
    out.progress("points");
    mesh::PointCloud pc;
    const double ms = medianMs(repeats, [&] { pc = mesh::surfacePointCloud(*part, points, 1, &pool); });
    const std::string name = points == 800'000 ? "800k" : std::to_string(points);
    out.add("mesh.points" + name + "_ms", ms, "ms", std::to_string(pc.positions.size()) + " points with normals");
}

/// SurfaceMesher::update after a carve dab inside one tile, at up to 15 vertices of `full`.
void benchTileRemesh(FigureSink& out, util::ThreadPool& pool, const AdfPtr& part, const Domain& d,
                     const mesh::MeshBuffers& full) {
    out.progress("incremental re-mesh of one tile");
    // A carve dab (r = 5 finest cells) well inside one tile, at surface points spread over
    // the part; the mesher re-meshes what the new snapshot does not share and splices it in.
    mesh::SurfaceMesher mesher(&pool);
    mesher.build(part);
    const double h = d.finestCellSize(), r = 5.0 * h, tile = h * double(1u << d.tileSpan());
    const SourcePtr old = makeAdfSource(part);
    std::vector<double> ms, tiles;
    std::vector<AdfPtr> dabs;
    for (std::size_t i = 0; i < full.vertexCount() && dabs.size() < 15; i += 997) {
        const glm::dvec3 c(full.positions[i]);
        const glm::dvec3 inTile = glm::mod(c - d.originWorld, tile);
        const double margin = r + 10.0 * h;
        if (glm::any(glm::lessThan(inTile, glm::dvec3(margin))) || glm::any(glm::greaterThan(inTile, glm::dvec3(tile - margin))))
            continue;
        const BoxWorld region{c - glm::dvec3(r + 2 * h), c + glm::dvec3(r + 2 * h)};
        dabs.push_back(regenerate(
            *part, *makeRegionLimited(old, makeCsg(CsgOp::Difference, old, makeTranslated(makeSphere(r), c)), region),
            region, &pool));
    }
    // Two passes over the dabs, the first untimed: a warm-up like medianMs's, so the figure
    // is the steady state, not the first touch of the mesher's fresh memory (page faults
    // that on a virtual machine can cost more than the update itself).
    for (int pass = 0; pass < 2; ++pass)
        for (const AdfPtr& edited : dabs) {
            const double t0 = nowSeconds();
            mesher.update(edited);
            const double t1 = nowSeconds();
            if (pass == 1) {
                ms.push_back((t1 - t0) * 1e3);
                tiles.push_back(double(mesher.stats().tilesMeshed));
            }
            mesher.update(part);  // back to the base for the next dab
        }
    // Then, in a loop of their own (mesh() and the shares would evict the update's caches): the
    // mesh delta of each dab (mesh_delta.h) and, for scale, mesh().
    std::vector<double> deltaMs, deltaTiles, meshMs;
    mesher.takeDelta();
    for (const AdfPtr& edited : dabs) {
        mesher.update(edited);
        const double t0 = nowSeconds();
        const mesh::MeshDelta delta = mesher.takeDelta();
        deltaMs.push_back((nowSeconds() - t0) * 1e3);
        deltaTiles.push_back(double(delta.tiles.size() + delta.removed.size()));
        const double t1 = nowSeconds();
        const mesh::MeshBuffers m = mesher.mesh();
        meshMs.push_back((nowSeconds() - t1) * 1e3);
        mesher.update(part);
        mesher.takeDelta();
    }
    if (ms.empty()) {
        out.progress("no surface point lies well inside a tile at this level: no re-mesh figure");
    } else {
        out.add("mesh.tile_remesh_ms", median(ms), "ms", "update after a dab inside one tile, median of " + std::to_string(ms.size()) + " after an untimed pass");
        out.add("mesh.tile_remesh_tiles", median(tiles), "tiles", "tiles whose vertices were recomputed (median)");
        out.add("mesh.tile_delta_ms", median(deltaMs), "ms", "takeDelta() after that update (median)");
        out.add("mesh.tile_delta_tiles", median(deltaTiles), "tiles", "tiles in that delta, changed or removed (median)");
        out.add("mesh.tile_delta_mesh_ms", median(meshMs), "ms", "mesh() after that update, for scale (median)");
    }
    // A consumer's resync: every tile's share, and the consumer's flatten of its mirror.
    mesher.update(part);
    mesh::MeshMirror mirror;
    std::vector<double> fullMs, flattenMs, assembleMs;
    for (int rep = 0; rep < 5; ++rep) {
        double t0 = nowSeconds();
        mesh::MeshDelta resync = mesher.fullDelta();
        fullMs.push_back((nowSeconds() - t0) * 1e3);
        mirror.apply(std::move(resync));
        t0 = nowSeconds();
        const mesh::MeshBuffers flat = mirror.flatten();
        flattenMs.push_back((nowSeconds() - t0) * 1e3);
        t0 = nowSeconds();
        const mesh::MeshBuffers m = mesher.mesh();
        assembleMs.push_back((nowSeconds() - t0) * 1e3);
    }
    out.add("mesh.full_delta_ms", median(fullMs), "ms", "fullDelta(): every tile's share (resync), median of 5");
    out.add("mesh.full_delta_mesh_ms", median(assembleMs), "ms", "mesh() of the same mesher, for scale, median of 5");
    out.add("mesh.mirror_flatten_ms", median(flattenMs), "ms", "MeshMirror::flatten() of the resynced mirror (consumer side, serial)");
}

#ifdef KIZAMU_HAVE_OPENVDB
/// OpenVDB's volumeToMesh of the test part beside our full mesh, interleaved. Returns the peer
/// (its level set of the test part), which the caller keeps to the end of the benchmark.
std::unique_ptr<OpenVdbPeer> compareMeshWithOpenVdb(FigureSink& out, util::ThreadPool& pool, const AdfPtr& part,
                                                    const Domain& d, int repeats, const std::string& levelSuffix) {
    out.progress("OpenVDB level set of the test part");
    auto peer = std::make_unique<OpenVdbPeer>(*makeTestPart(d), d, 3.0f);
    OpenVdbPeer::MeshResult vm;
    std::vector<double> vdbMs, ours, ratio;
    // Interleaved runs, ratio per pair: the machine is noisy.
    for (int r = 0; r < repeats; ++r) {
        vm = peer->meshSurface();
        const double t0 = nowSeconds();
        const mesh::MeshBuffers m = mesh::meshAdf(part, &pool);
        ours.push_back((nowSeconds() - t0) * 1e3);
        vdbMs.push_back(vm.seconds * 1e3);
        ratio.push_back(vdbMs.back() / ours.back());
    }
    out.add("mesh.openvdb.mesh_ms" + levelSuffix, median(vdbMs), "ms", "volumeToMesh, adaptivity 0, same lattice");
    out.add("mesh.openvdb.mesh_triangles" + levelSuffix, double(vm.triangleEquivalent()), "triangles",
            std::to_string(vm.quads) + " quads + " + std::to_string(vm.triangles) + " triangles");
    out.add("mesh.vs_openvdb.mesh_speedup", median(ratio), "ratio", "OpenVDB time / ours, same surface and lattice");
    return peer;
}
#endif

/// A real mesh from the CGAL data (extracted into `dir`): import into an ADF, then its full
/// mesh; with `vsOpenVdb`, OpenVDB's meshToLevelSet of the same triangles. `first`: the model
/// whose import gives the speed-up figure.
void benchModel(FigureSink& out, util::ThreadPool& pool, const std::filesystem::path& dir, const std::string& model,
                bool first, const MeshBenchOptions& opt, const std::string& levelSuffix) {
    const std::string name = stem(model);
    out.section(name + ", level " + std::to_string(opt.level));
    const mesh::MeshBuffers input = mesh::importMesh(extractModel(dir, model));
    GenerationSettings settings;
    const Domain md = mesh::domainAround(input, opt.level, settings.bandCells + 2.0);
    out.progress(name + ": import (" + std::to_string(input.triangleCount()) + " triangles)");
    AdfPtr a;
    const double t0 = nowSeconds();
    a = generate(*mesh::makeMeshSource(input), md, settings, &pool);
    const double importMs = (nowSeconds() - t0) * 1e3;  // one run: imports take seconds
    out.add("mesh.import_ms." + name + levelSuffix, importMs, "ms",
            std::to_string(input.triangleCount()) + " triangles -> ADF (exact distance, winding-number sign)");
    // Part of the import above (makeMeshSource orients a copy), timed alone.
    mesh::MeshBuffers copy = input;
    const double orientMs = medianMs(opt.repeats, [&] { copy.indices = input.indices; mesh::orientClosedComponents(copy); });
    out.add("mesh.orient_ms." + name + levelSuffix, orientMs, "ms", "closed parts oriented by nesting depth (in the import)");
    mesh::MeshBuffers m;
    const double ms = medianMs(opt.repeats, [&] { m = mesh::meshAdf(a, &pool); });
    out.add("mesh.full_ms." + name + levelSuffix, ms, "ms");
    out.add("mesh.full_triangles." + name + levelSuffix, double(m.triangleCount()), "triangles");
    benchUntangle(out, pool, m, std::min(opt.repeats, 5), "." + name + levelSuffix);
#ifdef KIZAMU_HAVE_OPENVDB
    if (opt.vsOpenVdb) {
        out.progress(name + ": OpenVDB meshToLevelSet");
        // The same band as ours (bandCells each side), at the same voxel size.
        const float halfWidth = float(settings.bandCells);
        const double vdbS = openVdbMeshToLevelSet(input.positions, input.indices, md.finestCellSize(), halfWidth);
        out.add("mesh.openvdb.import_ms." + name + levelSuffix, vdbS * 1e3, "ms",
                "meshToLevelSet, half width " + std::to_string(int(halfWidth)) + " voxels (our band)");
        const double vdb3 = openVdbMeshToLevelSet(input.positions, input.indices, md.finestCellSize(), 3.0f);
        out.add("mesh.openvdb.import_ms_halfwidth3." + name + levelSuffix, vdb3 * 1e3, "ms",
                "meshToLevelSet at its default half width of 3 voxels (a narrower band than ours)");
        if (first) out.add("mesh.vs_openvdb.import_speedup", vdbS * 1e3 / importMs, "ratio", "OpenVDB time / ours, " + name);
    }
#else
    (void)first;
#endif
}

}  // namespace

int runMeshBench(const MeshBenchOptions& opt) {
    FigureSink out(opt.json);
    util::ThreadPool pool(opt.threads);
    const std::string levelSuffix = ".level" + std::to_string(opt.level);
    if (!opt.json)
        std::printf("kizamu bench mesh: %u threads; times are medians of %d runs after a warm-up\n", pool.threadCount(),
                    opt.repeats);

    // ---- the test part ----
    const Domain d = testPartDomain(opt.level);
    out.section("test part, level " + std::to_string(opt.level));
    out.progress("generating the test part");
    const AdfPtr part = generate(*makeTestPart(d), d, testPartSettings(), &pool);
    const mesh::MeshBuffers full = benchFullMesh(out, pool, part, opt.repeats, levelSuffix);
    benchLod(out, pool, part, d, opt.repeats);
    benchPoints(out, pool, part, opt.points, opt.repeats);
    benchTileRemesh(out, pool, part, d, full);

    // The peer's level set stays in memory to the end, as the test part and its mesh do.
#ifdef KIZAMU_HAVE_OPENVDB
    std::unique_ptr<OpenVdbPeer> peer;
    if (opt.vsOpenVdb) peer = compareMeshWithOpenVdb(out, pool, part, d, opt.repeats, levelSuffix);
#else
    if (opt.vsOpenVdb) out.progress("OpenVDB was not found at build time: no comparison");
#endif

    // ---- real meshes ----
    const std::filesystem::path dir =
        std::filesystem::temp_directory_path() / ("kizamu_bench_mesh_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    for (const std::string& model : opt.models) benchModel(out, pool, dir, model, &model == &opt.models.front(), opt, levelSuffix);
    std::filesystem::remove_all(dir);
    return 0;
}

}  // namespace kizamu::bench
