// SPDX-License-Identifier: Apache-2.0
/// @file cmd_convert.cpp
/// @brief `kizamu convert IN OUT`: between mesh formats, and from a mesh to an ADF (.kza).
#include "adf/adf_file.h"
#include "adf/generate.h"
#include "app/commands.h"
#include "mesh/mesh_export.h"
#include "mesh/mesh_import.h"
#include "mesh/mesh_source.h"
#include "util/file_error.h"
#include "util/thread_pool.h"

#include <CLI/CLI.hpp>

#include <cctype>
#include <chrono>
#include <cstdio>
#include <memory>
#include <string>

namespace kizamu::app {

namespace {

struct ConvertOptions {
    std::string in, out;
    int level = 9;
    double error = adf::GenerationSettings{}.epsilonCells;
    unsigned threads = 0;
};

bool isAdf(const std::string& path) {
    if (path.size() < 4) return false;
    std::string ext = path.substr(path.size() - 4);
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    return ext == ".kza";
}

void runConvert(const ConvertOptions& o) {
    if (isAdf(o.in))
        throw FileError(o.in, "converting an ADF to a mesh needs the mesher, which is not built yet");
    const mesh::MeshBuffers m = mesh::importMesh(o.in);
    std::printf("read %s: %zu vertices, %zu triangles\n", o.in.c_str(), m.vertexCount(), m.triangleCount());
    if (!isAdf(o.out)) {
        mesh::exportMesh(m, o.out);
        std::printf("wrote %s\n", o.out.c_str());
        return;
    }
    adf::GenerationSettings settings;
    settings.epsilonCells = o.error;
    const adf::Domain d = mesh::domainAround(m, o.level, settings.bandCells + 2.0);
    util::ThreadPool pool(o.threads);
    const auto t0 = std::chrono::steady_clock::now();
    const adf::AdfPtr a = adf::generate(*mesh::makeMeshSource(m), d, settings, &pool);
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    const adf::Adf::Stats st = a->computeStats();
    std::printf("generated a level-%d ADF in %.1f ms: %zu cells, %.2f MB\n", o.level, ms, st.cells, double(st.bytes()) / 1e6);
    adf::saveAdf(*a, o.out);
    std::printf("wrote %s\n", o.out.c_str());
}

}  // namespace

void addConvertCommand(CLI::App& app) {
    auto* cmd = app.add_subcommand(
        "convert", "Convert between mesh formats (.obj .stl .ply .off -> .obj .stl .ply .glb), or a mesh to an ADF (.kza)");
    auto o = std::make_shared<ConvertOptions>();
    cmd->add_option("in", o->in, "Input file")->required();
    cmd->add_option("out", o->out, "Output file; its extension picks the format")->required();
    cmd->add_option("--level", o->level, "Maximum octree level of the ADF (mesh -> .kza)")
        ->check(CLI::Range(1, 16))
        ->capture_default_str();
    cmd->add_option("--error", o->error, "Error bound at the surface, finest cells (mesh -> .kza)")
        ->check(CLI::Range(0.01, 10.0))
        ->capture_default_str();
    cmd->add_option("--threads", o->threads, "Worker threads (0: all cores)")->capture_default_str();
    cmd->callback([o] { runConvert(*o); });
}

}  // namespace kizamu::app
