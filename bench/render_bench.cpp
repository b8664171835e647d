// SPDX-License-Identifier: Apache-2.0
/// @file render_bench.cpp
/// @brief runRenderBench: frame times, draw calls, sample-to-visible latency, off screen.
///
/// A frame is what the sculpting window draws (src/app/sculpt_app.cpp): the clay with the floor,
/// at 1280 x 720 with 4x multisampling, waited for with glFinish so the time is the GPU's (or
/// llvmpipe's) too. Draw calls are counted by wrapping libepoxy's dispatch pointers for the
/// draw entry points during one frame. The meshes are given to the renderer as the window gives
/// them: a mesher's full delta applied to the tiled GPU mesh. The latency run drives an Engine on
/// the level-10 test part with carve dabs and plays the window's loop on this thread: take the
/// mesh delta, apply it to the tiled mesh (uploading the tiles it changed), draw, finish; it stops
/// the clock at the first frame drawn from a delta of the dab's generation, and reports that
/// beside the engine's own sample-to-mesh-delta time, the frame time, and what the deltas
/// uploaded.
#include "bench/render_bench.h"

#include "adf/snapshot_store.h"
#include "bench/figures.h"
#include "bench/timing.h"
#include "engine/engine.h"
#include "mesh/mesh_delta.h"
#include "mesh/surface_nets.h"
#include "render/camera.h"
#include "render/clay_renderer.h"
#include "render/framebuffer.h"
#include "render/gl_context.h"
#include "render/gpu_mesh.h"
#include "render/shader_program.h"
#include "sculpt/script_start.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace kizamu::bench {

namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

sculpt::Script testPart(int level) {
    sculpt::Script s;
    s.domain.maxLevel = level;
    s.start.kind = sculpt::Shape::Kind::TestPart;
    return s;
}

// ---- draw-call counting: libepoxy dispatches every GL entry point through a pointer ----
uint64_t gDrawCalls = 0;
PFNGLDRAWELEMENTSPROC gRealDrawElements = nullptr;
PFNGLDRAWARRAYSPROC gRealDrawArrays = nullptr;
PFNGLMULTIDRAWELEMENTSPROC gRealMultiDrawElements = nullptr;
void GLAPIENTRY countDrawElements(GLenum mode, GLsizei count, GLenum type, const void* indices) {
    ++gDrawCalls;
    gRealDrawElements(mode, count, type, indices);
}
void GLAPIENTRY countDrawArrays(GLenum mode, GLint first, GLsizei count) {
    ++gDrawCalls;
    gRealDrawArrays(mode, first, count);
}
void GLAPIENTRY countMultiDrawElements(GLenum mode, const GLsizei* count, GLenum type, const void* const* indices,
                                       GLsizei drawCount) {
    ++gDrawCalls;
    gRealMultiDrawElements(mode, count, type, indices, drawCount);
}

/// Draws one frame as the window does and waits for it. Returns ms.
double frame(const render::ClayRenderer& r, const render::OrbitCamera& cam, const render::Framebuffer& fb,
             const render::RenderSettings& look) {
    const auto t0 = Clock::now();
    fb.bind();
    r.draw(cam, fb.width(), fb.height(), look);
    glFinish();
    return msSince(t0);
}

render::OrbitCamera framed(const render::ClayRenderer& r, float aspect) {
    render::OrbitCamera cam;
    cam.setView(render::ViewAxis::Iso);
    cam.frame(r.boundsMin(), r.boundsMax(), aspect, 1.2f);
    return cam;
}

struct FrameFigures {
    double ms = 0.0;
    std::size_t triangles = 0, tiles = 0;
    uint64_t drawCalls = 0;      ///< counted at the GL dispatch: the clay and the floor
    std::size_t clayDrawCalls = 0;  ///< the tiled mesh's own count
};

/// The test part at `level` meshed and applied to `r` as one full delta, as the window gets it.
void applyTestPart(render::ClayRenderer& r, int level) {
    mesh::SurfaceMesher mesher;
    mesher.build(sculpt::startAdf(testPart(level), 0));
    r.applyDelta(mesher.takeDelta());
}

