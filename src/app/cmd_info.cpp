// SPDX-License-Identifier: Apache-2.0
/// @file cmd_info.cpp
/// @brief `kizamu info FILE|DIR`: level, tiles, cells, memory and bounds of a .kza file, or
/// what a session directory holds.
#include "adf/adf_breakdown.h"
#include "adf/adf_file.h"
#include "adf/colour_layer.h"
#include "app/commands.h"
#include "sculpt/session.h"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <fstream>
#include <memory>
#include <vector>
#include <string>

namespace kizamu::app {

namespace {

void printSessionInfo(const std::string& dir) {
    std::vector<std::string> warnings;
    const auto session = sculpt::Session::open(dir, nullptr, &warnings, /*readOnly=*/true);
    for (const std::string& w : warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
    std::size_t strokes = 0, undos = 0, redos = 0, corrections = 0;
    for (const sculpt::Step& s : session->journal().steps) {
        strokes += s.kind == sculpt::Step::Kind::Stroke;
        undos += s.kind == sculpt::Step::Kind::Undo;
        redos += s.kind == sculpt::Step::Kind::Redo;
        corrections += s.kind == sculpt::Step::Kind::Correct;
    }
    const adf::Adf& a = *session->sculptor().current();
    const adf::Adf::Stats st = a.computeStats();
    std::printf("%s: Kizamu session\n", dir.c_str());
    std::printf("  strokes     %zu (and %zu undo, %zu redo records); %zu steps in the checkpoint\n", strokes, undos, redos,
                session->checkpointSteps());
    std::printf("  corrections %zu recorded, %zu zones pending\n", corrections, session->sculptor().pendingCorrections().size());
    std::printf("  level       %d\n", a.domain().maxLevel);
    std::printf("  cells       %zu leaves, %.2f MB\n", st.cells, double(st.bytes()) / 1e6);
}

void printInfo(const std::string& path, bool breakdown) {
    if (sculpt::isSessionDir(path)) {
        printSessionInfo(path);
        return;
    }
    const adf::AdfPtr a = adf::loadAdf(path);
    const adf::Domain& d = a->domain();
    const adf::GenerationSettings& s = a->settings();
    const adf::Adf::Stats st = a->computeStats();
    const double h = d.finestCellSize();
    uint32_t format = 0;  // the file's own format version (the loader accepted it)
    if (std::ifstream f{path, std::ios::binary}; f.seekg(8) && f.read(reinterpret_cast<char*>(&format), 4)) {}
    std::printf("%s: Kizamu ADF, format %u, snapshot version %llu\n", path.c_str(), format,
                static_cast<unsigned long long>(a->version()));
    std::printf("  domain      origin (%g, %g, %g) m, size %g m\n", d.originWorld.x, d.originWorld.y,
                d.originWorld.z, d.sizeWorld);
    std::printf("  level       %d (%u^3 finest cells of %.4g mm); tiles at level %d, %d levels deep\n",
                d.maxLevel, d.latticeSize(), h * 1e3, d.tileLevel(), d.tileSpan());
    std::printf("  accuracy    eps %.3g cells at the surface (Bremer k %.3g, C %.3g) within a band of %.3g cells\n",
                s.epsilonCells, s.boundK, s.boundC, s.bandCells);
    std::printf("  tiles       %zu (%zu coarse, above the tile level)\n", st.tiles, st.coarseTiles);
    std::printf("  cells       %zu leaves (%zu on the surface), %zu nodes\n", st.cells, st.boundaryCells, st.nodes);
    std::printf("  memory      %.2f MB (%.1f bytes per cell; tiles %.2f MB, table %.2f MB, paint %.2f MB)\n",
                double(st.bytes()) / 1e6, st.bytesPerCell(), double(st.tileBytes) / 1e6,
                double(st.tableBytes) / 1e6, double(st.colourBytes) / 1e6);
    if (const auto& paint = a->colours()) {
        const adf::Rgb8 base = paint->baseColour();
        std::printf("  paint       %zu points in %zu tile slots, %.2f MB; unpainted clay (%d, %d, %d)\n", st.paintedPoints,
                    paint->slotCount(), double(st.colourBytes) / 1e6, base.r, base.g, base.b);
    }
    if (st.boundaryCells > 0)
        std::printf("  bounds      (%.6g, %.6g, %.6g) .. (%.6g, %.6g, %.6g) m (surface cells)\n",
                    st.surfaceBounds.min.x, st.surfaceBounds.min.y, st.surfaceBounds.min.z,
                    st.surfaceBounds.max.x, st.surfaceBounds.max.y, st.surfaceBounds.max.z);
    else
        std::printf("  bounds      no surface in the domain\n");
    if (breakdown) std::fputs(adf::formatBreakdown(adf::computeBreakdown(*a), d.maxLevel).c_str(), stdout);
}

}  // namespace

void addInfoCommand(CLI::App& app) {
    auto* cmd = app.add_subcommand("info", "Print level, tiles, cells, memory and bounds of a .kza file, or the strokes of a session directory");
    auto path = std::make_shared<std::string>();
    cmd->add_option("file", *path, "ADF file (.kza) or session directory")->required();
    auto breakdown = std::make_shared<bool>(false);
    cmd->add_flag("--breakdown", *breakdown, "Also print cells per level, storage kind and distance, and bytes per part");
    cmd->callback([path, breakdown] { printInfo(*path, *breakdown); });
}

}  // namespace kizamu::app
