// SPDX-License-Identifier: Apache-2.0
/// @file import_probe.cpp
/// @brief Times one mesh file three ways: our reader (where the format is ours), assimp in this
/// process (the helper's exact reading, import/assimp_read.h), and assimp through the helper
/// process (importWithAssimp: spawn, read, reply, decode). Medians of REPEATS runs after one
/// warm-up, wall-clock and CPU time (this process and its reaped children: on a loaded machine
/// the CPU time is the steadier figure). Not a test: the figures of
/// docs/decisions/0028-assimp-in-a-child-process.md.
///
/// Usage: kizamu_import_probe FILE [REPEATS]   (the helper: $KIZAMU_IMPORT_HELPER, or the one
/// built beside the app)
#include "import/assimp_read.h"
#include "mesh/mesh_import.h"
#include "mesh/mesh_import_assimp.h"
#include "util/atomic_file.h"
#include "util/file_error.h"

#include <sys/resource.h>
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <string>
#include <vector>

using namespace kizamu;

namespace {

struct Timing {
    double wallMs, cpuMs;
};

/// CPU time of this process and of its children that have been waited for, in ms.
double cpuMs() {
    rusage self{}, children{};
    ::getrusage(RUSAGE_SELF, &self);
    ::getrusage(RUSAGE_CHILDREN, &children);
    const auto ms = [](const timeval& t) { return double(t.tv_sec) * 1e3 + double(t.tv_usec) * 1e-3; };
    return ms(self.ru_utime) + ms(self.ru_stime) + ms(children.ru_utime) + ms(children.ru_stime);
}

Timing median(int repeats, const std::function<std::size_t()>& run, std::size_t& triangles) {
    triangles = run();  // warm-up: the file in the page cache, the libraries loaded
    std::vector<double> wall, cpu;
    for (int i = 0; i < repeats; ++i) {
        const double c0 = cpuMs();
        const auto t0 = std::chrono::steady_clock::now();
        triangles = run();
        wall.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
        cpu.push_back(cpuMs() - c0);
    }
    std::sort(wall.begin(), wall.end());
    std::sort(cpu.begin(), cpu.end());
    return {wall[wall.size() / 2], cpu[cpu.size() / 2]};
}

void print(const char* what, Timing t, std::size_t triangles) {
    std::printf("%-34s %8.1f ms wall %8.1f ms CPU  %zu triangles\n", what, t.wallMs, t.cpuMs, triangles);
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: kizamu_import_probe FILE [REPEATS]\n");
        return 2;
    }
    ::setenv("KIZAMU_IMPORT_HELPER", KIZAMU_IMPORT_HELPER_PATH, 0);
    const std::string path = argv[1];
    const int repeats = argc > 2 ? std::max(1, std::atoi(argv[2])) : 7;
    std::size_t tris = 0;
    try {
        const mesh::MeshFormat f = mesh::meshFormatOf(path);
        if (f != mesh::MeshFormat::Glb) {
            const Timing t = median(repeats, [&] {
                return mesh::decodeMesh(util::readWholeFile(path), f, path).triangleCount();
            }, tris);
            print("ours (read + decodeMesh)", t, tris);
        }
    } catch (const FileError&) {
        // not one of our formats
    }
    const Timing inProcess = median(repeats, [&] {
        mesh::MeshBuffers m;
        std::vector<std::string> warnings;
        const std::string problem = import::readWithAssimp(path, "", m, warnings);
        if (!problem.empty()) std::fprintf(stderr, "assimp: %s\n", problem.c_str());
        return m.triangleCount();
    }, tris);
    print("assimp in this process", inProcess, tris);
    const Timing child = median(repeats, [&] { return mesh::importWithAssimp(path).triangleCount(); }, tris);
    print("assimp in the helper process", child, tris);
    return 0;
}
