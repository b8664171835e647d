// SPDX-License-Identifier: Apache-2.0
/// @file mesh_decimate.cpp
/// @brief decimateMesh: meshopt_simplify, then the used vertices compacted with their attributes.
#include "mesh/mesh_decimate.h"

#include "mesh/mesh_untangle.h"

#include <meshoptimizer.h>

#include <algorithm>
#include <array>
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

/// Removes each pair of triangles on the same three vertices facing opposite ways: the zero-volume
/// fold a collapse leaves where two sheets meet. Their six directed edges pair among themselves,
/// so the rest of the surface is closed again where the fold sat. Complexity: O(T log T).
void removeFolds(std::vector<unsigned>& indices) {
    struct Face {
        std::array<unsigned, 3> sorted;
        bool even;  ///< the corners' order is an even permutation of `sorted`
        std::size_t triangle;
    };
    std::vector<Face> faces;
    faces.reserve(indices.size() / 3);
    for (std::size_t t = 0; t + 2 < indices.size(); t += 3) {
        std::array<unsigned, 3> c{indices[t], indices[t + 1], indices[t + 2]};
        const std::size_t low = std::size_t(std::min_element(c.begin(), c.end()) - c.begin());
        std::rotate(c.begin(), c.begin() + std::ptrdiff_t(low), c.end());  // a rotation keeps the orientation
        faces.push_back({{c[0], std::min(c[1], c[2]), std::max(c[1], c[2])}, c[1] < c[2], t / 3});
    }
    std::sort(faces.begin(), faces.end(), [](const Face& a, const Face& b) { return a.sorted < b.sorted || (a.sorted == b.sorted && a.even < b.even); });
    std::vector<uint8_t> drop(indices.size() / 3, 0);
    for (std::size_t i = 0; i < faces.size();) {
        std::size_t j = i, evens = 0;
        for (; j < faces.size() && faces[j].sorted == faces[i].sorted; ++j) evens += faces[j].even ? 1 : 0;
        const std::size_t odds = (j - i) - evens, folds = std::min(evens, odds);
        for (std::size_t k = 0; k < folds; ++k) {  // odd ones sort first
            drop[faces[i + k].triangle] = 1;
            drop[faces[i + odds + k].triangle] = 1;
        }
        i = j;
    }
    std::size_t out = 0;
    for (std::size_t t = 0; t < drop.size(); ++t)
        if (!drop[t])
            for (int k = 0; k < 3; ++k) indices[out++] = indices[3 * t + std::size_t(k)];
    indices.resize(out);
}

}  // namespace

MeshBuffers decimateMesh(const MeshBuffers& mesh, const DecimateSettings& settings, DecimateReport* report) {
    if (!(settings.ratio > 0.0 && settings.ratio <= 1.0)) throw std::invalid_argument("decimate: the ratio must be in (0, 1]");
    if (!mesh.valid()) throw std::invalid_argument("decimate: the mesh is not valid");
    if (mesh.triangleCount() == 0) return mesh;
    const std::size_t targetIndices = 3 * std::size_t(std::llround(double(mesh.triangleCount()) * settings.ratio));
    // The simplifier avoids flips but may fold two sheets onto each other: folds are removed, each
    // pass is checked, and a pass that still adds defects (two faces meeting along an edge they
    // did not share) is retried with half the step, so the copy is as watertight as the source.
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
        removeFolds(next);
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
