// SPDX-License-Identifier: Apache-2.0
/// @file render_bench.cpp
/// @brief runRenderBench: frame times, draw calls, sample-to-visible latency, off screen.
///
/// A frame is what the sculpting window draws (src/app/sculpt_app.cpp): the clay with the floor,
/// at 1280 x 720 with 4x multisampling, waited for with glFinish so the time is the GPU's (or
/// llvmpipe's) too. Draw calls are counted by wrapping libepoxy's dispatch pointers for the
/// draw entry points during one frame. The latency run drives an Engine on the level-10 test
/// part with carve dabs and plays the window's loop on this thread: take the mesh delta, apply it
/// to a MeshMirror, flatten, upload, draw, finish; it stops the clock at the first frame drawn
/// from a delta of the dab's generation, and reports that beside the engine's own
/// sample-to-mesh-delta time and the frame time.
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
#include "render/shader_program.h"
#include "sculpt/script_start.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
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
void GLAPIENTRY countDrawElements(GLenum mode, GLsizei count, GLenum type, const void* indices) {
    ++gDrawCalls;
    gRealDrawElements(mode, count, type, indices);
}
void GLAPIENTRY countDrawArrays(GLenum mode, GLint first, GLsizei count) {
    ++gDrawCalls;
    gRealDrawArrays(mode, first, count);
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

render::OrbitCamera framed(const mesh::MeshBuffers& m, float aspect) {
    glm::vec3 lo(HUGE_VALF), hi(-HUGE_VALF);
    for (const glm::vec3& p : m.positions) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    render::OrbitCamera cam;
    cam.setView(render::ViewAxis::Iso);
    cam.frame(lo, hi, aspect, 1.2f);
    return cam;
}

struct FrameFigures {
    double ms = 0.0;
    std::size_t triangles = 0;
    uint64_t drawCalls = 0;
};

FrameFigures timeFrames(render::ClayRenderer& r, const mesh::MeshBuffers& m, const RenderBenchOptions& o,
                        const render::Framebuffer& fb, const render::RenderSettings& look) {
    r.setMesh(m);
    const render::OrbitCamera cam = framed(m, float(o.width) / float(o.height));
    FrameFigures f;
    f.triangles = m.triangleCount();
    frame(r, cam, fb, look);  // warm-up: the first frame compiles llvmpipe's shaders
    std::vector<double> ms;
    for (int i = 0; i < o.frames; ++i) ms.push_back(frame(r, cam, fb, look));
    f.ms = median(ms);
    gRealDrawElements = epoxy_glDrawElements;
    gRealDrawArrays = epoxy_glDrawArrays;
    epoxy_glDrawElements = &countDrawElements;
    epoxy_glDrawArrays = &countDrawArrays;
    gDrawCalls = 0;
    frame(r, cam, fb, look);
    f.drawCalls = gDrawCalls;
    epoxy_glDrawElements = gRealDrawElements;
    epoxy_glDrawArrays = gRealDrawArrays;
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
    const FrameFigures l10 = timeFrames(renderer, mesh::meshAdf(sculpt::startAdf(testPart(10), 0)), o, fb, look);
    out.progress("the level-12 test part");
    const FrameFigures l12 = timeFrames(renderer, mesh::meshAdf(sculpt::startAdf(testPart(12), 0)), o, fb, look);
    out.progress("the level-13 test part (about a million triangles)");
    const FrameFigures l13 = timeFrames(renderer, mesh::meshAdf(sculpt::startAdf(testPart(13), 0)), o, fb, look);

    // Sample to visible: dabs on the level-10 part through the engine, the window's loop here.
    out.progress("sample to visible, level 10");
    engine::EngineSettings es;
    es.start = testPart(10);
    es.correctAfterIdle = std::chrono::milliseconds(0);
    engine::Engine e(es);
    engine::ToolSettings carve;
    carve.tool.radius = 0.02;
    e.setTool(carve).get();
    mesh::MeshMirror mirror;
    render::OrbitCamera cam;
    std::vector<double> visible, toDelta;
    for (int i = 0; i < o.edits + 1; ++i) {
        // Bring the mirror up to date and draw, as an idle window would.
        while (auto d = e.takeMeshDelta()) mirror.apply(std::move(*d));
        const uint64_t before = mirror.generation();
        if (i == 0) {
            const mesh::MeshBuffers m = mirror.flatten();
            renderer.setMesh(m);
            cam = framed(m, float(o.width) / float(o.height));
        }
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
        double deltaMs = -1.0;
        for (;;) {
            if (auto d = e.takeMeshDelta()) {
                if (deltaMs < 0.0) deltaMs = msSince(t0);
                mirror.apply(std::move(*d));
                renderer.setMesh(mirror.flatten());
            }
            frame(renderer, cam, fb, look);
            if (mirror.generation() != before && deltaMs >= 0.0) break;
            if (msSince(t0) > 5000.0) break;  // a lost dab: counted by the missing figure below
        }
        if (i == 0 || deltaMs < 0.0) continue;  // the first dab also warms the engine's caches
        visible.push_back(msSince(t0));
        toDelta.push_back(deltaMs);
        e.sync().get();
    }

    out.section("frames (" + std::to_string(o.width) + "x" + std::to_string(o.height) + ", 4x MSAA, the clay and the floor, glFinish)");
    out.add("render.frame_ms.level10", l10.ms, "ms", std::to_string(l10.triangles) + " triangles");
    out.add("render.frame_ms.1m_triangles", l13.ms, "ms", "the level-13 test part, " + std::to_string(l13.triangles) + " triangles");
    out.add("render.triangles.1m", double(l13.triangles), "triangles");
    out.add("render.frame_ms.level12", l12.ms, "ms", std::to_string(l12.triangles) + " triangles");
    out.add("render.draw_calls.level12", double(l12.drawCalls), "calls", "per frame, counted at the GL dispatch");
    const double frameMs = l10.ms;
    const double vis = visible.empty() ? NAN : median(visible), del = toDelta.empty() ? NAN : median(toDelta);
    out.section("a carve dab on the level-10 part: sample to the first frame that shows it");
    out.add("render.edit_to_visible_ms", vis, "ms", "median of " + std::to_string(visible.size()) + " dabs");
    out.add("render.edit_to_mesh_ms", del, "ms", "the engine's part: sample to mesh delta");
    out.add("render.edit_to_visible_frames", (vis - del) / frameMs, "frames",
            "beyond the engine's latency, in level-10 frame times; target <= 2");
    return visible.size() == std::size_t(o.edits) ? 0 : 1;
}

}  // namespace kizamu::bench
