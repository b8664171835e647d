// SPDX-License-Identifier: Apache-2.0
/// @file mesh_source.cpp
/// @brief MeshSource and domain fitting.
#include "mesh/mesh_source.h"

#include "mesh/mesh_orientation.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cstdint>
#include <vector>
#include <cmath>
#include <stdexcept>
#include <utility>

namespace kizamu::mesh {

namespace {

class MeshSource final : public adf::DistanceSource {
public:
    /// `closed`: every part of `mesh` is closed and consistently oriented.
    MeshSource(const MeshBuffers& mesh, bool closed) : mBvh(mesh), mClosed(closed) {}
    double distance(const glm::dvec3& p) const override {
        const TriangleBvh::Closest c = mBvh.closest(p, TriangleBvh::kNoHint);
        const double d = std::sqrt(c.distanceSquared);
        return inside(p) ? -d : d;
    }
    void distances(std::span<const glm::dvec3> p, std::span<double> out) const override {
        // Batches are one cell's points: each answer's triangle seeds the next search.
        uint32_t hint = TriangleBvh::kNoHint;
        for (std::size_t i = 0; i < p.size(); ++i) {
            const TriangleBvh::Closest c = mBvh.closest(p[i], hint);
            hint = c.triangle;
            out[i] = std::sqrt(c.distanceSquared);
        }
        // Signs: by a signed neighbour when no surface can lie between (closed meshes only).
        for (std::size_t i = 0; i < p.size(); ++i) {
            int sign = 0;
            if (mClosed)
                for (std::size_t j = 0; j < i && sign == 0; ++j) {
                    const double gap = glm::distance(p[i], p[j]);
                    if (out[i] + std::abs(out[j]) > gap * (1.0 + 1e-9) + kSlack) sign = out[j] < 0.0 ? -1 : 1;
                }
            if (sign == 0) sign = inside(p[i]) ? -1 : 1;
            out[i] *= sign;
        }
    }
private:
    bool inside(const glm::dvec3& p) const { return mBvh.windingNumber(p) > 0.5; }
    TriangleBvh mBvh;
    bool mClosed;
    static constexpr double kSlack = 1e-12;  ///< m: rounding of distances and gaps
};

}  // namespace

adf::SourcePtr makeMeshSource(const MeshBuffers& mesh, std::vector<std::string>* warnings) {
    if (mesh.triangleCount() == 0 || !mesh.valid()) throw std::invalid_argument("mesh source needs a valid mesh with triangles");
    MeshBuffers oriented;  // what the BVH reads
    oriented.positions = mesh.positions;
    oriented.indices = mesh.indices;
    const OrientationReport report = orientClosedComponents(oriented);
    if (warnings && report.flipped > 0) warnings->push_back(describeOrientation(report));
    return std::make_shared<MeshSource>(oriented, report.allClosed());
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
