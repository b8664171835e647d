// SPDX-License-Identifier: Apache-2.0
/// @file adf_source.cpp
/// @brief AdfSource and RegionLimited.
#include "adf/adf_source.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vector_relational.hpp>

#include <algorithm>
#include <limits>

#include <stdexcept>
#include <utility>

namespace kizamu::adf {

namespace {

/// A leaf found by descending a tile, without decoding its corners (most lookups only need to
/// know whether a point is one of them).
struct LeafCell {
    const Tile* tile = nullptr;
    uint32_t word = 0;     ///< the lone leaf's or the brick's node word
    int brickChild = -1;   ///< which child of the brick, or -1 for a lone leaf
    glm::uvec3 origin{0};  ///< lattice
    uint32_t size = 0;     ///< lattice units
    bool contains(glm::uvec3 p) const {
        const glm::uvec3 rel = p - origin;  // wraps around below the origin
        return rel.x < size && rel.y < size && rel.z < size;
    }
    float corner(int c) const {
        const int16_t q = brickChild < 0 ? tile->leafValue(node::leafIndex(word), c)
                                         : tile->brickValue(node::brickIndex(word), brickPoint(brickChild, c));
        return float(q) * tile->scale();
    }
};

/// The field of a snapshot. At a lattice point that is a corner of some leaf it answers that
/// corner's stored value rather than whichever leaf the half-open lookup lands in: a larger
/// neighbour's interpolation there can differ, even in sign, and a regenerated tile must agree
/// with the untouched tiles around it on every corner they share (the mesher relies on it).
/// Elsewhere it interpolates in the leaf holding the point (half-open), as Adf::sample does.
class AdfSource final : public DistanceSource {
public:
    explicit AdfSource(AdfPtr adf)
        : mAdf(std::move(adf)), mOrigin(mAdf->domain().originWorld), mInvCell(1.0 / mAdf->domain().finestCellSize()),
          mTop(mAdf->domain().latticeSize()), mMaxLevel(mAdf->domain().maxLevel),
          mTileShift(uint32_t(mAdf->domain().tileSpan())) {}
    double distance(const glm::dvec3& p) const override {
        Cache cache;
        return value(p, cache);
    }
    void distances(std::span<const glm::dvec3> p, std::span<double> out) const override {
        Cache cache;  // batches are coherent (one cell's points): keep the last leaves found
        for (std::size_t i = 0; i < p.size(); ++i) out[i] = value(p[i], cache);
    }

private:
    /// The last few leaves found. A leaf answers for the points of its half-open box, exactly
    /// as a fresh descent would, so the cache changes no result.
    struct Cache {
        static constexpr int kSize = 4;
        LeafCell cells[kSize];
        int count = 0, next = 0;
    };

    LeafCell locate(glm::uvec3 p, Cache& cache) const {
        for (int i = 0; i < cache.count; ++i)
            if (cache.cells[i].contains(p)) return cache.cells[i];
        LeafCell c;
        c.tile = mAdf->tileAtSlot(p >> mTileShift);
        const uint32_t* nodes = c.tile->nodes();
        int level = c.tile->level();
        auto childAt = [&](int l) {
            const uint32_t shift = uint32_t(mMaxLevel - l - 1);
            return ((p.x >> shift) & 1u) | (((p.y >> shift) & 1u) << 1) | (((p.z >> shift) & 1u) << 2);
        };
        uint32_t w = nodes[0];
        while (node::isInternal(w)) w = nodes[w + childAt(level++)];
        if (node::isBrick(w)) c.brickChild = int(childAt(level++));
        c.word = w;
        const uint32_t shift = uint32_t(mMaxLevel - level);
        c.origin = (p >> shift) << shift;
        c.size = 1u << shift;
        cache.cells[cache.next] = c;
        cache.next = (cache.next + 1) % Cache::kSize;
        cache.count = std::min(cache.count + 1, Cache::kSize);
        return c;
    }

