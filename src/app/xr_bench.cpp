// SPDX-License-Identifier: Apache-2.0
/// @file xr_bench.cpp
/// @brief runXrBench: the sculpting window's headset frame (sculpt_app.cpp) on this thread: the
/// mesh deltas applied and uploaded, both eyes drawn, the frame submitted. A dab is the sample
/// the app pushes in the frame it reads the controller; its latency is the number of frames
/// begun (xrWaitFrame returns) from that one to the first whose submitted eyes show its delta.
#include "app/xr_bench.h"

#include "adf/snapshot_store.h"
#include "app/headset_mode.h"
#include "bench/figures.h"
#include "bench/timing.h"
#include "engine/engine.h"
#include "mesh/mesh_delta.h"
#include "render/clay_renderer.h"
#include "render/shader_program.h"
#include "sculpt/script_start.h"
#include "ui/glfw_window.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace kizamu::app {

namespace {

using Clock = std::chrono::steady_clock;

/// The loop's mesh side, as the window's: the engine's deltas onto the GPU tile by tile.
void takeDeltas(engine::Engine& e, render::ClayRenderer& renderer) {
    while (auto d = e.takeMeshDelta())
        if (!renderer.applyDelta(std::move(*d), {})) e.requestFullMesh();
}

}  // namespace

int runXrBench(const XrBenchOptions& o) {
    if (!std::getenv("DISPLAY")) {
        std::fprintf(stderr, "kizamu bench xr: needs an X display (OpenXR's OpenGL binding is GLX); run it under xvfb-run\n");
        return 1;
    }
#ifdef KIZAMU_XRSIM_MANIFEST
    setenv("XR_RUNTIME_JSON", KIZAMU_XRSIM_MANIFEST, 0);  // the simulated runtime unless told otherwise
#endif
    bench::FigureSink out(o.json);
    ui::WindowSettings ws;
    ws.visible = false;
    ws.samples = 0;
    ui::GlfwWindow window(ws);
    const render::ShaderLibrary shaders;
    render::ClayRenderer renderer(shaders);
    render::RenderSettings look;

    engine::EngineSettings es;
    es.start.domain.maxLevel = 10;
    es.start.start.kind = sculpt::Shape::Kind::TestPart;
    es.correctAfterIdle = std::chrono::milliseconds(0);
    engine::Engine e(es);
    engine::ToolSettings carve;
    carve.tool.radius = 0.02;
    e.setTool(carve).get();
    adf::Domain domain;
    {
        adf::SnapshotStore::Reader reader(e.snapshots());
        domain = reader.acquire().adf().domain();
    }
    HeadsetModeOptions ho;
    ho.clayCentre = domain.originWorld + glm::dvec3(0.5 * domain.sizeWorld);
    ho.domainSize = domain.sizeWorld;
    HeadsetMode headset(ho);
    if (!o.json) std::printf("kizamu bench xr: %s; the level-10 test part\n", headset.describe().c_str());
    for (int i = 0; i < 200 && !headset.running(); ++i) headset.alive();
    if (!headset.running()) {
        std::fprintf(stderr, "kizamu bench xr: the runtime never made the session ready\n");
        return 1;
    }
    e.sync().get();
    takeDeltas(e, renderer);

    auto frame = [&] {
        headset.alive();
        headset.beginFrame();
        const auto t0 = Clock::now();
        takeDeltas(e, renderer);
        headset.drawEyes(renderer, look, nullptr);
        headset.beginPanel();
        headset.endPanel();
        headset.endFrame();
        return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    };

    out.progress("stereo frames");
    std::vector<double> ms;
    for (int i = 0; i < o.frames; ++i) ms.push_back(frame());

    out.progress("carve dabs");
    std::vector<double> frames;
    for (int i = 0; i < o.edits + 1; ++i) {
        e.sync().get();
        takeDeltas(e, renderer);
        const uint64_t before = renderer.tiledMesh().generation();
        // The frame that reads the controller pushes its sample (SculptApp::sculptInHeadset).
        headset.alive();
        headset.beginFrame();
        engine::ToolSample s;
        s.timeNs = std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now().time_since_epoch()).count();
        s.posWorld = glm::dvec3(0.3 + 0.02 * i, 0.5, 0.62);  // along the part's top, a fresh spot each time
        s.buttons = engine::kButtonPrimary;
        e.samples(0).push(s);
        s.buttons = 0;
        s.timeNs += 1000;
        e.samples(0).push(s);
        e.samples(0).flush();
        takeDeltas(e, renderer);
        headset.drawEyes(renderer, look, nullptr);
        headset.beginPanel();
        headset.endPanel();
        headset.endFrame();
        int waited = 0;
        const auto t0 = Clock::now();
        bool shown = renderer.tiledMesh().generation() != before;
        while (!shown && Clock::now() - t0 < std::chrono::seconds(5)) {
            frame();
            ++waited;
            shown = renderer.tiledMesh().generation() != before;
        }
        if (!shown) continue;
        if (i > 0) frames.push_back(double(waited));  // the first dab also warms the engine's caches
    }

    out.section("the headset's stereo frame: both eyes drawn and submitted (the level-10 test part)");
    out.add("xr.frame_ms", bench::median(ms), "ms", "median of " + std::to_string(ms.size()) + " frames, per eye pair");
    out.section("a carve dab from the controller: frames until the headset shows it");
    out.add("xr.edit_to_visible_frames", frames.empty() ? NAN : bench::median(frames), "frames",
            "median of " + std::to_string(frames.size()) + " dabs; xrWaitFrame cycles after the sample's own");
    return frames.size() == std::size_t(o.edits) ? 0 : 1;
}

}  // namespace kizamu::app
