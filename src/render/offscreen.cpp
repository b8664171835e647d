// SPDX-License-Identifier: Apache-2.0
/// @file offscreen.cpp
/// @brief One off-screen picture of a mesh (see offscreen.h).
#include "render/offscreen.h"

#include "render/gl_context.h"

namespace kizamu::render {

Image renderMeshImage(const mesh::MeshBuffers& m, const OffscreenView& view) {
    const auto context = GlContext::createOffscreen();
    const ShaderLibrary shaders(view.shaderDirectory.empty() ? ShaderLibrary::defaultDirectory()
                                                             : view.shaderDirectory);
    Image image;
    {
        // The renderer's GL objects go before the context does.
        ClayRenderer renderer(shaders);
        renderer.setMesh(m);
        renderer.setCellBoxes(view.cellBoxes);
        OrbitCamera camera;
        camera.projection = view.projection;
        camera.setView(view.view);
        camera.frame(renderer.mesh().boundsMin(), renderer.mesh().boundsMax(),
                     float(view.width) / float(view.height));
        image = renderer.renderToImage(camera, view.width, view.height, view.settings);
    }
    return image;
}

}  // namespace kizamu::render
