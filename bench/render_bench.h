// SPDX-License-Identifier: Apache-2.0
/// @file render_bench.h
/// @brief `kizamu bench render`: the renderer's frame time on the level-10 test part and on a
/// sculpt of about a million triangles (the level-13 part), its draw calls per frame at level 12, and the latency
/// from a tool sample to the first frame that shows its edit. Off screen (EGL), so software
/// renderer figures (Mesa's llvmpipe here) are relative only.
#pragma once

namespace kizamu::bench {

struct RenderBenchOptions {
    bool json = false;
    int width = 1280, height = 720;
    int frames = 30;  ///< frames timed per mesh (figures: medians)
    int edits = 20;   ///< dabs timed for the sample-to-visible latency
};

/// Runs the benchmark and prints its figures (render.*). Returns a process exit code.
int runRenderBench(const RenderBenchOptions& options);

}  // namespace kizamu::bench
