// SPDX-License-Identifier: Apache-2.0
/// @file render_output.cpp
/// @brief Shared headless-render options and the PNG write (see render_output.h).
#include "app/render_output.h"

#include "mesh/mesh_buffers.h"
#if KIZAMU_HAVE_RENDER
#include "render/image.h"
#include "render/offscreen.h"
#endif

#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>
#include <optional>
#include <stdexcept>
#include <utility>

namespace kizamu::app {

namespace {

constexpr int kMaxSide = 16384;

/// "WxH" with both in 1..kMaxSide; nullopt otherwise.
std::optional<std::pair<int, int>> parseSize(const std::string& s) {
    int w = 0, h = 0;
    char x = 0, extra = 0;
    if (std::sscanf(s.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || (x != 'x' && x != 'X'))
        return std::nullopt;
    if (w < 1 || h < 1 || w > kMaxSide || h > kMaxSide) return std::nullopt;
    return std::pair{w, h};
}

}  // namespace

void addRenderOptions(CLI::App* cmd, RenderOptions& o) {
    cmd->add_option("--size", o.size, "Picture size in pixels, WxH")
        ->check(CLI::Validator(
            [](std::string& s) {
                return parseSize(s) ? std::string()
                                    : "expected WxH with sides 1 to " + std::to_string(kMaxSide) +
                                          ", got '" + s + "'";
            },
            "WxH"))
        ->capture_default_str();
    cmd->add_option("--view", o.view,
                    "Camera view, Blender's axes (Z up; front looks along +Y, right along -X, top "
                    "along -Z; iso: "
                    "front-right-above)")
        ->check(CLI::IsMember({"iso", "front", "back", "left", "right", "top", "bottom"}))
        ->capture_default_str();
    cmd->add_option("--mode", o.mode,
                    "Shading: lit clay, matcap, points (lit discs at the vertices, a fast global view), or "
                    "wireframe (lit with the triangle edges)")
        ->check(CLI::IsMember({"lit", "matcap", "points", "wireframe"}))
        ->capture_default_str();
    cmd->add_flag("--ortho", o.ortho, "Orthographic projection (default: perspective)");
    cmd->add_flag("--ground", o.ground, "A floor under the model with a soft contact shadow");
}

#if KIZAMU_HAVE_RENDER

void checkRendererBuilt(const std::string&) {}

void renderToPng(const mesh::MeshBuffers& m, const RenderOptions& o, const std::string& path,
                 const std::vector<render::CellBox>* cells) {
    const auto t0 = std::chrono::steady_clock::now();
    render::OffscreenView v;
    const auto wh = parseSize(o.size);
    v.width = wh->first;
    v.height = wh->second;
    v.view = *render::viewAxisOf(o.view);
    v.projection = o.ortho ? render::Projection::Orthographic : render::Projection::Perspective;
    render::applyModeName(o.mode, v.settings);
    v.settings.ground = o.ground;
    if (cells) {
        v.settings.cells = true;
        v.cellBoxes = *cells;
    }
    const render::Image image = render::renderMeshImage(m, v);
    render::writePng(path, image);
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    std::printf("rendered %dx%d (%s, %s) in %.1f ms\nwrote %s\n", v.width, v.height, o.view.c_str(),
                o.mode.c_str(), ms, path.c_str());
}

#else

void checkRendererBuilt(const std::string& path) {
    throw std::runtime_error(
        "cannot render " + path +
        ": this kizamu was built without the renderer (KIZAMU_BUILD_RENDER=OFF)");
}

void renderToPng(const mesh::MeshBuffers&, const RenderOptions&, const std::string& path,
                 const std::vector<render::CellBox>*) {
    checkRendererBuilt(path);
}

#endif

}  // namespace kizamu::app
