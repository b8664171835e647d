// SPDX-License-Identifier: Apache-2.0
/// @file adf_bench.h
/// @brief `kizamu bench adf`: generation, memory, query latency and accuracy of the test part,
/// optionally side by side with an OpenVDB level set of the same part in the same process.
#pragma once

#include <cstddef>
#include <vector>

namespace kizamu::bench {

struct AdfBenchOptions {
    bool json = false;                ///< JSON lines instead of a table
    bool vsOpenVdb = false;           ///< also build and query the OpenVDB peer
    std::vector<int> levels{8, 10, 12};
    std::size_t queries = 1'000'000;  ///< random points and walk steps per level
    std::size_t errorPoints = 200'000;  ///< band points for the accuracy figure
    int repeats = 3;                  ///< generation runs per level (median reported)
    int queryPasses = 5;              ///< timed passes over the query points (medians reported)
    unsigned threads = 0;             ///< 0: util::allowedCpuCount()
    int tileSpan = 0;                 ///< 0: the default tile span
};

/// Runs the benchmark and prints its figures. Returns a process exit code.
int runAdfBench(const AdfBenchOptions& options);

}  // namespace kizamu::bench
