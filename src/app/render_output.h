// SPDX-License-Identifier: Apache-2.0
/// @file render_output.h
/// @brief The headless picture options the commands share (`render`, `run --render`): size,
/// view, mode, projection, and writing the PNG.
#pragma once

#include "render/offscreen.h"

#include <string>

namespace CLI {
class App;
}

namespace kizamu::mesh {
struct MeshBuffers;
}

namespace kizamu::app {

/// The options as parsed; turned into a render::OffscreenView by view().
struct RenderOptions {
    std::string size = "1024x768";  ///< WxH, pixels
    std::string view = "iso";
    std::string mode = "lit";
    bool ortho = false;
    /// The parsed request. Precondition: the options passed their CLI checks.
    render::OffscreenView offscreenView() const;
};

/// Registers --size, --view, --mode and --ortho on `cmd`, checked at parse time (a bad --view
/// or size is refused before any work).
void addRenderOptions(CLI::App* cmd, RenderOptions& o);

/// Renders `m` off screen as `o` asks and writes the PNG to `path`; prints what it wrote.
/// @throw FileError when the PNG cannot be written; std::runtime_error when no GL context can
///        be had or a shader fails (naming its file and line).
void renderToPng(const mesh::MeshBuffers& m, const RenderOptions& o, const std::string& path);

}  // namespace kizamu::app
