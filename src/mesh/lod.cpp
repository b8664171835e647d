// SPDX-License-Identifier: Apache-2.0
/// @file lod.cpp
/// @brief coarsenAdf, meshLod, lodErrorForTriangles.
#include "mesh/lod.h"

#include "adf/generate.h"
#include "mesh/mesh_colours.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace kizamu::mesh {

namespace {

/// The fine field as a source: plain trilinear reconstruction (the coarse ADF is a new, full
/// generation: a lattice point has one value however often it is asked for, so signs agree
/// between its cells).
/// The coarse lattice is a sub-lattice of the fine one, so every point the generator asks for
/// is a fine lattice point, nearly always a stored corner, read without gradient (a
/// world-space sample would add a conversion and a gradient per point, and its float
/// coordinates can land a rounding error off the corner).
class AdfSampler final : public adf::DistanceSource {
public:
    explicit AdfSampler(adf::AdfPtr adf) : mAdf(std::move(adf)), mRounding(mAdf->domain()) {}
    double distance(const glm::dvec3& p) const override {
        glm::uvec3 lattice;
        return mRounding.nearest(p, 1e-6, lattice) ? mAdf->latticeDistance(lattice) : mAdf->sample(glm::vec3(p)).distance;
    }
    /// The lattice points of a batch together (Adf::latticeDistances overlaps their descents).
    void distances(std::span<const glm::dvec3> p, std::span<double> out) const override {
        constexpr std::size_t kBatch = 64;
        glm::uvec3 lattice[kBatch];
        uint32_t at[kBatch];
        float values[kBatch];
        for (std::size_t first = 0; first < p.size(); first += kBatch) {
            const std::size_t n = std::min(kBatch, p.size() - first);
            std::size_t m = 0;
            for (std::size_t i = first; i < first + n; ++i) {
                if (mRounding.nearest(p[i], 1e-6, lattice[m])) at[m++] = uint32_t(i);
                else out[i] = mAdf->sample(glm::vec3(p[i])).distance;
            }
            mAdf->latticeDistances({lattice, m}, {values, m});
            for (std::size_t k = 0; k < m; ++k) out[at[k]] = values[k];
        }
    }

    /// A coarse domain's lattice (the fine one's, fewer levels) is the fine lattice's every
    /// 2^k-th point: no world coordinates, no rounding.
    bool answersLattice(const adf::Domain& d) const override {
        const adf::Domain& fine = mAdf->domain();
        return d.originWorld == fine.originWorld && d.sizeWorld == fine.sizeWorld && d.maxLevel <= fine.maxLevel;
    }
    /// Such a point read as the fine lattice point it is; any other domain's through world space.
    void latticeDistances(const adf::Domain& d, std::span<const glm::uvec3> lattice,
                          std::span<double> out) const override {
        if (!answersLattice(d)) {
            DistanceSource::latticeDistances(d, lattice, out);
            return;
        }
        const adf::Domain& fine = mAdf->domain();
        const auto shift = uint32_t(fine.maxLevel - d.maxLevel);
        constexpr std::size_t kBatch = 64;
        glm::uvec3 at[kBatch];
        float values[kBatch];
        for (std::size_t first = 0; first < lattice.size(); first += kBatch) {
            const std::size_t n = std::min(kBatch, lattice.size() - first);
            for (std::size_t i = 0; i < n; ++i) at[i] = lattice[first + i] << shift;
            mAdf->latticeDistances({at, n}, {values, n});
            for (std::size_t i = 0; i < n; ++i) out[first + i] = values[i];
        }
    }

private:
    adf::AdfPtr mAdf;
    adf::LatticeRounding mRounding;
};

}  // namespace

adf::SourcePtr makeFineFieldSource(adf::AdfPtr fine) {
    if (!fine) throw std::invalid_argument("LOD needs a snapshot");
    return std::make_shared<AdfSampler>(std::move(fine));
}

adf::AdfPtr coarsenAdf(const adf::AdfPtr& fine, double errorWorld, util::ThreadPool* pool) {
    if (!fine) throw std::invalid_argument("LOD needs a snapshot");
    if (!(errorWorld > 0.0) || !std::isfinite(errorWorld)) throw std::invalid_argument("LOD error must be positive");
    // The coarse lattice stops where a finest cell is between once and twice the error: finer
    // cells could not be told apart from their parent within the bound, and a small lattice
    // keeps the fixed costs (tile table, tiles) in proportion to the output.
    adf::Domain d = fine->domain();
    while (d.maxLevel > 1 && d.finestCellSize() <= errorWorld) --d.maxLevel;  // finest cell in (E, 2E]
    // As few tiles as 2^3: a small generation runs its tiles at once (adf/generate.cpp), so a
    // few large tiles still generate in parallel, and the mesher's fixed cost per tile, which
    // more tiles would multiply, stays small next to the coarse output.
    d.tileSpanLevels = std::clamp(d.maxLevel - 1, 1, d.tileSpanLevels);
    adf::GenerationSettings s = fine->settings();
    s.epsilonCells = errorWorld / d.finestCellSize();
    s.bandCells = 0.0;  // surface only: a mesh needs nothing else
    return adf::generate(*makeFineFieldSource(fine), d, s, pool);
}

MeshBuffers meshLod(const adf::AdfPtr& fine, double errorWorld, util::ThreadPool* pool, SurfaceNetsStats* stats) {
    MeshBuffers m = meshAdf(coarsenAdf(fine, errorWorld, pool), pool, stats);
    // The coarse ADF carries no paint: the colours come from the fine snapshot's layer.
    if (fine->colours()) colourPoints(*fine->colours(), m.positions, m.colours, pool);
    return m;
}

double lodErrorForTriangles(const adf::AdfPtr& fine, std::size_t triangles, util::ThreadPool* pool) {
    if (!fine) throw std::invalid_argument("LOD needs a snapshot");
    // More error, fewer triangles: bisect log(error) between a finest cell and the domain.
    double lo = std::log(fine->domain().finestCellSize() * 0.25), hi = std::log(fine->domain().sizeWorld * 0.25);
    double best = std::exp(hi), bestMiss = std::numeric_limits<double>::infinity();
    for (int i = 0; i < 24; ++i) {
        const double mid = 0.5 * (lo + hi);
        const std::size_t n = meshLod(fine, std::exp(mid), pool).triangleCount();
        const double miss = std::abs(double(n) - double(triangles));
        if (miss < bestMiss) {
            bestMiss = miss;
            best = std::exp(mid);
        }
        if (miss < 0.15 * double(triangles)) break;
        if (n > triangles) lo = mid;
        else hi = mid;
    }
    return best;
}

}  // namespace kizamu::mesh
