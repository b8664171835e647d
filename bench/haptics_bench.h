// SPDX-License-Identifier: Apache-2.0
/// @file haptics_bench.h
/// @brief `kizamu bench haptics`: the real-time servo thread (haptics/servo_loop.h) with nothing
/// else running (the machine's timer floor) and while the live engine carves and re-meshes a
/// level-12 test part, interleaved, at 1 kHz and 4 kHz.
#pragma once

namespace kizamu::bench {

struct HapticsBenchOptions {
    bool json = false;
    double seconds = 20.0;       ///< length of each run (s)
    double rateHz = 1000.0;      ///< the servo rate of the main figures
    double highRateHz = 4000.0;  ///< the rate of the `.4k` figures; 0 skips them
    int level = 12;              ///< finest level of the engine's test part
    int repeats = 3;             ///< bare and loaded runs, interleaved, per rate (figures: medians)
    int spinUs = 50;             ///< ServoSettings::spinUs
    int servoCpu = -1;           ///< ServoSettings::cpu (-1: not pinned, shares the CPUs)
    int priority = 80;           ///< SCHED_FIFO priority asked for (0: none)
};

/// Runs the benchmark and prints its figures (haptics.*). Returns a process exit code.
int runHapticsBench(const HapticsBenchOptions& options);

}  // namespace kizamu::bench
