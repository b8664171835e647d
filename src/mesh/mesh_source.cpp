// SPDX-License-Identifier: Apache-2.0
/// @file mesh_source.cpp
/// @brief MeshSource and domain fitting.
#include "mesh/mesh_source.h"

#include <glm/common.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <tuple>
#include <utility>

namespace kizamu::mesh {

namespace {

class MeshSource final : public adf::DistanceSource {
public:
    explicit MeshSource(const MeshBuffers& mesh) : mBvh(mesh) {}
    double distance(const glm::dvec3& p) const override { return signedDistance(p, TriangleBvh::kNoHint).first; }
    void distances(std::span<const glm::dvec3> p, std::span<double> out) const override {
        // Batches are one cell's points: each answer's triangle seeds the next search.
        uint32_t hint = TriangleBvh::kNoHint;
        for (std::size_t i = 0; i < p.size(); ++i) std::tie(out[i], hint) = signedDistance(p[i], hint);
    }

private:
    std::pair<double, uint32_t> signedDistance(const glm::dvec3& p, uint32_t hint) const {
        const TriangleBvh::Closest c = mBvh.closest(p, hint);
        const double d = std::sqrt(c.distanceSquared);
        return {mBvh.windingNumber(p) > 0.5 ? -d : d, c.triangle};
    }
    TriangleBvh mBvh;
};

}  // namespace

adf::SourcePtr makeMeshSource(const MeshBuffers& mesh) {
    if (mesh.triangleCount() == 0 || !mesh.valid()) throw std::invalid_argument("mesh source needs a valid mesh with triangles");
    return std::make_shared<MeshSource>(mesh);
}

adf::Domain domainAround(const MeshBuffers& mesh, int maxLevel, double marginCells) {
    glm::dvec3 lo(mesh.positions.at(0)), hi(lo);
    for (const glm::vec3& p : mesh.positions) {
        lo = glm::min(lo, glm::dvec3(p));
        hi = glm::max(hi, glm::dvec3(p));
    }
    const double extent = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z, 1e-9});
    // size = extent * 1.04 + 2 * margin * size / 2^L  =>  solve for size.
    const double cells = double(1u << maxLevel);
    const double size = extent * 1.04 / std::max(0.5, 1.0 - 2.0 * marginCells / cells);
    adf::Domain d;
    d.maxLevel = maxLevel;
    d.sizeWorld = size;
    d.originWorld = 0.5 * (lo + hi) - glm::dvec3(0.5 * size);
    return d;
}

}  // namespace kizamu::mesh