FrameFigures timeFrames(render::ClayRenderer& r, int level, const RenderBenchOptions& o, const render::Framebuffer& fb,
                        const render::RenderSettings& look) {
    applyTestPart(r, level);
    const render::OrbitCamera cam = framed(r, float(o.width) / float(o.height));
    FrameFigures f;
    f.triangles = r.triangleCount();
    f.tiles = r.tiledMesh().tileCount();
    f.clayDrawCalls = r.tiledMesh().drawCallsPerDraw();
    frame(r, cam, fb, look);  // warm-up: the first frame compiles llvmpipe's shaders
    std::vector<double> ms;
    for (int i = 0; i < o.frames; ++i) ms.push_back(frame(r, cam, fb, look));
    f.ms = median(ms);
    gRealDrawElements = epoxy_glDrawElements;
    gRealDrawArrays = epoxy_glDrawArrays;
    gRealMultiDrawElements = epoxy_glMultiDrawElements;
    epoxy_glDrawElements = &countDrawElements;
    epoxy_glDrawArrays = &countDrawArrays;
    epoxy_glMultiDrawElements = &countMultiDrawElements;
    gDrawCalls = 0;
    frame(r, cam, fb, look);
    f.drawCalls = gDrawCalls;
    epoxy_glDrawElements = gRealDrawElements;
    epoxy_glDrawArrays = gRealDrawArrays;
    epoxy_glMultiDrawElements = gRealMultiDrawElements;
    return f;
}

}  // namespace

