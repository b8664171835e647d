// SPDX-License-Identifier: Apache-2.0
/// @file live_engine_bench.h
/// @brief `kizamu bench live`, the engine half: a 2-second carving stroke at 1 kHz through the
/// live Engine over the test part, with the servo thread querying the clay alongside.
#pragma once

#include "bench/figures.h"

#include <vector>

namespace kizamu::bench {

struct LiveEngineBenchOptions {
    std::vector<int> levels{10, 12};
    bool placement = true;  ///< also the haptic-core and supersede comparisons at the first level
    int repeats = 3;        ///< runs per configuration; each figure is the median over them
};

/// Runs the stroke at each level and adds the live.* latency figures to `out`.
void liveEngineFigures(FigureSink& out, const LiveEngineBenchOptions& options);

}  // namespace kizamu::bench
