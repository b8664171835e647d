// SPDX-License-Identifier: Apache-2.0
/// @file edit_bench.h
/// @brief `kizamu bench edit`: carve dabs (edit, and edit + re-mesh) at levels 10 and 12, a
/// 500-sample stroke, the 2000-stroke chisel slab, undo and redo.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace kizamu::bench {

struct EditBenchOptions {
    bool json = false;
    bool vsOpenVdb = false;            ///< also the same dabs in an OpenVDB level set
    std::vector<int> levels{10, 12};  ///< dab levels
    int dabs = 21;                    ///< dabs per level (median, p99)
    int slabLevel = 12;
    std::size_t slabStrokes = 2000;   ///< strokes of examples/slab2000.jsonl to replay (0: skip)
    std::string slabScript = "examples/slab2000.jsonl";
    unsigned threads = 0;
};

int runEditBench(const EditBenchOptions& options);

}  // namespace kizamu::bench
