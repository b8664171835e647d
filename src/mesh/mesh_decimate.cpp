// SPDX-License-Identifier: Apache-2.0
/// @file mesh_decimate.cpp
/// @brief decimateMesh: meshopt_simplify, then the used vertices compacted with their attributes.
#include "mesh/mesh_decimate.h"

#include "mesh/mesh_untangle.h"

#include <meshoptimizer.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <vector>

namespace kizamu::mesh {

namespace {

/// Directed edges used more than once, plus directed edges whose opposite is missing (a border
/// or a pinch): 0 for a closed, consistently oriented manifold. Complexity: O(T log T).
std::size_t edgeDefects(const std::vector<unsigned>& indices) {
    std::vector<uint64_t> edges;
    edges.reserve(indices.size());
    for (std::size_t t = 0; t + 2 < indices.size(); t += 3)
        for (int k = 0; k < 3; ++k) edges.push_back(uint64_t(indices[t + k]) << 32 | indices[t + (k + 1) % 3]);
    std::sort(edges.begin(), edges.end());
    std::size_t defects = 0;
    for (std::size_t i = 0; i < edges.size(); ++i) {
        if (i > 0 && edges[i] == edges[i - 1]) {
            ++defects;
            continue;
        }
        const uint64_t opposite = (edges[i] & 0xffffffffu) << 32 | edges[i] >> 32;
        if (!std::binary_search(edges.begin(), edges.end(), opposite)) ++defects;
    }
    return defects;
}

}  // namespace

MeshBuffers decimateMesh(const MeshBuffers& mesh, const DecimateSettings& settings, DecimateReport* report) {
    if (!(settings.ratio > 0.0 && settings.ratio <= 1.0)) throw std::invalid_argument("decimate: the ratio must be in (0, 1]");
    if (!mesh.valid()) throw std::invalid_argument("decimate: the mesh is not valid");
    if (mesh.triangleCount() == 0) return mesh;
    const std::size_t targetIndices = 3 * std::size_t(std::llround(double(mesh.triangleCount()) * settings.ratio));
    // The simplifier avoids flips but not every collapse that pinches the surface (two faces
    // meeting along an edge they did not share): each pass is checked, and a pass that adds
    // defects is retried with half the step, so the copy is as watertight as the source.
    // The simplifier takes vertices at one position for one vertex, which pinches the mesher's
    // surface where two sheets touch: they are separated first (by the least that tells them apart).
    MeshBuffers separated;
    separated.positions = mesh.positions;
    separated.indices = mesh.indices;
    untangle(separated);
    const glm::vec3* positions = separated.positions.data();
    std::vector<unsigned> kept(mesh.indices.begin(), mesh.indices.end()), next;
    const std::size_t defects = edgeDefects(kept);
    std::size_t goal = targetIndices;
    double errorRelative = 0.0;
    while (kept.size() > targetIndices) {
        next.resize(kept.size());
        float passError = 0.0f;
        next.resize(meshopt_simplify(next.data(), kept.data(), kept.size(), &positions[0].x, mesh.vertexCount(), sizeof(glm::vec3), goal,
                                     float(settings.maxErrorRelative), meshopt_SimplifyLockBorder, &passError));
        if (next.size() < kept.size() && edgeDefects(next) <= defects) {
            kept.swap(next);
            errorRelative += passError;  // each pass's error is relative to its own input: their sum bounds the whole
            goal = targetIndices;
            continue;
        }
        const std::size_t smaller = kept.size() - (kept.size() - goal) / 6 * 3;  // half the step, whole triangles
        if (smaller >= kept.size() || next.size() >= kept.size()) break;  // nothing more to collapse
        goal = smaller;
    }
    // The used vertices, in their source order: remap[v] is v's index in the result, or ~0u.
    std::vector<unsigned> remap(mesh.vertexCount());
    const std::size_t vertexCount = meshopt_optimizeVertexFetchRemap(remap.data(), kept.data(), kept.size(), mesh.vertexCount());
    MeshBuffers out;
    out.positions.resize(vertexCount);
    if (!mesh.normals.empty()) out.normals.resize(vertexCount);
    if (!mesh.colours.empty()) out.colours.resize(vertexCount);
    for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
        const unsigned to = remap[v];
        if (to == ~0u) continue;
        out.positions[to] = positions[v];
        if (!mesh.normals.empty()) out.normals[to] = mesh.normals[v];
        if (!mesh.colours.empty()) out.colours[to] = mesh.colours[v];
    }
    out.indices.resize(kept.size());
    for (std::size_t i = 0; i < kept.size(); ++i) out.indices[i] = remap[kept[i]];
    if (report) {
        report->trianglesBefore = mesh.triangleCount();
        report->trianglesAfter = out.triangleCount();
        report->errorWorld = errorRelative * double(meshopt_simplifyScale(&positions[0].x, mesh.vertexCount(), sizeof(glm::vec3)));
    }
    return out;
}

std::string decimatedPath(const std::string& path) {
    const std::filesystem::path p(path);
    return (p.parent_path() / (p.stem().string() + ".decimated" + p.extension().string())).string();
}

}  // namespace kizamu::mesh
