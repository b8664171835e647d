// SPDX-License-Identifier: Apache-2.0
/// @file clay_renderer.h
/// @brief Draws the clay: lit (Blinn-Phong), matcap, or as lit points (surface-oriented discs, a
/// fast global view), with a wireframe overlay on request; painted vertex colours where the mesh
/// has them. Renders into the bound framebuffer or into
/// an off-screen image.
///
/// Programs: clay.vert with clay.frag + clay_shading.frag (lit), matcap.frag (matcap) and
/// wire.frag (overlay); points.vert with points.frag + clay_shading.frag (points); ground.vert
/// with ground.frag (the optional floor); cells.vert with cells.frag (the cells debug view),
/// from a `ShaderLibrary`. Colours are sRGB
/// throughout the API; shading runs in linear light.
///
/// Threading: the GL context current at construction must be current on every call; one
/// renderer per context. Not thread-safe.
#pragma once

#include "mesh/mesh_buffers.h"
#include "render/camera.h"
#include "render/cell_box_lines.h"
#include "render/framebuffer.h"
#include "render/gpu_mesh.h"
#include "render/image.h"
#include "render/shader_program.h"
#include "render/tiled_gpu_mesh.h"
#include "render/tool_body.h"

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <array>
#include <optional>
#include <span>
#include <string_view>

namespace kizamu::render {

/// Lit: shaded triangles. Matcap: the normal looked up on a lit sphere. Points: each vertex a lit
/// disc on its tangent plane, sized by its spacing (Kizamu paper 6.1), no triangles rasterised.
enum class ShadeMode { Lit, Matcap, Points };

/// What a frame looks like. Plain data.
struct RenderSettings {
    ShadeMode shade = ShadeMode::Lit;
    bool wireframe = false;  ///< triangle edges over the surface
    bool cells = false;      ///< the boxes given to ClayRenderer::setCellBoxes, over the surface
    /// A floor under the model (z = its lowest point; Z up) with a soft contact shadow, drawn
    /// only while the eye is above it.
    bool ground = false;
    glm::vec3 floorSrgb{0.36f, 0.36f, 0.38f};  ///< the floor, sRGB 0..1
    /// Unpainted clay, sRGB 0..1: a light warm grey, the colour layer's unpainted clay
    /// (adf::kClayColour, 200 192 180), so a painted mesh's unpainted parts and an unpainted
    /// mesh look the same.
    glm::vec3 claySrgb{200.0f / 255.0f, 192.0f / 255.0f, 180.0f / 255.0f};
    glm::vec3 backgroundSrgb{0.235f, 0.240f, 0.255f};  ///< cleared colour, sRGB 0..1
    glm::vec4 wireSrgba{0.10f, 0.08f, 0.07f, 0.55f};   ///< overlay lines, sRGB 0..1, alpha blended
    int samples = 4;                                   ///< MSAA samples off screen (1: none)
};

/// Where the tool is, drawn over the clay: a ring of the brush's radius on the surface under it
/// (always visible), and, with the floor, a line down to the floor and a spot there (depth cues).
struct ToolMark {
    glm::vec3 centre{0.0f};             ///< m, world: the tool's centre
    glm::vec3 normal{0.0f, 0.0f, 1.0f};  ///< unit: the surface normal under it
    float radius = 0.01f;               ///< m
    glm::vec4 ringSrgba{1.0f, 0.55f, 0.15f, 0.9f};
    /// The tool's own shape drawn as lines at the centre, `radius` in size (a hand in 3D holds
    /// it: the headset); None draws the ring alone.
    ToolBody body = ToolBody::None;
};

/// Where the clay is seen from, for draw(): world to eye, eye to clip, and the eye (world).
/// The view may scale uniformly (a headset's clay held at another size).
struct ViewSetup {
    glm::mat4 view{1.0f};
    glm::mat4 projection{1.0f};
    glm::vec3 eye{0.0f};
    bool orthographic = false;
    int viewportHeight = 1;  ///< pixels (points mode sizes its discs by it)
    /// The camera's (OrbitCamera::viewMatrix, projectionMatrix) for a width × height viewport.
    static ViewSetup of(const OrbitCamera& camera, int width, int height);
};

/// The CLI's `--mode`: "lit", "matcap", "points", or "wireframe" (lit with the overlay). Leaves
/// `settings` unchanged and returns false for any other name.
bool applyModeName(std::string_view name, RenderSettings& settings);

/// Owned by the thread that owns the GL context; not thread-safe.
class ClayRenderer {
public:
    /// Builds the programs from `shaders`. Precondition: a GL 3.3 core context is current.
    /// @throw ShaderError naming the shader file and line when one fails to compile or link.
    explicit ClayRenderer(const ShaderLibrary& shaders);
    ClayRenderer(const ClayRenderer&) = delete;
    ClayRenderer& operator=(const ClayRenderer&) = delete;
    ~ClayRenderer();

