// SPDX-License-Identifier: Apache-2.0
/// @file cmd_convert.cpp
/// @brief `kizamu convert IN OUT`: between mesh formats and ADFs (.kza), either way.
#include "adf/adf_file.h"
#include "adf/generate.h"
#include "app/commands.h"
#include "app/progress.h"
#include "mesh/mesh_decimate.h"
#include "mesh/mesh_export.h"
#include "mesh/mesh_import.h"
#include "mesh/lod.h"
#include "mesh/mesh_source.h"
#include "mesh/surface_nets.h"
#include "sculpt/session.h"
#include "util/file_error.h"
#include "util/thread_pool.h"

#include <CLI/CLI.hpp>
#include <glm/vec3.hpp>

#include <cctype>
#include <chrono>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

namespace kizamu::app {

namespace {

struct ConvertOptions {
    std::string in, out;
    int level = 9;
    double error = adf::GenerationSettings{}.epsilonCells;
    double lod = 0.0;        ///< LOD error, finest cells (0: full resolution)
    bool levelGiven = false;  ///< mesh -> mesh goes through an ADF only when asked
    unsigned threads = 0;
    std::string units;           ///< the output mesh's unit symbol; empty: its format's default
    std::string inUnits = "mm";  ///< the input mesh's unit symbol
    bool quiet = false;
    double decimate = 0.0;  ///< a decimated copy's fraction of the triangles (0: none)
};

/// How the output mesh is written: its unit, and the mesh's own unit (the clay is in metres).
mesh::ExportOptions exportOptions(const ConvertOptions& o,
                                  mesh::LengthUnit meshUnit = mesh::LengthUnit::Metre) {
    mesh::ExportOptions e;
    e.unit = mesh::lengthUnitOf(o.units);
    e.meshUnit = meshUnit;
    return e;
}

/// With --decimate: writes the decimated copy of `m` beside o.out (mesh::decimatedPath).
void writeDecimatedCopy(const mesh::MeshBuffers& m, const ConvertOptions& o, const mesh::ExportOptions& e) {
    if (o.decimate <= 0.0) return;
    mesh::DecimateReport report;
    const mesh::MeshBuffers d = mesh::decimateMesh(m, {o.decimate, 1.0}, &report);
    const std::string path = mesh::decimatedPath(o.out);
    mesh::exportMesh(d, path, e);
    std::printf("wrote %s: %zu of %zu triangles, error %.3g (mesh units)\n", path.c_str(), report.trianglesAfter, report.trianglesBefore,
                report.errorWorld);
}

double msSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

/// Writes the SurfaceNets mesh of `a`, or its LOD mesh when o.lod > 0, to o.out.
void writeMeshOf(const adf::AdfPtr& a, const ConvertOptions& o, util::ThreadPool& pool) {
    const auto t0 = std::chrono::steady_clock::now();
    mesh::MeshBuffers m;
    mesh::UntangleReport untangled;
    double meshMs = 0.0;
    {
        const ProgressReporter reporter("mesh and write", progressWanted(o.quiet));
        m = o.lod > 0.0 ? mesh::meshLod(a, o.lod * a->domain().finestCellSize(), &pool)
                        : mesh::meshAdf(a, &pool);
        meshMs = msSince(t0);
        mesh::ExportOptions e = exportOptions(o);
        e.untangle = true;
        e.pool = &pool;
        e.untangled = &untangled;
        mesh::exportMesh(m, o.out, e);
        writeDecimatedCopy(m, o, e);
    }
    std::printf("meshed in %.1f ms: %zu vertices, %zu triangles\n", meshMs, m.vertexCount(), m.triangleCount());
    printUntangled(untangled);
}


void runConvert(const ConvertOptions& o) {
    util::ThreadPool pool(o.threads);
    if (sculpt::isSessionDir(o.in)) {
        std::vector<std::string> warnings;
        const auto session = sculpt::Session::open(o.in, &pool, &warnings, /*readOnly=*/true);
        for (const std::string& w : warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
        std::printf("opened session %s: %zu steps\n", o.in.c_str(), session->steps());
        // With pending remote-field corrections made (a session cut off before its checkpoint
        // may have some), on a copy: the session on disk is not touched.
        const adf::AdfPtr clay = session->sculptor().settled();
        if (isAdfPath(o.out)) {
            adf::saveAdf(*clay, o.out);
        } else {
            writeMeshOf(clay, o, pool);
        }
        std::printf("wrote %s\n", o.out.c_str());
        return;
    }
    if (isAdfPath(o.in)) {
        if (isAdfPath(o.out)) throw FileError(o.out, "the input is already an ADF; pick a mesh format for the output");
        const adf::AdfPtr a = adf::loadAdf(o.in);
        std::printf("read %s: level %d\n", o.in.c_str(), a->domain().maxLevel);
        writeMeshOf(a, o, pool);
        std::printf("wrote %s\n", o.out.c_str());
        return;
    }
    std::vector<std::string> warnings;
    bool inMetres = false;  // a format that declares its unit (glTF, FBX, COLLADA)
    mesh::MeshBuffers m = mesh::importMesh(o.in, &warnings, &inMetres);
    const mesh::LengthUnit inUnit = inMetres ? mesh::LengthUnit::Metre : *mesh::lengthUnitOf(o.inUnits);
    for (const std::string& w : warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
    std::printf("read %s: %zu vertices, %zu triangles\n", o.in.c_str(), m.vertexCount(), m.triangleCount());
    if (!isAdfPath(o.out) && !o.levelGiven && o.lod == 0.0) {
        // In the input's unit: with the same unit out, the coordinates are copied exactly.
        mesh::exportMesh(m, o.out, exportOptions(o, inUnit));
        writeDecimatedCopy(m, o, exportOptions(o, inUnit));
        std::printf("wrote %s\n", o.out.c_str());
        return;
    }
    mesh::scaleToMetres(m, inUnit);
    adf::GenerationSettings settings;
    settings.epsilonCells = o.error;
    const adf::Domain d = mesh::domainAround(m, o.level, settings.bandCells + 2.0);
    const auto t0 = std::chrono::steady_clock::now();
    warnings.clear();
    adf::AdfPtr a;
    {
        const adf::SourcePtr source = mesh::makeMeshSource(m, &warnings);  // closed parts oriented by nesting
        for (const std::string& w : warnings) std::fprintf(stderr, "warning: %s: %s\n", o.in.c_str(), w.c_str());
        adf::GenerationProgress progress;
        const ProgressReporter reporter("generate", "tiles", progress.tilesDone,
                                        progress.tilesTotal, progressWanted(o.quiet));
        a = adf::generate(*source, d, settings, &pool, nullptr, &progress);
    }
    const adf::Adf::Stats st = a->computeStats();
    std::printf("generated a level-%d ADF in %.1f ms: %zu cells, %.2f MB\n", o.level, msSince(t0), st.cells,
                double(st.bytes()) / 1e6);
    if (isAdfPath(o.out)) {
        adf::saveAdf(*a, o.out);
    } else {
        writeMeshOf(a, o, pool);  // a watertight remesh of the input
    }
    std::printf("wrote %s\n", o.out.c_str());
}

}  // namespace

void printUntangled(const mesh::UntangleReport& r) {
    if (r.contacts + r.coincidentVertices > 0)
        std::printf("untangled: %zu contacts and %zu coincident vertices removed (%zu vertices moved, at most %.3g m)\n",
                    r.contacts, r.coincidentVertices, r.verticesMoved, r.largestMove);
    if (r.remaining > 0)
        std::fprintf(stderr, "warning: %zu contacts are left after untangling: a slicer that welds by position may "
                             "find the mesh non-manifold there\n", r.remaining);
}

bool isAdfPath(const std::string& path) {
    if (path.size() < 4) return false;
    std::string ext = path.substr(path.size() - 4);
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    return ext == ".kza";
}

void addConvertCommand(CLI::App& app) {
    auto* cmd = app.add_subcommand(
        "convert",
        "Convert between mesh formats (.obj .stl .ply .off, and through assimp .gltf .glb .fbx .dae .3ds and more "
        "-> .obj .stl .ply .glb .3mf) and ADFs (.kza), either way. A mesh -> mesh conversion with --level or --lod "
        "goes through an ADF: a closed, manifold remesh. ADFs are in metres; mesh files in millimetres unless "
        "--units/--in-units say otherwise (.glb: metres; glTF, FBX and COLLADA inputs keep the unit they declare).");
    auto o = std::make_shared<ConvertOptions>();
    cmd->add_option("in", o->in, "Input file")->required();
    cmd->add_option("out", o->out, "Output file; its extension picks the format")->required();
    cmd->add_option("--level", o->level, "Maximum octree level of the ADF (from a mesh)")
        ->check(CLI::Range(1, 16))
        ->capture_default_str();
    cmd->add_option("--lod", o->lod,
                    "Level of detail: mesh the coarsest cells within this error, finest cells (to a mesh; 0: full)")
        ->check(CLI::Range(0.0, 1e6))
        ->capture_default_str();
    cmd->add_option("--error", o->error, "Error bound at the surface, finest cells (from a mesh)")
        ->check(CLI::Range(0.01, 10.0))
        ->capture_default_str();
    cmd->add_option("--units", o->units,
                    "Unit of the output mesh's coordinates (default: mm; .3mf records it; .glb is "
                    "always m)")
        ->check(CLI::IsMember({"mm", "cm", "m"}));
    cmd->add_option("--in-units", o->inUnits, "Unit of a mesh input's coordinates (glTF, FBX and COLLADA declare theirs and keep it)")
        ->check(CLI::IsMember({"mm", "cm", "m"}))
        ->capture_default_str();
    cmd->add_option("--decimate", o->decimate,
                    "Also write a copy with this fraction of the triangles (0 < RATIO < 1; borders kept) to NAME.decimated.EXT")
        ->check(CLI::Range(0.0, 1.0));
    cmd->add_flag("--quiet", o->quiet, "No progress line on stderr (drawn only on a terminal)");
    cmd->add_option("--threads", o->threads, "Worker threads (0: one per CPU this process may use)")->capture_default_str();
    cmd->callback([o, cmd] {
        o->levelGiven = cmd->count("--level") > 0;
        // A unit the output cannot take fails here, before the work.
        if (!isAdfPath(o->out))
            mesh::exportUnit(o->out, exportOptions(*o));
        else if (!o->units.empty())
            throw FileError(o->out, "an ADF is in metres: --units applies to mesh output");
        runConvert(*o);
    });
}

}  // namespace kizamu::app
