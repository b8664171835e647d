// SPDX-License-Identifier: Apache-2.0
/// @file offscreen.h
/// @brief One picture of a mesh, off screen: context, renderer, framing and read-back in one
/// call (the headless commands' `--render`).
#pragma once

#include "mesh/mesh_buffers.h"
#include "render/camera.h"
#include "render/clay_renderer.h"
#include "render/image.h"

#include <filesystem>
#include <span>

namespace kizamu::render {

/// How the picture is taken. Plain data.
struct OffscreenView {
    int width = 1024, height = 768;  ///< pixels
    ViewAxis view = ViewAxis::Iso;
    Projection projection = Projection::Perspective;
    RenderSettings settings;
    /// The cells view's boxes (drawn where settings.cells); the caller keeps them alive.
    std::span<const CellBox> cellBoxes;
    /// Empty: ShaderLibrary::defaultDirectory().
    std::filesystem::path shaderDirectory;
};

/// Renders `m`, framed to fill the view, from the named axis view.
/// @throw std::runtime_error when no off-screen GL context can be had (gl_context.h), and
///        ShaderError when a shader fails (naming its file and line).
/// Complexity: context start-up, one upload, one frame. Threading: creates and destroys its own
///             GL context on the calling thread (which must have none current it relies on).
/// Memory: the mesh's GPU copy and the target, freed on return; the returned image.
Image renderMeshImage(const mesh::MeshBuffers& m, const OffscreenView& view);

}  // namespace kizamu::render