    /// Replaces the mesh drawn (whole upload; the off-screen `kizamu render` path) and drops the
    /// tiled mesh. See GpuMesh::upload.
    void setMesh(const mesh::MeshBuffers& m);
    const GpuMesh& mesh() const { return mMesh; }
    /// Applies a mesher's delta to the tiled mesh (uploading the tiles that changed) and draws
    /// that from now on, dropping a mesh given to setMesh. Returns false, changing nothing, when
    /// the delta does not follow the tiled mesh: the caller asks for a full one.
    /// See TiledGpuMesh::apply for `colour`, complexity and memory.
    bool applyDelta(mesh::MeshDelta&& delta, const VertexColourFunction& colour = {});
    /// See TiledGpuMesh::requireReset.
    void requireFullMesh() { mTiled.requireReset(); }
    /// Repaints every vertex of the tiled mesh. See TiledGpuMesh::recolour.
    void recolour(const VertexColourFunction& colour) { mTiled.recolour(colour); }
    const TiledGpuMesh& tiledMesh() const { return mTiled; }
    /// Replaces the boxes the cells view draws (RenderSettings::cells). See CellBoxLines::upload.
    void setCellBoxes(std::span<const CellBox> boxes) { mCellBoxes.upload(boxes); }
    const CellBoxLines& cellBoxes() const { return mCellBoxes; }
    /// Of the mesh drawn (the tiled one after applyDelta, else setMesh's): triangles and bounds
    /// (m, world; both zero when empty).
    std::size_t triangleCount() const;
    const glm::vec3& boundsMin() const {
        return mDrawsTiled ? mTiled.boundsMin() : mMesh.boundsMin();
    }
    const glm::vec3& boundsMax() const {
        return mDrawsTiled ? mTiled.boundsMax() : mMesh.boundsMax();
    }

    /// Clears and draws the mesh into the framebuffer bound now, over a viewport of
    /// width × height pixels already set by the caller.
    /// Complexity: one draw call (plus one each for the wireframe, the cells and the ground),
    ///             whatever the tiled mesh's tile count; O(triangles) on the GPU.
    /// Threading: the context's thread. Memory: none.
    /// State: sets depth test, culling off, polygon mode and offset, blending, and the program;
    /// leaves depth test on, blending off, fill mode and no program bound.
    void draw(const OrbitCamera& camera, int width, int height,
              const RenderSettings& settings, const ToolMark* tool = nullptr) const;
    /// The same from explicit matrices (a headset's eye).
    void draw(const ViewSetup& view, const RenderSettings& settings, const ToolMark* tool = nullptr) const;

    /// Draws into an off-screen multisampled target of width × height (kept for the next call
    /// of the same size) and reads it back: RGBA8, sRGB, top row first.
    /// @throw std::runtime_error when the target cannot be made (size beyond the driver's).
    /// Complexity: draw() plus an O(pixels) read-back that waits for the GPU.
    Image renderToImage(const OrbitCamera& camera, int width, int height,
                        const RenderSettings& settings, const ToolMark* tool = nullptr);

private:
    void drawGround(const ViewSetup& v, const RenderSettings& settings) const;
    void drawTool(const ToolMark& tool, const glm::mat4& view, const glm::mat4& projection, bool floor) const;
    void drawToolBody(const ToolMark& tool, const glm::mat4& view, const glm::mat4& projection) const;
    bool meshEmpty() const { return mDrawsTiled ? mTiled.empty() : mMesh.empty(); }
    void drawMesh() const;
    void drawMeshPoints() const;
    void drawCells(const glm::mat4& view, const glm::mat4& projection) const;
    ShaderProgram mLit, mMatcap, mPoints, mWire, mGround, mTool, mCells;
    GpuMesh mMesh;
    TiledGpuMesh mTiled;
    bool mDrawsTiled = false;  ///< which of the two holds the mesh drawn
    CellBoxLines mCellBoxes;
    mutable std::array<std::optional<GpuMesh>, 4> mToolBodies;  ///< by ToolBody, made at first use
    GLuint mEmptyVao = 0;        ///< the ground's draw reads no attributes, but core GL needs a VAO
    float mMaxPointSize = 1.0f;  ///< pixels: the driver's largest point (points mode)
    std::optional<Framebuffer> mTarget;
};

}  // namespace kizamu::render
