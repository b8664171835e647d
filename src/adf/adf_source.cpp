// SPDX-License-Identifier: Apache-2.0
/// @file adf_source.cpp
/// @brief AdfSource and RegionLimited.
#include "adf/adf_source.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vector_relational.hpp>

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cmath>
#include <limits>

#include <stdexcept>
#include <utility>

namespace kizamu::adf {

namespace {

/// Bit m set for each non-empty subset m of the axis set a, for each a (bit k: axis k).
constexpr std::array<uint8_t, 8> kSubsetsOf = [] {
    std::array<uint8_t, 8> t{};
    for (uint32_t a = 0; a < 8; ++a)
        for (uint32_t m = 1; m < 8; ++m)
            if ((m & a) == m) t[a] |= uint8_t(1u << m);
    return t;
}();

/// The field of a snapshot. At a lattice point that is a corner of some leaf it answers that
/// corner's stored value rather than whichever leaf the half-open lookup lands in: a larger
/// neighbour's interpolation there can differ, even in sign, and a regenerated tile must agree
/// with the untouched tiles around it on every corner they share (the mesher relies on it).
/// Elsewhere it interpolates in the leaf holding the point (half-open), as Adf::sample does.
class AdfSource final : public DistanceSource {
public:
    explicit AdfSource(AdfPtr adf)
        : mAdf(std::move(adf)), mRounding(mAdf->domain()), mTop(mAdf->domain().latticeSize()), mSerial(gNextSerial.fetch_add(1, std::memory_order_relaxed)) {}
    double distance(const glm::dvec3& p) const override { return value(p, threadCache()); }
    void distances(std::span<const glm::dvec3> p, std::span<double> out) const override {
        Cache& cache = threadCache();
        for (std::size_t i = 0; i < p.size(); ++i) out[i] = value(p[i], cache);
    }

private:
    /// A found leaf and, once asked for, its 8 decoded corners (most of a regeneration's points
    /// fall inside a few larger old leaves and interpolate there) and which of its neighbours
    /// are finer (finerNeighbours).
    struct CachedLeaf : LeafCell {
        float values[8];
        bool isDecoded = false;
        uint8_t neighboursKnown = 0, neighboursFiner = 0;  ///< bit m: neighbour cell m (finerNeighbours)
        const float* decoded() {
            if (!isDecoded) {
                corners(values);
                isDecoded = true;
            }
            return values;
        }
    };
    /// Leaves found recently, kept per thread across calls: a regeneration asks for a tile's
    /// points in many small, coherent batches. Direct-mapped by the point's 4-cell block (the
    /// table wraps every 32 x 32 x 16 finest cells): a lookup that misses the hint tries one
    /// entry and otherwise descends into it, cheaper than the search of a few recent leaves this
    /// replaced (dab edits -3 % instructions), and it keeps more of the leaves a tile's
    /// traversal returns to. A leaf answers for the points of its half-open box exactly as a
    /// fresh descent would, so the cache changes no result. It is tagged with the serial number
    /// of the source that filled it and emptied when another source uses the thread, so no entry
    /// outlives the snapshot it points into.
    struct Cache {
        static constexpr int kSize = 256;  ///< 8 x 8 x 4 blocks, about 20 KB
        uint64_t owner = 0;
        CachedLeaf cells[kSize];  ///< an empty entry has size 0: it contains no point
        /// The entries found last for a point and for the neighbours value() asks about: asked
        /// first (consecutive points share leaves, and so do their neighbours).
        int lastPoint = 0, lastNeighbour = 0;
    };
    Cache& threadCache() const {
        thread_local Cache cache;
        if (cache.owner != mSerial) {
            cache.owner = mSerial;
            for (CachedLeaf& c : cache.cells) c.size = 0;
            cache.lastPoint = cache.lastNeighbour = 0;
        }
        return cache;
    }

    /// The cached leaf holding `p`, asking entry `last` first (the common case, inline), then
    /// the entry of p's block; sets `last` to the entry used.
    CachedLeaf& locate(glm::uvec3 p, Cache& cache, int& last) const {
        CachedLeaf& hint = cache.cells[last];
        return hint.contains(p) ? hint : locateFurther(p, cache, last);
    }

    [[gnu::noinline]] CachedLeaf& locateFurther(glm::uvec3 p, Cache& cache, int& last) const {
        const glm::uvec3 b = p >> 2u;
        last = int((b.x & 7u) | ((b.y & 7u) << 3) | ((b.z & 3u) << 6));
        CachedLeaf& c = cache.cells[last];
        if (c.contains(p)) return c;
        static_cast<LeafCell&>(c) = mAdf->locateLeaf(p);
        c.isDecoded = false;
        c.neighboursKnown = c.neighboursFiner = 0;
        return c;
    }

