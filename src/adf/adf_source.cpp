// SPDX-License-Identifier: Apache-2.0
/// @file adf_source.cpp
/// @brief AdfSource and RegionLimited.
#include "adf/adf_source.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vector_relational.hpp>

#include <algorithm>

#include <stdexcept>
#include <utility>

namespace kizamu::adf {

namespace {

/// The field of a snapshot. At a lattice point that is a corner of some leaf it answers that
/// corner's stored value rather than whichever leaf the half-open lookup lands in: a larger
/// neighbour's interpolation there can differ, even in sign, and a regenerated tile must agree
/// with the untouched tiles around it on every corner they share (the mesher relies on it).
class AdfSource final : public DistanceSource {
public:
    explicit AdfSource(AdfPtr adf)
        : mAdf(std::move(adf)), mOrigin(mAdf->domain().originWorld),
          mInvCell(1.0 / mAdf->domain().finestCellSize()), mTop(mAdf->domain().latticeSize()) {}
    double distance(const glm::dvec3& p) const override {
        double corner;
        if (cornerValue(p, corner)) return corner;
        return mAdf->sample(glm::vec3(p)).distance;
    }
    void distances(std::span<const glm::dvec3> p, std::span<double> out) const override {
        AdfAccessor acc(*mAdf);  // batches are coherent (one cell's points): cache the leaf
        for (std::size_t i = 0; i < p.size(); ++i) {
            double corner;
            out[i] = cornerValue(p[i], corner) ? corner : acc.sample(glm::vec3(p[i])).distance;
        }
    }

private:
    /// Stored value at `p` if it is a lattice point and a corner of one of the (up to 8) leaves
    /// around it; the first in octant order wins (their values differ only by quantisation).
    /// Only octants across faces of the first leaf that `p` lies on can hold such a corner.
    bool cornerValue(const glm::dvec3& p, double& value) const {
        const glm::dvec3 u = (p - mOrigin) * mInvCell;
        const glm::dvec3 r = glm::round(u);
        if (!(glm::all(glm::lessThan(glm::abs(u - r), glm::dvec3(1e-4)))) || glm::any(glm::lessThan(r, glm::dvec3(0.0))) ||
            glm::any(glm::greaterThan(r, glm::dvec3(mTop))))
            return false;
        const glm::uvec3 pt(r);
        auto cornerOf = [&](const LeafRef& leaf) {
            const glm::uvec3 rel = pt - leaf.latticeOrigin;
            int c = 0;
            for (int k = 0; k < 3; ++k) {
                if (rel[k] == leaf.latticeSize) c |= 1 << k;
                else if (rel[k] != 0) return -1;
            }
            return c;
        };
        // Octant 0 (the unit cube above p), when inside the domain.
        uint32_t onFace = 7;  // axes where p lies on the first leaf's lower face
        if (pt.x < mTop && pt.y < mTop && pt.z < mTop) {
            const LeafRef first = mAdf->findLeaf(pt);
            const int c = cornerOf(first);
            if (c >= 0) {
                value = first.corners[c];
                return true;
            }
            onFace = 0;
            for (int k = 0; k < 3; ++k)
                if (pt[k] == first.latticeOrigin[k]) onFace |= 1u << k;
        }
        for (uint32_t o = 1; o < 8; ++o) {
            if ((o & onFace) != o) continue;  // that cube lies in the first leaf too
            const glm::uvec3 off(o & 1, (o >> 1) & 1, o >> 2);
            if (glm::any(glm::lessThan(pt, off))) continue;
            const glm::uvec3 cube = pt - off;
            if (cube.x >= mTop || cube.y >= mTop || cube.z >= mTop) continue;
            const LeafRef leaf = mAdf->findLeaf(cube);
            const int c = cornerOf(leaf);
            if (c >= 0) {
                value = leaf.corners[c];
                return true;
            }
        }
        return false;
    }

    AdfPtr mAdf;
    glm::dvec3 mOrigin;
    double mInvCell;
    uint32_t mTop;
};

class RegionLimited final : public DistanceSource {
public:
    RegionLimited(SourcePtr outside, SourcePtr inside, const BoxWorld& region)
        : mOutside(std::move(outside)), mInside(std::move(inside)), mRegion(region) {
        mSmallestFeature = std::min(mOutside->smallestFeature(), mInside->smallestFeature());
    }
    double distance(const glm::dvec3& p) const override {
        return mRegion.contains(p) ? mInside->distance(p) : mOutside->distance(p);
    }
    /// A cell touching the region takes the new field's features only. Asking both sides would
    /// make a chain of edits (each `inside` built on the previous source) exponential, and the
    /// old field's features are already resolved in the snapshot being edited.
    double featureSize(const glm::dvec3& c, double radius) const override {
        const glm::dvec3 nearest = glm::clamp(c, mRegion.min, mRegion.max);
        return glm::distance(nearest, c) > radius ? mOutside->featureSize(c, radius)
                                                  : mInside->featureSize(c, radius);
    }

private:
    SourcePtr mOutside, mInside;
    BoxWorld mRegion;
};

}  // namespace

SourcePtr makeAdfSource(AdfPtr adf) {
    if (!adf) throw std::invalid_argument("ADF source needs a snapshot");
    return std::make_shared<AdfSource>(std::move(adf));
}

SourcePtr makeRegionLimited(SourcePtr outside, SourcePtr inside, const BoxWorld& region) {
    if (!outside || !inside) throw std::invalid_argument("region-limited source needs both sources");
    return std::make_shared<RegionLimited>(std::move(outside), std::move(inside), region);
}

}  // namespace kizamu::adf
