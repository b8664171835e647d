// SPDX-License-Identifier: Apache-2.0
/// @file xr_bench.h
/// @brief `kizamu bench xr`: the headset's frame against an OpenXR runtime (the project's
/// simulated one unless XR_RUNTIME_JSON names another): the time of a stereo frame (both eyes
/// drawn and submitted, the level-10 test part), and, counted in xrWaitFrame cycles, how long a
/// controller's carve sample takes to show in the headset. Needs an X display (the OpenGL
/// binding is GLX; Xvfb will do).
#pragma once

namespace kizamu::app {

struct XrBenchOptions {
    bool json = false;
    int frames = 120;  ///< stereo frames timed (the figure: their median)
    int edits = 12;    ///< carve dabs timed for the latency
};

/// Returns the exit code (non-zero: no display, no runtime, or a dab never showed).
int runXrBench(const XrBenchOptions& options);

}  // namespace kizamu::app
