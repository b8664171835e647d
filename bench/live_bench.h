// SPDX-License-Identifier: Apache-2.0
/// @file live_bench.h
/// @brief `kizamu bench live`: the live engine's input, the cost of one SampleQueue push with
/// a consumer draining on another thread, and while the ring is full (the pending buffer
/// simplifying); then the engine's latency (live_engine_bench.h).
#pragma once

#include <cstddef>
#include <vector>

namespace kizamu::bench {

struct LiveBenchOptions {
    bool json = false;
    std::size_t pushes = 1'000'000;    ///< timed pushes with a draining consumer
    std::size_t fullPushes = 200'000;  ///< timed pushes into a full ring (nobody drains)
    std::vector<int> levels{10, 12};   ///< the engine's stroke at these levels (none: the queue only)
    bool placement = true;             ///< the haptic-core and supersede comparisons
    int repeats = 3;                   ///< runs of the engine's stroke per configuration (medians)
};

/// Runs the benchmark and prints its figures. Returns a process exit code.
int runLiveBench(const LiveBenchOptions& options);

}  // namespace kizamu::bench
