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
#include <cstring>
#include <limits>
#include <memory>
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
///
/// Two ways to the same value: point by point (a cached descent, the corner rule and an
/// interpolation, value()), or, in a block of 8^3 lattice points asked for often, every point
/// of it at once from one pass over the leaves around it (fill()). A dab's edit asks for most
/// of its points in the few blocks of its crater, where the pass costs a fraction of the
/// point-by-point answers; a block asked only at a few corners of coarse cells is never filled
/// (docs/decisions/0015-old-field-cache-and-blocks.md). The two ways give the same
/// bits (the same stored corners, the same interpolation), so which one answers a point
/// changes no result.
class AdfSource final : public DistanceSource {
public:
    explicit AdfSource(AdfPtr adf)
        : mAdf(std::move(adf)), mRounding(mAdf->domain()), mTop(mAdf->domain().latticeSize()), mSerial(gNextSerial.fetch_add(1, std::memory_order_relaxed)) {}
    double distance(const glm::dvec3& p) const override { return value(p, threadCache()); }
    void distances(std::span<const glm::dvec3> p, std::span<double> out) const override {
        Cache& cache = threadCache();
        for (std::size_t i = 0; i < p.size(); ++i) out[i] = value(p[i], cache);
    }
    /// Its own lattice: an edit's generation asks for lattice points, which the source would
    /// otherwise round back from their world positions, a cost on every point.
    bool answersLattice(const Domain& d) const override { return d == mAdf->domain(); }
    void latticeDistances(const Domain& d, std::span<const glm::uvec3> lattice, std::span<double> out) const override {
        if (!answersLattice(d)) return DistanceSource::latticeDistances(d, lattice, out);
        Cache& cache = threadCache();
        for (std::size_t i = 0; i < lattice.size(); ++i)
            if (!latticeValue(lattice[i], cache, out[i])) out[i] = mAdf->sample(glm::vec3(d.latticeToWorld(lattice[i].x, lattice[i].y, lattice[i].z))).distance;
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
    /// The values of one block's points, filled when `asked` reaches kFillAfter (it counts no
    /// further).
    static constexpr uint32_t kBlockShift = 3, kBlockSide = 1u << kBlockShift, kBlockPoints = kBlockSide * kBlockSide * kBlockSide;
    struct Block {
        glm::uvec3 key{~0u};  ///< lattice point >> kBlockShift
        uint32_t asked = 0;
        float values[kBlockPoints];  ///< x fastest
    };
    /// Points of a block asked for before it is filled: a pass over a block costs about as
    /// much as this many point-by-point answers where its leaves are finest.
    static constexpr uint32_t kFillAfter = 24;
    /// Direct-mapped by block (wrapping every 64 finest cells along each axis, past a dab's
    /// region), about 1 MB, allocated on first use.
    static constexpr uint32_t kBlockSlots = 512;
    /// Leaves found recently, kept per thread across calls: a regeneration asks for a tile's
    /// points in many small, coherent batches. Direct-mapped by the point's 4-cell block (the
    /// table wraps every 32 x 32 x 16 finest cells): a lookup that misses the hint tries one
    /// entry and otherwise descends into it, cheaper than searching a few recent leaves, and it
    /// keeps more of the leaves a tile's traversal returns to
    /// (docs/decisions/0015-old-field-cache-and-blocks.md). A leaf answers for the points of its
    /// half-open box exactly as a fresh descent would, so the cache changes no result. It is tagged with the serial number
    /// of the source that filled it and emptied when another source uses the thread, so no entry
    /// outlives the snapshot it points into. The filled blocks (fill()) are kept beside them,
    /// under the same tag.
    /// Why not AdfAccessor's one leaf and its path: a regeneration asks in two interleaved
    /// streams (points, and the neighbours of points on a leaf's faces) and keeps per leaf what
    /// it learnt of its neighbours (finerNeighbours), both lost when a single entry is replaced;
    /// with one leaf per stream a dab's edit takes more instructions and time
    /// (docs/decisions/0013-leaf-locator-cache.md).
    struct Cache {
        static constexpr int kSize = 256;  ///< 8 x 8 x 4 blocks, about 20 KB
        uint64_t owner = 0;
        CachedLeaf cells[kSize];  ///< an empty entry has size 0: it contains no point
        /// The entries found last for a point and for the neighbours value() asks about: asked
        /// first (consecutive points share leaves, and so do their neighbours).
        int lastPoint = 0, lastNeighbour = 0;
        std::unique_ptr<Block[]> blocks;
    };
    Cache& threadCache() const {
        thread_local Cache cache;
        if (cache.owner != mSerial) {
            cache.owner = mSerial;
            for (CachedLeaf& c : cache.cells) c.size = 0;
            cache.lastPoint = cache.lastNeighbour = 0;
            if (!cache.blocks) cache.blocks = std::make_unique<Block[]>(kBlockSlots);
            for (uint32_t i = 0; i < kBlockSlots; ++i) cache.blocks[i].key = glm::uvec3(~0u);
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
    /// lookup of their own.
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
        double v;
        // Off the lattice, or on the domain's upper faces with no leaf there to take a corner
        // from: the snapshot's own (clamped) field.
        if (!mRounding.nearest(p, 1e-4, pt) || !latticeValue(pt, cache, v)) return mAdf->sample(glm::vec3(p)).distance;
        return v;
    }

    /// The value at lattice point `pt` into `out`, or false on the domain's upper faces where
    /// no leaf has `pt` as a corner (value() then samples the field there).
    bool latticeValue(glm::uvec3 pt, Cache& cache, double& out) const {
        if (pt.x < mTop && pt.y < mTop && pt.z < mTop) {
            const glm::uvec3 key = pt >> kBlockShift, in = pt & (kBlockSide - 1);
            Block& b = cache.blocks[(key.x & 7u) | ((key.y & 7u) << 3) | ((key.z & 7u) << 6)];
            const uint32_t i = (in.z * kBlockSide + in.y) * kBlockSide + in.x;
            if (b.key == key) {
                if (b.asked == kFillAfter) {
                    out = b.values[i];
                    return true;
                }
                if (++b.asked == kFillAfter) {
                    fill(b);
                    out = b.values[i];
                    return true;
                }
            } else {
                b.key = key;
                b.asked = 1;
            }
        }
        return pointValue(pt, cache, out);
    }

    /// latticeValue() point by point.
    bool pointValue(glm::uvec3 pt, Cache& cache, double& out) const {
        // Octant 0 (the unit cube above p) when inside the domain; then only octants across
        // faces of that leaf that p lies on can hold a leaf with p as a corner. The first in
        // octant order wins (their values differ only by quantisation).
        uint32_t onFace = 7;    // axes along which p lies on the first leaf's lower face
        uint32_t finer = 0xff;  // bit m: the first leaf's neighbour cell across its faces m is finer
        CachedLeaf first;  // a copy: the lookups below may reuse its cache entry
        if (pt.x < mTop && pt.y < mTop && pt.z < mTop) {
            CachedLeaf& found = locate(pt, cache, cache.lastPoint);
            const int c = found.cornerIndex(pt);
            if (c >= 0) return out = found.corner(c), true;
            onFace = 0;
            for (int k = 0; k < 3; ++k)
                if (pt[k] == found.origin[k]) onFace |= 1u << k;
            const glm::vec3 f = (glm::vec3(pt) - glm::vec3(found.origin)) / float(found.size);
            if (onFace == 0) return out = trilinear(found.decoded(), f).distance, true;  // strictly inside it
            // p, no corner of the found leaf, is no corner of a leaf at least as large next to
            // it (along an axis where p lies strictly inside, such a leaf has no corner there).
            finer = finerNeighbours(found, onFace);
            if (finer == 0) return out = trilinear(found.decoded(), f).distance, true;
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
            if (c >= 0) return out = leaf.corner(c), true;
        }
        if (!first.tile) return false;  // on the domain's upper faces
        // On the first leaf's faces but a corner of no leaf: interpolate there.
        out = trilinear(first.decoded(), (glm::vec3(pt) - glm::vec3(first.origin)) / float(first.size)).distance;
        return true;
    }

    /// Which leaf a block point's value comes from so far: the corner of the leaf it is corner
    /// `c` of (rank c: the first octant wins, as in pointValue), else (rank 8) the interpolation
    /// in the leaf holding its unit cube, the only leaf that interpolates there.
    static constexpr uint8_t kInterpolated = 8;

    /// Every value of block `b`, as pointValue gives them: one pass over the leaves that hold
    /// a unit cube of the block or one just below it (the leaves with a block point as a corner).
    /// Complexity: O(leaves around the block + 8^3). Memory: none.
    void fill(Block& b) const {
        const glm::uvec3 lo = b.key << kBlockShift;
        // (In a domain under 8 cells across the block runs past the top: its points there are
        // never asked through it.)
        const glm::uvec3 cubeLo = glm::max(lo, glm::uvec3(1u)) - 1u, cubeEnd = glm::min(lo + kBlockSide, glm::uvec3(mTop));
        uint8_t rank[kBlockPoints];
        std::memset(rank, kInterpolated, sizeof rank);
        const auto span = uint32_t(mAdf->domain().tileSpan());
        const glm::uvec3 first = cubeLo >> span, last = (cubeEnd - 1u) >> span;
        for (uint32_t z = first.z; z <= last.z; ++z)
            for (uint32_t y = first.y; y <= last.y; ++y)
                for (uint32_t x = first.x; x <= last.x; ++x) {
                    const Tile* t = mAdf->tileAtSlot({x, y, z});
                    // A coarse tile covers several slots: visited from the first of them here.
                    if (glm::uvec3(x, y, z) != glm::max(t->latticeOrigin() >> span, first)) continue;
                    visit(*t, 0, t->latticeOrigin(), mTop >> uint32_t(t->level()), cubeLo, cubeEnd, b, rank);
                }
    }

    /// The leaves under node `i` of `t` (a cell at `o`, `size` wide) that meet [cubeLo, cubeEnd).
    void visit(const Tile& t, uint32_t i, glm::uvec3 o, uint32_t size, glm::uvec3 cubeLo, glm::uvec3 cubeEnd,
               Block& b, uint8_t* rank) const {
        if (o.x >= cubeEnd.x || o.y >= cubeEnd.y || o.z >= cubeEnd.z || o.x + size <= cubeLo.x ||
            o.y + size <= cubeLo.y || o.z + size <= cubeLo.z)
            return;
        const uint32_t w = t.node(i), half = size / 2;
        float v[8];
        if (node::isInternal(w)) {
            for (uint32_t c = 0; c < 8; ++c)
                visit(t, w + c, o + glm::uvec3(c & 1, (c >> 1) & 1, c >> 2) * half, half, cubeLo, cubeEnd, b, rank);
        } else if (node::isLeaf(w)) {
            t.leafCorners(node::leafIndex(w), v);
            paint(o, size, v, b, rank);
        } else {
            paintBrick(t, node::brickIndex(w), o, half, b, rank);
        }
    }

    /// paint() for the 8 children of brick `brick` (at `o`, children `half` wide) at once: each
    /// point of its half grid is a corner of every child around it, the first octant of which
    /// is the child on the point's lower side along each axis where the point is not on the
    /// brick's upper face. The children interpolate nowhere when they are finest (half 1).
    static void paintBrick(const Tile& t, uint32_t brick, glm::uvec3 o, uint32_t half, Block& b, uint8_t* rank) {
        int16_t q[27];
        t.brickValues(brick, q);
        if (half > 1) {
            float v[8];
            for (int child = 0; child < 8; ++child) {
                for (int c = 0; c < 8; ++c) v[c] = float(q[brickPoint(child, c)]) * t.scale();  // as brickCorners
                paint(o + glm::uvec3(child & 1, (child >> 1) & 1, child >> 2) * half, half, v, b, rank);
            }
            return;
        }
        const glm::uvec3 lo = b.key << kBlockShift;
        for (uint32_t g = 0; g < 27; ++g) {
            const glm::uvec3 at(g % 3, (g / 3) % 3, g / 9);
            const glm::uvec3 rel = o + at - lo;  // wraps below lo
            if (rel.x >= kBlockSide || rel.y >= kBlockSide || rel.z >= kBlockSide) continue;
            const uint32_t i = (rel.z * kBlockSide + rel.y) * kBlockSide + rel.x;
            const auto r = uint8_t((at.x == 2) | ((at.y == 2) << 1) | ((at.z == 2) << 2));
            if (r < rank[i]) {
                b.values[i] = float(q[g]) * t.scale();
                rank[i] = r;
            }
        }
    }

    /// Leaf (`o`, `size`, corners `v`)'s part in block `b`: its own corner 0 and the
    /// interpolation at the other points of its half-open box (where it holds their unit cube),
    /// and each other corner c at the point it is the corner of (where it lies in octant c).
    static void paint(glm::uvec3 o, uint32_t size, const float v[8], Block& b, uint8_t* rank) {
        const glm::uvec3 lo = b.key << kBlockShift;
        const glm::uvec3 from = glm::max(o, lo), to = glm::min(o + size, lo + kBlockSide);
        if (size > 1 && from.x < to.x && from.y < to.y && from.z < to.z) {
            // trilinear()'s distance, its lerps hoisted out of the loops they do not depend on
            // (the same operations on the same operands: the same bits).
            const auto f = [&](uint32_t k, uint32_t at) { return (float(at) - float(o[k])) / float(size); };
            const uint32_t n = to.x - from.x;
            float a00[kBlockSide], a10[kBlockSide], a01[kBlockSide], a11[kBlockSide], b0[kBlockSide], b1[kBlockSide];
            for (uint32_t j = 0; j < n; ++j) {
                const float fx = f(0, from.x + j);
                a00[j] = v[0] + fx * (v[1] - v[0]);
                a10[j] = v[2] + fx * (v[3] - v[2]);
                a01[j] = v[4] + fx * (v[5] - v[4]);
                a11[j] = v[6] + fx * (v[7] - v[6]);
            }
            for (uint32_t y = from.y; y < to.y; ++y) {
                const float fy = f(1, y);
                for (uint32_t j = 0; j < n; ++j) {
                    b0[j] = a00[j] + fy * (a10[j] - a00[j]);
                    b1[j] = a01[j] + fy * (a11[j] - a01[j]);
                }
                for (uint32_t z = from.z; z < to.z; ++z) {
                    const float fz = f(2, z);
                    const uint32_t row = ((z - lo.z) * kBlockSide + (y - lo.y)) * kBlockSide + (from.x - lo.x);
                    for (uint32_t j = 0; j < n; ++j)
                        if (rank[row + j] == kInterpolated) b.values[row + j] = b0[j] + fz * (b1[j] - b0[j]);
                }
            }
        }
        for (uint32_t c = 0; c < 8; ++c) {
            const glm::uvec3 rel = o + glm::uvec3(c & 1, (c >> 1) & 1, c >> 2) * size - lo;  // wraps below lo
            if (rel.x >= kBlockSide || rel.y >= kBlockSide || rel.z >= kBlockSide) continue;
            const uint32_t i = (rel.z * kBlockSide + rel.y) * kBlockSide + rel.x;
            if (c < rank[i]) {
                b.values[i] = v[c];
                rank[i] = uint8_t(c);
            }
        }
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
    void distances(std::span<const glm::dvec3> p, std::span<double> out) const override {
        bySide(p, out, [&](const glm::dvec3& q) { return mRegion.contains(q); },
               [](const DistanceSource& s, std::span<const glm::dvec3> q, std::span<double> o) { s.distances(q, o); });
    }
    bool answersLattice(const Domain& d) const override {
        return mInside->answersLattice(d) && mOutside->answersLattice(d);
    }
    /// distances() at lattice points, each side asked at lattice points too (the region test
    /// on the world position the point stands for, as distances() makes it).
    void latticeDistances(const Domain& d, std::span<const glm::uvec3> p, std::span<double> out) const override {
        const glm::dvec3 origin = d.originWorld;
        const double cell = d.finestCellSize();
        auto inRegion = [&](glm::uvec3 q) { return mRegion.contains(Domain::latticeToWorld(origin, cell, q)); };
        auto ask = [&d](const DistanceSource& s, std::span<const glm::uvec3> q, std::span<double> o) { s.latticeDistances(d, q, o); };
        // A batch whose lattice box has both corners inside lies inside (latticeToWorld is
        // monotonic on each axis, the region a box): most of an edit's batches, one test each.
        glm::uvec3 lo(UINT32_MAX), hi(0);
        for (const glm::uvec3& q : p) {
            lo = glm::min(lo, q);
            hi = glm::max(hi, q);
        }
        if (!p.empty() && inRegion(lo) && inRegion(hi)) return ask(*mInside, p, out);
        bySide(p, out, inRegion, ask);
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
    /// Each side in batches (the old field's batch caches its leaf lookups), then merged; a
    /// call wholly on one side (most of a regeneration's) goes there as it is.
    template <class Point, class InRegion, class Ask>
    void bySide(std::span<const Point> p, std::span<double> out, InRegion inRegion, Ask ask) const {
        const auto inside = std::size_t(std::count_if(p.begin(), p.end(), inRegion));
        if (inside == p.size()) return ask(*mInside, p, out);
        if (inside == 0) return ask(*mOutside, p, out);
        Point in[kSourceBatch], outside[kSourceBatch];
        double inValues[kSourceBatch], outValues[kSourceBatch];
        bool isIn[kSourceBatch];
        for (std::size_t start = 0; start < p.size(); start += kSourceBatch) {
            const std::size_t n = std::min(kSourceBatch, p.size() - start);
            std::size_t ni = 0, no = 0;
            for (std::size_t i = 0; i < n; ++i) (isIn[i] = inRegion(p[start + i])) ? (in[ni++] = p[start + i]) : (outside[no++] = p[start + i]);
            if (ni) ask(*mInside, std::span<const Point>(in, ni), std::span<double>(inValues, ni));
            if (no) ask(*mOutside, std::span<const Point>(outside, no), std::span<double>(outValues, no));
            ni = no = 0;
            for (std::size_t i = 0; i < n; ++i) out[start + i] = isIn[i] ? inValues[ni++] : outValues[no++];
        }
    }

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
