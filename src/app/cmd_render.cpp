// SPDX-License-Identifier: Apache-2.0
/// @file cmd_render.cpp
/// @brief `kizamu render INPUT --out OUT.png`: a picture of an ADF, a session or a mesh file,
/// off screen (EGL without a display; Mesa's software renderer where there is no GPU).
#include "adf/adf_file.h"
#include "adf/generate.h"
#include "app/cell_view.h"
#include "app/commands.h"
#include "app/progress.h"
#include "app/render_output.h"
#include "mesh/mesh_import.h"
#include "mesh/mesh_source.h"
#include "mesh/surface_nets.h"
#include "sculpt/session.h"
#include "util/file_error.h"
#include "util/thread_pool.h"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

namespace kizamu::app {

namespace {

struct RenderCommandOptions {
    std::string in, out;
    int level = 0;  ///< mesh input: remesh through an ADF at this level (0: as read)
    unsigned threads = 0;
    bool quiet = false;
    bool cells = false;  ///< draw the boundary cells' boxes (the cells debug view)
    RenderOptions picture;
};

/// Boxes beyond this are thinned (cell_view.h): lines enough to read the cells' sizes.
constexpr std::size_t kMaxCellBoxes = 200000;

/// The mesh `o.in` names: an ADF or a session meshed with SurfaceNets, or a mesh file as read
/// (or remeshed through a level-`o.level` ADF). `adfOut` gets the ADF meshed (null for a mesh
/// read as it is).
mesh::MeshBuffers meshOf(const RenderCommandOptions& o, util::ThreadPool& pool, adf::AdfPtr& adfOut) {
    if (sculpt::isSessionDir(o.in) || isAdfPath(o.in)) {
        if (o.level != 0)
            throw FileError(o.in, "--level applies to a mesh input (an ADF has its own level)");
        adf::AdfPtr a;
        if (sculpt::isSessionDir(o.in)) {
            std::vector<std::string> warnings;
            const auto session = sculpt::Session::open(o.in, &pool, &warnings, /*readOnly=*/true);
            for (const std::string& w : warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
            a = session->sculptor().settled();
        } else {
            a = adf::loadAdf(o.in);
        }
        const ProgressReporter reporter("mesh", progressWanted(o.quiet));
        adfOut = a;
        return mesh::meshAdf(a, &pool);
    }
    std::vector<std::string> warnings;
    mesh::MeshBuffers m = mesh::importMesh(o.in, &warnings);
    for (const std::string& w : warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
    if (o.level == 0) {
        if (o.cells) throw FileError(o.in, "--cells needs an ADF: a .kza, a session, or a mesh with --level");
        return m;
    }
    // As `convert --level`: a closed, manifold remesh (the picture is framed to fit, so the
    // mesh's unit does not matter).
    adf::GenerationSettings settings;
    const adf::Domain d = mesh::domainAround(m, o.level, settings.bandCells + 2.0);
    const adf::SourcePtr source = mesh::makeMeshSource(m, &warnings);
    const ProgressReporter reporter("generate and mesh", progressWanted(o.quiet));
    adfOut = adf::generate(*source, d, settings, &pool);
    return mesh::meshAdf(adfOut, &pool);
}

}  // namespace

void addRenderCommand(CLI::App& app) {
    auto* cmd = app.add_subcommand("render",
                                   "Render a picture (PNG) of an ADF (.kza), a session or a mesh "
                                   "file, off screen: no display is needed "
                                   "(EGL; Mesa's software renderer where there is no GPU). The "
                                   "model is framed to fill the view.");
    auto o = std::make_shared<RenderCommandOptions>();
    cmd->add_option("input", o->in,
                    "A .kza, a session directory, or a mesh (.obj .stl .ply .off .glb ...)")
        ->required();
    cmd->add_option("--out", o->out, "The PNG to write")->required();
    addRenderOptions(cmd, o->picture);
    cmd->add_option("--level", o->level,
                    "Mesh input: remesh through an ADF at this level first (0: as read)")
        ->check(CLI::Range(0, 16));
    cmd->add_flag("--cells", o->cells,
                  "Draw the ADF's leaf cells the surface passes through as boxes over the clay, "
                  "coloured by level (the cells debug view)");
    cmd->add_flag("--quiet", o->quiet, "No progress line on stderr (drawn only on a terminal)");
    cmd->add_option("--threads", o->threads, "Worker threads (0: one per CPU this process may use)")
        ->capture_default_str();
    cmd->callback([o] {
        util::ThreadPool pool(o->threads);
        adf::AdfPtr a;
        const mesh::MeshBuffers m = meshOf(*o, pool, a);
        std::printf("meshed %s: %zu vertices, %zu triangles\n", o->in.c_str(), m.vertexCount(),
                    m.triangleCount());
        if (m.triangleCount() == 0) throw FileError(o->in, "no triangles to render");
        if (!o->cells) {
            renderToPng(m, o->picture, o->out);
            return;
        }
        std::vector<render::CellBox> boxes;
        const std::size_t cells = collectBoundaryCellBoxes(*a, kMaxCellBoxes, boxes);
        std::printf("cells: %zu boundary cells, %zu drawn\n", cells, boxes.size());
        renderToPng(m, o->picture, o->out, &boxes);
    });
}

}  // namespace kizamu::app
