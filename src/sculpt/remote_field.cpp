// SPDX-License-Identifier: Apache-2.0
/// @file remote_field.cpp
/// @brief Remote-field correction: surface samples, a k-d tree, a regenerated zone.
#include "sculpt/remote_field.h"

#include "adf/adf_source.h"
#include "adf/generate.h"
#include "adf/boundary_cells.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vector_relational.hpp>
#include <nanoflann.hpp>

#include <algorithm>
#include <cmath>
#include <unordered_set>

namespace kizamu::sculpt {

namespace {

/// The samples as nanoflann's dataset.
struct Cloud {
    const std::vector<glm::dvec3>* points;
    std::size_t kdtree_get_point_count() const { return points->size(); }
    double kdtree_get_pt(std::size_t i, std::size_t dim) const { return (*points)[i][int(dim)]; }
    template <class Box>
    bool kdtree_get_bbox(Box&) const { return false; }
};
using KdTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, Cloud>, Cloud, 3, uint32_t>;

/// nanoflann result set: the nearest sample within a radius (squared distances). The search
/// prunes every branch farther than the best so far, which starts at the radius.
struct NearestWithin {
    double best2;
    bool found = false;
    bool full() const { return found; }
    double worstDist() const { return best2; }
    bool addPoint(double d2, uint32_t) {
        if (d2 < best2) best2 = d2, found = true;
        return true;
    }
};

/// The corrected field of the zone: old near the surface, distance to the samples beyond.
class CorrectedField final : public adf::DistanceSource {
public:
    CorrectedField(adf::SourcePtr old, std::vector<glm::dvec3> samples, double keep, double radius)
        : mOld(std::move(old)), mSamples(std::move(samples)), mCloud{&mSamples},
          mTree(3, mCloud, nanoflann::KDTreeSingleIndexAdaptorParams(16)), mKeep(keep), mRadius(radius) {
        mSmallestFeature = mOld->smallestFeature();
    }
    double distance(const glm::dvec3& p) const override { return correct(p, mOld->distance(p)); }
    void distances(std::span<const glm::dvec3> p, std::span<double> out) const override {
        mOld->distances(p, out);
        for (std::size_t i = 0; i < p.size(); ++i) out[i] = correct(p[i], out[i]);
    }

private:
    double correct(const glm::dvec3& p, double old) const {
        const double a = std::abs(old);
        if (!(a > mKeep)) return old;  // the surface's own band (and NaN) stay as they are
        double d = std::max(mRadius, a);  // no surface within the radius: at least the radius
        NearestWithin nearest{mRadius * mRadius};
        if (!mSamples.empty()) mTree.findNeighbors(nearest, &p.x, nanoflann::SearchParams());
        if (nearest.found) d = std::sqrt(nearest.best2);
        // Blend over [keep, 2 keep] so the field stays continuous where correction starts.
        const double t = std::min(1.0, (a - mKeep) / mKeep), w = t * t * (3.0 - 2.0 * t);
        return std::copysign((1.0 - w) * a + w * d, old);
    }
    adf::SourcePtr mOld;
    std::vector<glm::dvec3> mSamples;
    Cloud mCloud;
    KdTree mTree;
    double mKeep, mRadius;
};

}  // namespace

std::vector<glm::dvec3> surfaceSamples(const adf::Adf& adf, const adf::BoxWorld& box) {
    const adf::Domain& d = adf.domain();
    const double h = d.finestCellSize();
    std::unordered_set<const adf::Tile*> seen;
    std::vector<adf::BoundaryCell> cells;
    adf::forEachSlotIn(d, box, [&](glm::uvec3 slot) {
        const adf::Tile* t = adf.tileAtSlot(slot);
        if (t && seen.insert(t).second) adf::appendBoundaryCells(*t, d.maxLevel, cells);
    });
    std::vector<glm::dvec3> out;
    for (const adf::BoundaryCell& c : cells) {
        const glm::dvec3 origin = d.originWorld + glm::dvec3(c.origin) * h;
        const double size = double(c.size) * h;
        if (glm::any(glm::greaterThan(origin, box.max)) || glm::any(glm::lessThan(origin + size, box.min))) continue;
        // A k x k grid across the two axes where the gradient is smallest, starting half-way
        // along the third, each point moved onto the leaf's trilinear zero set by Newton steps:
        // about k^2 points on the surface, half a finest cell apart in finest leaves and one
        // apart in larger ones (flat there: the distance to a plane sampled that finely is off
        // by spacing^2 / (8 d), under a tenth of a cell beyond the kept band).
        const glm::vec3 absGradient = glm::abs(adf::trilinear(c.corners, glm::vec3(0.5f)).gradient);
        const int axis = absGradient.x >= absGradient.y && absGradient.x >= absGradient.z
                             ? 0
                             : (absGradient.y >= absGradient.z ? 1 : 2);
        const int k = c.size == 1 ? 2 : int(std::min<uint32_t>(c.size, 64));  // grid points per side
        for (int i = 0; i < k; ++i)
            for (int j = 0; j < k; ++j) {
                glm::vec3 u;
                u[axis] = 0.5f;
                u[(axis + 1) % 3] = (float(i) + 0.5f) / float(k);
                u[(axis + 2) % 3] = (float(j) + 0.5f) / float(k);
                adf::Sample f = adf::trilinear(c.corners, u);  // gradient per unit of cell coordinate
                for (int step = 0; step < 4; ++step) {
                    const float g2 = glm::dot(f.gradient, f.gradient);
                    if (!(g2 > 0.0f)) break;
                    u -= f.distance * f.gradient / g2;
                    f = adf::trilinear(c.corners, u);
                }
                const bool inside = glm::all(glm::greaterThanEqual(u, glm::vec3(-1e-5f))) &&
                                    glm::all(glm::lessThanEqual(u, glm::vec3(1.0f + 1e-5f)));
                if (inside && std::abs(double(f.distance)) <= 1e-3 * h) out.push_back(origin + glm::dvec3(u) * size);
            }
    }
    return out;
}

adf::BoxWorld correctionZone(const adf::Adf& adf, const adf::BoxWorld& region, const CorrectionSettings& settings) {
    return adf::grownWithin(adf.domain(), region, settings.radiusCells * adf.domain().finestCellSize());
}

adf::AdfPtr correctRemoteField(const adf::AdfPtr& adf, const adf::BoxWorld& zone, util::ThreadPool* pool,
                               const CorrectionSettings& settings) {
    const double h = adf->domain().finestCellSize();
    const double radius = settings.radiusCells * h;
    // Surface within the radius of any point of the zone.
    const adf::BoxWorld searched{zone.min - radius, zone.max + radius};
    const adf::SourcePtr old = adf::makeAdfSource(adf);
    const auto corrected = std::make_shared<CorrectedField>(old, surfaceSamples(*adf, searched), settings.keepCells * h, radius);
    return adf::regenerate(*adf, *adf::makeRegionLimited(old, corrected, zone), zone, pool);
}

adf::AdfPtr correctZones(adf::AdfPtr adf, std::vector<adf::BoxWorld> zones, util::ThreadPool* pool,
                         const CorrectionSettings& settings) {
    // Merged boxes stay within four tiles: one pass over a huge box would sample its whole
    // surface at once.
    const adf::Domain& d = adf->domain();
    for (const adf::BoxWorld& z : mergeZones(std::move(zones), 4.0 * d.finestCellSize() * double(1u << d.tileSpan())))
        adf = correctRemoteField(adf, z, pool, settings);
    return adf;
}

std::vector<adf::BoxWorld> mergeZones(std::vector<adf::BoxWorld> zones, double maxExtent) {
    auto volume = [](const adf::BoxWorld& b) {
        const glm::dvec3 e = glm::max(b.max - b.min, glm::dvec3(0.0));
        return e.x * e.y * e.z;
    };
    // Greedy passes until one merges nothing; a merged box is tried against the rest again.
    for (bool merged = true; merged;) {
        merged = false;
        for (std::size_t i = 0; i < zones.size(); ++i)
            for (std::size_t j = i + 1; j < zones.size();) {
                const adf::BoxWorld joined{glm::min(zones[i].min, zones[j].min), glm::max(zones[i].max, zones[j].max)};
                const glm::dvec3 extent = joined.max - joined.min;
                if (std::max(extent.x, std::max(extent.y, extent.z)) <= maxExtent &&
                    volume(joined) <= volume(zones[i]) + volume(zones[j])) {
                    zones[i] = joined;
                    zones.erase(zones.begin() + std::ptrdiff_t(j));
                    merged = true;
                } else {
                    ++j;
                }
            }
    }
    return zones;
}

}  // namespace kizamu::sculpt