    /// Corner index of lattice point `pt` in `leaf`, or -1.
    static int cornerIndex(const LeafCell& leaf, glm::uvec3 pt) {
        const glm::uvec3 rel = pt - leaf.origin;
        int c = 0;
        for (int k = 0; k < 3; ++k) {
            if (rel[k] == leaf.size) c |= 1 << k;
            else if (rel[k] != 0) return -1;
        }
        return c;
    }

    double value(const glm::dvec3& p, Cache& cache) const {
        const glm::dvec3 u = (p - mOrigin) * mInvCell;
        const glm::dvec3 r = glm::round(u);
        const bool lattice = glm::all(glm::lessThan(glm::abs(u - r), glm::dvec3(1e-4))) &&
                             glm::all(glm::greaterThanEqual(r, glm::dvec3(0.0))) && glm::all(glm::lessThanEqual(r, glm::dvec3(mTop)));
        if (!lattice) return mAdf->sample(glm::vec3(p)).distance;
        const glm::uvec3 pt(r);
        // Octant 0 (the unit cube above p) when inside the domain; then only octants across
        // faces of that leaf that p lies on can hold a leaf with p as a corner. The first in
        // octant order wins (their values differ only by quantisation).
        uint32_t onFace = 7;
        LeafCell first;
        if (pt.x < mTop && pt.y < mTop && pt.z < mTop) {
            first = locate(pt, cache);
            const int c = cornerIndex(first, pt);
            if (c >= 0) return first.corner(c);
            onFace = 0;
            for (int k = 0; k < 3; ++k)
                if (pt[k] == first.origin[k]) onFace |= 1u << k;
        }
        for (uint32_t o = 1; o < 8; ++o) {
            if ((o & onFace) == 0) continue;  // moves only along axes where p is inside the first leaf
            const glm::uvec3 off(o & 1, (o >> 1) & 1, o >> 2);
            if (glm::any(glm::lessThan(pt, off))) continue;
            const glm::uvec3 cube = pt - off;
            if (cube.x >= mTop || cube.y >= mTop || cube.z >= mTop) continue;
            const LeafCell leaf = locate(cube, cache);
            const int c = cornerIndex(leaf, pt);
            if (c >= 0) return leaf.corner(c);
        }
        if (!first.tile) return mAdf->sample(glm::vec3(p)).distance;  // on the domain's upper faces
        // Inside the first leaf (or on its faces, corner of no leaf): interpolate there.
        float corners[8];
        for (int c = 0; c < 8; ++c) corners[c] = first.corner(c);
        return trilinear(corners, (glm::vec3(pt) - glm::vec3(first.origin)) / float(first.size)).distance;
    }

    AdfPtr mAdf;
    glm::dvec3 mOrigin;
    double mInvCell;
    uint32_t mTop;
    int mMaxLevel;
    uint32_t mTileShift;
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
    /// Each side in batches (the old field's batch caches its leaf lookups), then merged.
    void distances(std::span<const glm::dvec3> p, std::span<double> out) const override {
        glm::dvec3 in[kSourceBatch], outside[kSourceBatch];
        double inValues[kSourceBatch], outValues[kSourceBatch];
        for (std::size_t start = 0; start < p.size(); start += kSourceBatch) {
            const std::size_t n = std::min(kSourceBatch, p.size() - start);
            std::size_t ni = 0, no = 0;
            for (std::size_t i = 0; i < n; ++i) (mRegion.contains(p[start + i]) ? in[ni++] : outside[no++]) = p[start + i];
            if (ni) mInside->distances({in, ni}, {inValues, ni});
            if (no) mOutside->distances({outside, no}, {outValues, no});
            ni = no = 0;
            for (std::size_t i = 0; i < n; ++i) out[start + i] = mRegion.contains(p[start + i]) ? inValues[ni++] : outValues[no++];
        }
    }
    /// Outside the region the source is the base field (regenerate's contract); a ball reaching
    /// into it is as unchanged as the edit says.
    Range unchangedRange(const glm::dvec3& c, double radius) const override {
        const glm::dvec3 nearest = glm::clamp(c, mRegion.min, mRegion.max);
        if (glm::distance(nearest, c) > radius)
            return {-std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
        return mInside->unchangedRange(c, radius);
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
