// SPDX-License-Identifier: Apache-2.0
/// @file mesh_bench.h
/// @brief `kizamu bench mesh`: SurfaceNets of the test part and of real meshes, LOD, points,
/// incremental re-meshing and mesh import, optionally beside OpenVDB's volumeToMesh and
/// meshToLevelSet on the same inputs at the same resolution, in the same process.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace kizamu::bench {

struct MeshBenchOptions {
    bool json = false;
    bool vsOpenVdb = false;
    int level = 10;                       ///< finest level of the test part and the imports
    int repeats = 5;                      ///< timed runs per figure (median reported)
    std::size_t points = 800'000;         ///< point-cloud size
    std::vector<std::string> models{"bunny00.off"};  ///< from the CGAL data archive
    unsigned threads = 0;                 ///< 0: util::allowedCpuCount()
};

/// Runs the benchmark and prints its figures. Returns a process exit code.
int runMeshBench(const MeshBenchOptions& options);

}  // namespace kizamu::bench
