// SPDX-License-Identifier: Apache-2.0
/// @file render_output.h
/// @brief The headless picture options the commands share (`render`, `run --render`): size,
/// view, mode, projection, and writing the PNG.
///
/// Compiled in every build; where the renderer is not built (KIZAMU_BUILD_RENDER=OFF) the
/// options still parse and renderToPng says the build has no renderer.
#pragma once

#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace kizamu::mesh {
struct MeshBuffers;
}
namespace kizamu::render {
struct CellBox;
}

namespace kizamu::app {

/// The options as parsed (checked by addRenderOptions' validators).
struct RenderOptions {
    std::string size = "1024x768";  ///< WxH, pixels
    std::string view = "iso";       ///< a render::viewAxisOf name
    std::string mode = "lit";       ///< a render::applyModeName name
    bool ortho = false;
    bool ground = false;  ///< a floor with a soft contact shadow under the model
};

/// Registers --size, --view, --mode, --ortho and --ground on `cmd`, checked at parse time (a bad --view
/// or size is refused before any work).
void addRenderOptions(CLI::App* cmd, RenderOptions& o);

/// Throws (as renderToPng would) when this build has no renderer; nothing otherwise. For
/// commands that render at the end of long work, to refuse before it.
void checkRendererBuilt(const std::string& path);

/// Renders `m` off screen as `o` asks and writes the PNG to `path`; prints what it wrote. With
/// `cells`, their boxes are drawn over the clay (the cells debug view, app/cell_view.h).
/// @throw FileError when the PNG cannot be written; std::runtime_error when no GL context can
///        be had, a shader fails (naming its file and line), or the build has no renderer.
void renderToPng(const mesh::MeshBuffers& m, const RenderOptions& o, const std::string& path,
                 const std::vector<render::CellBox>* cells = nullptr);

}  // namespace kizamu::app
