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

class AdfSource final : public DistanceSource {
public:
    explicit AdfSource(AdfPtr adf) : mAdf(std::move(adf)) {}
    double distance(const glm::dvec3& p) const override { return mAdf->sample(glm::vec3(p)).distance; }
    void distances(std::span<const glm::dvec3> p, std::span<double> out) const override {
        AdfAccessor acc(*mAdf);  // batches are coherent (one cell's points): cache the leaf
        for (std::size_t i = 0; i < p.size(); ++i) out[i] = acc.sample(glm::vec3(p[i])).distance;
    }

private:
    AdfPtr mAdf;
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