    /// Bit m set for each non-empty subset m of `axes` whose neighbour cell of `leaf` (the
    /// cell of its size across its lower faces along m) lies in finer leaves: only those can
    /// have a point on the leaf's faces as a corner. One descent per leaf and m, kept with the
    /// leaf: most face points of a leaf have neighbours no finer than it, and then need no
    /// lookup of their own (dab edits -6 % instructions).
    uint32_t finerNeighbours(CachedLeaf& leaf, uint32_t axes) const {
        const uint32_t wanted = kSubsetsOf[axes];
        for (uint32_t missing = wanted & ~uint32_t(leaf.neighboursKnown); missing != 0; missing &= missing - 1) {
            const uint32_t m = uint32_t(std::countr_zero(missing));
            // The neighbour cell's point next to the leaf's origin; below 0 wraps past the top
            // (no neighbour there). A leaf at least as large as ours holding it holds the whole
            // cell.
            const glm::uvec3 q = leaf.origin - glm::uvec3(m & 1, (m >> 1) & 1, m >> 2);
            if (q.x < mTop && q.y < mTop && q.z < mTop && mAdf->locateLeaf(q).size < leaf.size)
                leaf.neighboursFiner |= uint8_t(1u << m);
        }
        leaf.neighboursKnown |= uint8_t(wanted);
        return leaf.neighboursFiner & wanted;
    }

    double value(const glm::dvec3& p, Cache& cache) const {
        glm::uvec3 pt;
        if (!mRounding.nearest(p, 1e-4, pt)) return mAdf->sample(glm::vec3(p)).distance;
        // Octant 0 (the unit cube above p) when inside the domain; then only octants across
        // faces of that leaf that p lies on can hold a leaf with p as a corner. The first in
        // octant order wins (their values differ only by quantisation).
        uint32_t onFace = 7;    // axes along which p lies on the first leaf's lower face
        uint32_t finer = 0xff;  // bit m: the first leaf's neighbour cell across its faces m is finer
        CachedLeaf first;  // a copy: the lookups below may reuse its cache entry
        if (pt.x < mTop && pt.y < mTop && pt.z < mTop) {
            CachedLeaf& found = locate(pt, cache, cache.lastPoint);
            const int c = found.cornerIndex(pt);
            if (c >= 0) return found.corner(c);
            onFace = 0;
            for (int k = 0; k < 3; ++k)
                if (pt[k] == found.origin[k]) onFace |= 1u << k;
            const glm::vec3 f = (glm::vec3(pt) - glm::vec3(found.origin)) / float(found.size);
            if (onFace == 0) return trilinear(found.decoded(), f).distance;  // strictly inside it
            // p, no corner of the found leaf, is no corner of a leaf at least as large next to
            // it (along an axis where p lies strictly inside, such a leaf has no corner there).
            finer = finerNeighbours(found, onFace);
            if (finer == 0) return trilinear(found.decoded(), f).distance;
            found.decoded();  // decoded where it stays cached, before the copy (most points need them)
            first = found;
        }
        for (uint32_t o = 1; o < 8; ++o) {
            // Octant o reaches the neighbour cell across the faces o & onFace (none: the first leaf).
            if ((o & onFace) == 0 || !((finer >> (o & onFace)) & 1u)) continue;
            // Below 0 wraps around past the top: one test for both ends of the domain.
            const glm::uvec3 cube = pt - glm::uvec3(o & 1, (o >> 1) & 1, o >> 2);
            if (cube.x >= mTop || cube.y >= mTop || cube.z >= mTop) continue;
            const CachedLeaf& leaf = locate(cube, cache, cache.lastNeighbour);
            const int c = leaf.cornerIndex(pt);
            if (c >= 0) return leaf.corner(c);
        }
        if (!first.tile) return mAdf->sample(glm::vec3(p)).distance;  // on the domain's upper faces
        // On the first leaf's faces but a corner of no leaf: interpolate there.
        return trilinear(first.decoded(), (glm::vec3(pt) - glm::vec3(first.origin)) / float(first.size)).distance;
    }

    static inline std::atomic<uint64_t> gNextSerial{1};
    AdfPtr mAdf;
    LatticeRounding mRounding;
    uint32_t mTop;
    uint64_t mSerial;  ///< tags this source's entries in the per-thread leaf caches
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
    /// Each side in batches (the old field's batch caches its leaf lookups), then merged; a
    /// call wholly on one side (most of a regeneration's) goes there as it is.
    void distances(std::span<const glm::dvec3> p, std::span<double> out) const override {
        const auto inside = std::size_t(std::count_if(p.begin(), p.end(), [&](const glm::dvec3& q) { return mRegion.contains(q); }));
        if (inside == p.size()) return mInside->distances(p, out);
        if (inside == 0) return mOutside->distances(p, out);
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