int runRenderBench(const RenderBenchOptions& o) {
    FigureSink out(o.json);
    const auto context = render::GlContext::createOffscreen();
    const render::ShaderLibrary shaders;
    render::ClayRenderer renderer(shaders);
    const render::Framebuffer fb(o.width, o.height, 4);
    render::RenderSettings look;
    look.ground = true;
    if (!o.json)
        std::printf("kizamu bench render: %dx%d, 4x MSAA, on %s (%s); software renderer figures are relative only\n", o.width,
                    o.height, context->renderer().c_str(), context->version().c_str());

    out.progress("the level-10 test part");
    const FrameFigures l10 = timeFrames(renderer, 10, o, fb, look);
    out.progress("the level-12 test part");
    const FrameFigures l12 = timeFrames(renderer, 12, o, fb, look);
    out.progress("the level-13 test part (about a million triangles)");
    const FrameFigures l13 = timeFrames(renderer, 13, o, fb, look);
    // The same mesh in points mode (the fast global view): the renderer still holds it.
    render::RenderSettings pointsLook = look;
    pointsLook.shade = render::ShadeMode::Points;
    const render::OrbitCamera l13Camera = framed(renderer, float(o.width) / float(o.height));
    frame(renderer, l13Camera, fb, pointsLook);  // warm-up: llvmpipe compiles the program
    std::vector<double> pointsMs;
    for (int i = 0; i < o.frames; ++i) pointsMs.push_back(frame(renderer, l13Camera, fb, pointsLook));
    const std::size_t l13Vertices = renderer.tiledMesh().vertexCount();

    // Sample to visible: dabs on the level-10 part through the engine, the window's loop here.
    out.progress("sample to visible, level 10");
    engine::EngineSettings es;
    es.start = testPart(10);
    es.correctAfterIdle = std::chrono::milliseconds(0);
    engine::Engine e(es);
    engine::ToolSettings carve;
    carve.tool.radius = 0.02;
    e.setTool(carve).get();
    const render::TiledGpuMesh& tiled = renderer.tiledMesh();
    render::OrbitCamera cam;
    std::vector<double> visible, toDelta, uploadMs, uploadBytes, reEmitted;
    for (int i = 0; i < o.edits + 1; ++i) {
        // Bring the tiled mesh up to date and draw, as an idle window would.
        while (auto d = e.takeMeshDelta()) renderer.applyDelta(std::move(*d));
        const uint64_t before = tiled.generation();
        if (i == 0) cam = framed(renderer, float(o.width) / float(o.height));
        const glm::dvec3 at(0.3 + 0.02 * i, 0.5, 0.62);  // along the part's top, a fresh spot each time
        engine::ToolSample s;
        const auto t0 = Clock::now();
        s.timeNs = std::chrono::duration_cast<std::chrono::nanoseconds>(t0.time_since_epoch()).count();
        s.posWorld = at;
        s.buttons = engine::kButtonPrimary;
        e.samples().push(s);
        s.buttons = 0;
        s.timeNs += 1000;
        e.samples().push(s);
        e.samples().flush();
        double deltaMs = -1.0, appliedMs = 0.0;
        std::size_t bytes = 0, tiles = 0;
        for (;;) {
            if (auto d = e.takeMeshDelta()) {
                if (deltaMs < 0.0) deltaMs = msSince(t0);
                const auto applied = Clock::now();
                renderer.applyDelta(std::move(*d));
                appliedMs += msSince(applied);
                bytes += tiled.lastApply().bytesUploaded;
                tiles += tiled.lastApply().tilesReEmitted;
            }
            frame(renderer, cam, fb, look);
            if (tiled.generation() != before && deltaMs >= 0.0) break;
            if (msSince(t0) > 5000.0) break;  // a lost dab: counted by the missing figure below
        }
        if (i == 0 || deltaMs < 0.0) continue;  // the first dab also warms the engine's caches
        visible.push_back(msSince(t0));
        toDelta.push_back(deltaMs);
        uploadMs.push_back(appliedMs);
        uploadBytes.push_back(double(bytes));
        reEmitted.push_back(double(tiles));
        e.sync().get();
    }

    // For comparison, what a delta cost without tiles: flatten a mirror of the whole mesh and
    // upload it all.
    std::vector<double> wholeUploadMs;
    e.requestFullMesh();
    const auto asked = Clock::now();
    std::optional<mesh::MeshDelta> full;
    while (!(full = e.takeMeshDelta()) && msSince(asked) < 5000.0) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    if (full) {
        mesh::MeshMirror mirror;
        mirror.apply(std::move(*full));
        render::GpuMesh whole;
        for (int i = 0; i < 5; ++i) {
            const auto t0 = Clock::now();
            whole.upload(mirror.flatten());
            glFinish();
            wholeUploadMs.push_back(msSince(t0));
        }
    }

    out.section("frames (" + std::to_string(o.width) + "x" + std::to_string(o.height) + ", 4x MSAA, the clay and the floor, glFinish)");
    out.add("render.frame_ms.level10", l10.ms, "ms", std::to_string(l10.triangles) + " triangles");
    out.add("render.frame_ms.1m_triangles", l13.ms, "ms", "the level-13 test part, " + std::to_string(l13.triangles) + " triangles");
    out.add("render.triangles.1m", double(l13.triangles), "triangles");
    out.add("render.frame_ms.points.1m_triangles", median(pointsMs), "ms",
            "the same part in points mode: " + std::to_string(l13Vertices) + " discs");
    out.add("render.frame_ms.level12", l12.ms, "ms", std::to_string(l12.triangles) + " triangles");
    out.add("render.draw_calls.level12", double(l12.drawCalls), "calls",
            "per frame, counted at the GL dispatch: the floor and the clay (" + std::to_string(l12.clayDrawCalls) +
                " by the tiled mesh's count, " + std::to_string(l12.tiles) + " tiles)");
    const double frameMs = l10.ms;
    const double vis = visible.empty() ? NAN : median(visible), del = toDelta.empty() ? NAN : median(toDelta);
    out.section("a carve dab on the level-10 part: sample to the first frame that shows it");
    out.add("render.edit_to_visible_ms", vis, "ms", "median of " + std::to_string(visible.size()) + " dabs");
    out.add("render.edit_to_mesh_ms", del, "ms", "the engine's part: sample to mesh delta");
    out.add("render.edit_to_visible_frames", (vis - del) / frameMs, "frames",
            "beyond the engine's latency, in level-10 frame times; target <= 2");
    const double wholeBytes = double(tiled.vertexCount() * 32 + tiled.triangleCount() * 12);
    out.add("render.edit_upload_bytes", uploadBytes.empty() ? NAN : median(uploadBytes), "bytes",
            "a dab's deltas applied to the tiled mesh, median; " +
                std::to_string(reEmitted.empty() ? 0 : int(median(reEmitted))) + " of " +
                std::to_string(tiled.tileCount()) + " tiles re-emitted; the whole mesh is " +
                std::to_string(std::size_t(wholeBytes)) + " bytes");
    out.add("render.edit_upload_ms", uploadMs.empty() ? NAN : median(uploadMs), "ms",
            "applying a dab's deltas to the tiled mesh (CPU and upload), median");
    out.add("render.whole_upload_ms", wholeUploadMs.empty() ? NAN : median(wholeUploadMs), "ms",
            "the same mesh flattened from a mirror and uploaded whole (a delta's cost without tiles), median");
    return visible.size() == std::size_t(o.edits) ? 0 : 1;
}

}  // namespace kizamu::bench
