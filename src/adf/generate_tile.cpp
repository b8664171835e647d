// SPDX-License-Identifier: Apache-2.0
/// @file generate_tile.cpp
/// @brief One tile's generation: subdivision from the tile root, batched sampling in the
/// tile's scratch volume, and the tile's node, leaf and brick arrays.
///
/// Takes a tile job (slot, corner samples, the base's tile in a regeneration) and produces the
/// tile: each cell looks at its centre, then its face and edge centres, and the cell rule
/// (generate_rule.h) settles it as a leaf or splits it; the children's first samples are
/// evaluated in batches for all 8 at once (prefetchChildren). Cells whose 8 children are leaves
/// become bricks; children of one type outside the band coalesce back into their parent. In
/// parts (Run::generateSmall) the root is decided first, its 8 children built as separate
/// parts, and the parts joined into the same arrays build() makes.
/// Complexity: O(cells + evaluated points) per tile; every lattice point of the tile evaluated
/// at most once (a stamp per tile marks the valid samples). Threading: one TileGenerator per
/// task, each with its own scratch volume; the scratch pool is shared and thread-safe.
#include "adf/generate_tile.h"

#include <algorithm>
#include <cassert>
#include <mutex>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace kizamu::adf::detail {

namespace {

/// Free scratch volumes, so that an edit (a few tiles) does not pay for allocating and zeroing
/// megabytes each time: per thread the one it released last, then a process-wide list.
/// Thread-safe (a mutex, held for a push or pop of the list). Memory: up to kKeep volumes in
/// the list and one per thread that generated.
class ScratchPool {
public:
    static ScratchPool& instance() {
        static ScratchPool pool;
        return pool;
    }
    std::unique_ptr<TileScratch> acquire(uint32_t dim) {
        std::unique_ptr<TileScratch>& mine = threadsOwn();
        if (mine && mine->dim == dim) return std::move(mine);
        {
            std::lock_guard lock(mMutex);
            for (std::size_t i = 0; i < mFree.size(); ++i)
                if (mFree[i]->dim == dim) {
                    std::unique_ptr<TileScratch> s = std::move(mFree[i]);
                    mFree.erase(mFree.begin() + std::ptrdiff_t(i));
                    return s;
                }
        }
        return std::make_unique<TileScratch>(dim);
    }
    void release(std::unique_ptr<TileScratch> s) {
        std::swap(threadsOwn(), s);  // this thread's from now on; the one it had goes to the list
        if (!s) return;
        std::lock_guard lock(mMutex);
        if (mFree.size() < kKeep) mFree.push_back(std::move(s));
    }

private:
    /// The volume this thread released last, which it takes again first: its lines are in this
    /// core's caches, where the shared list would hand them to either thread and a line written
    /// by another core is slow to reach (docs/decisions/0014-generation-flat-map-and-scratch.md).
    static std::unique_ptr<TileScratch>& threadsOwn() {
        thread_local std::unique_ptr<TileScratch> own;
        return own;
    }
    static constexpr std::size_t kKeep = 8;
    std::mutex mMutex;
    std::vector<std::unique_ptr<TileScratch>> mFree;
};

}  // namespace

void throwNonFinite(const glm::dvec3& p) {
    throw std::domain_error("the distance source returned a non-finite value at (" + std::to_string(p.x) + ", " +
                            std::to_string(p.y) + ", " + std::to_string(p.z) + ")");
}

TileGenerator::TileGenerator(const Domain& d, const GenerationSettings& s,
                             const DistanceSource& src, glm::uvec3 regionMin, glm::uvec3 regionMax)
    : mDomain(d),
      mRule(d, s, src),
      mSource(src),
      mLatticeSource(src.answersLattice(d)),
      mRegionMin(regionMin),
      mRegionMax(regionMax),
      mSpan(d.cellLattice(d.tileLevel())),
      mDim(mSpan + 1),
      mScratch(ScratchPool::instance().acquire(mDim)),
      mValues(mScratch->values),
      mStamp(mScratch->stamp),
      mCurrent(mScratch->current),
      mNodes(mScratch->nodes),
      mLeafCorners(mScratch->leafCorners),
      mBrickValues(mScratch->brickValues),
      mLeafFrom(mScratch->leafFrom),
      mBrickFrom(mScratch->brickFrom),
      mRecorded(mScratch->border) {
    for (int g = 0; g < 27; ++g) mGridStep[g] = index(gridOffset(g));
}

TileGenerator::~TileGenerator() { ScratchPool::instance().release(std::move(mScratch)); }

TilePtr TileGenerator::build(const TileJob& job,
                             const std::array<const BorderSamples*, kNeighbours>& neighbours,
                             BorderSamples& border, uint64_t version) {
    begin(job);
    for (int i = 0; i < kNeighbours; ++i)
        if (neighbours[i]) importFrom(*neighbours[i], i);
    mHandsOverBorder = true;
    subdivide(0, glm::uvec3(0), mSpan, mDomain.tileLevel(), false, false, oldRoot());
    groupBorder(border);
    return finish(version);
}

TilePtr TileGenerator::planRoot(const TileJob& job, Split& split, uint64_t version) {
    begin(job);
    if (decide(0, glm::uvec3(0), mSpan, mDomain.tileLevel(), false, false, oldRoot(), split)) return finish(version);
    return nullptr;
}

TileGenerator::Part TileGenerator::buildChild(const TileJob& job, const Split& split, int c) {
    beginBelowRoot(job, split);
    child(0, glm::uvec3(0), mSpan / 2, mDomain.tileLevel() + 1, c, split, false);
    return {mNodes, mLeafCorners, mBrickValues, mLeafFrom, mBrickFrom};
}

TilePtr TileGenerator::buildChildren(const TileJob& job, const Split& split, uint64_t version) {
    beginBelowRoot(job, split);
    children(0, glm::uvec3(0), mSpan, mDomain.tileLevel(), split);
    return finish(version);
}

TilePtr TileGenerator::join(const TileJob& job, const Split& split, const Part* parts, uint64_t version) {
    begin(job);
    mNodes.resize(9);
    for (int c = 0; c < 8; ++c) {
        const Part& part = parts[c];
        const auto nodeShift = uint32_t(mNodes.size() - 1);  // part node k >= 1 lands at k + shift
        const auto leafShift = uint32_t(mLeafFrom.size()), brickShift = uint32_t(mBrickFrom.size());
        auto moved = [&](uint32_t w) {
            if (node::isLeaf(w)) return node::makeLeaf(node::leafIndex(w) + leafShift, node::leafType(w));
            if (node::isBrick(w)) return node::makeBrick(node::brickIndex(w) + brickShift);
            return w + nodeShift;
        };
        mNodes[1 + c] = moved(part.nodes[0]);
        for (std::size_t k = 1; k < part.nodes.size(); ++k) mNodes.push_back(moved(part.nodes[k]));
        mLeafCorners.insert(mLeafCorners.end(), part.leafCorners.begin(), part.leafCorners.end());
        mBrickValues.insert(mBrickValues.end(), part.brickValues.begin(), part.brickValues.end());
        mLeafFrom.insert(mLeafFrom.end(), part.leafFrom.begin(), part.leafFrom.end());
        mBrickFrom.insert(mBrickFrom.end(), part.brickFrom.begin(), part.brickFrom.end());
    }
    finishParent(0, 1, 0, split);
    return finish(version);
}

void TileGenerator::begin(const TileJob& job) {
    if (++mCurrent == 0) {  // stamp wrapped: clear once every 4 billion tiles
        std::fill(mStamp.begin(), mStamp.end(), 0u);
        mCurrent = 1;
    }
    mBase = job.slot * mSpan;
    mOld = job.old && job.old->level() == mDomain.tileLevel() && job.old->latticeOrigin() == mBase ? job.old : nullptr;
    for (int c = 0; c < 8; ++c) set(index(childOffset(c) * mSpan), job.corners[c]);
    mRecorded.clear();
    mNodes.assign(1, 0u);
    mLeafCorners.clear();
    mBrickValues.clear();
    mLeafFrom.clear();
    mBrickFrom.clear();
}

void TileGenerator::beginBelowRoot(const TileJob& job, const Split& split) {
    begin(job);
    const uint32_t half = mSpan / 2;
    for (int g = 0; g < 27; ++g) set(index(gridOffset(g) * half), split.v[g]);
}

TilePtr TileGenerator::finish(uint64_t version) const {
    return Tile::create(mDomain.tileLevel(), mBase, mNodes, mLeafCorners, mBrickValues, version, mDomain.finestCellSize(),
                        mOld ? mOld->scale() : 0.0f, {mOld, mLeafFrom, mBrickFrom});
}

// ---- sampling ----

void TileGenerator::ensure(glm::uvec3 o, uint32_t half, const int* gs, int n, float* v, bool prefetched) {
    const uint32_t base = index(o);
    if (!prefetched) {
        glm::uvec3 missing[27];
        int m = 0;
        for (int k = 0; k < n; ++k)
            if (!valid(base + half * mGridStep[gs[k]])) missing[m++] = o + gridOffset(gs[k]) * half;
        if (m > 0) evaluate(missing, m);
    }
    for (int k = 0; k < n; ++k) {
        assert(valid(base + half * mGridStep[gs[k]]));
        v[gs[k]] = mValues[base + half * mGridStep[gs[k]]];
    }
}

void TileGenerator::prefetchChildren(glm::uvec3 o, uint32_t childSize, int childLevel, const Keep* keep) {
    const uint32_t q = childSize / 2;
    glm::uvec3 pts[8 * 18];
    int n = 0;
    for (int c = 0; c < 8; ++c)
        if (keep[c] == Keep::No) pts[n++] = o + childOffset(c) * childSize + gridOffset(kCentre) * q;
    evaluate(pts, n);
    n = 0;
    // The face and edge points' index steps and offsets at this size, worked out for the
    // first child that needs them (not per child and point).
    uint32_t faceStep[18];
    glm::uvec3 faceOffset[18];
    bool faceReady = false;
    for (int c = 0; c < 8; ++c) {
        const glm::uvec3 co = o + childOffset(c) * childSize;
        const uint32_t base = index(co);
        const float centre = mValues[base + q * mGridStep[kCentre]];
        // The same tests, in the same order, as decide() makes before it loads these points
        // (it only loads them when its parent prefetched: keep them in step).
        if (keep[c] != Keep::No || mRule.firstLook(centre, childLevel).leaf) continue;
        float corners[8];
        for (int k = 0; k < 8; ++k) corners[k] = mValues[base + q * mGridStep[cornerToGrid(k)]];
        if (mRule.farFromSurfaceAtFirstLook(corners, centre, childLevel) && !mRule.hidesFeature(mSource, mBase + co, childLevel))
            continue;
        if (!faceReady) {
            for (int j = 0; j < 18; ++j) {
                faceStep[j] = q * mGridStep[kFaceEdgePoints[std::size_t(j)]];
                faceOffset[j] = gridOffset(kFaceEdgePoints[std::size_t(j)]) * q;
            }
            faceReady = true;
        }
        for (int j = 0; j < 18; ++j)  // only those not evaluated yet: most are, by a sibling or a neighbour
            if (!valid(base + faceStep[j])) pts[n++] = co + faceOffset[j];
    }
    evaluate(pts, n);
}

void TileGenerator::evaluate(const glm::uvec3* local, int n) {
    // One loop per way of asking, the choice made once per call rather than per point
    // (docs/decisions/0014-generation-flat-map-and-scratch.md).
    if (mLatticeSource)
        evaluateAt<glm::uvec3>(local, n);
    else
        evaluateAt<glm::dvec3>(local, n);
}

template <class Point>
void TileGenerator::evaluateAt(const glm::uvec3* local, int n) {
    constexpr bool kLattice = std::is_same_v<Point, glm::uvec3>;
    constexpr int kBatch = 64;
    Point pts[kBatch];
    double out[kBatch];
    glm::uvec3 todo[kBatch];
    uint32_t todoAt[kBatch];
    int m = 0;
    auto flush = [&] {
        if constexpr (kLattice)
            mSource.latticeDistances(mDomain, {pts, std::size_t(m)}, {out, std::size_t(m)});
        else
            mSource.distances({pts, std::size_t(m)}, {out, std::size_t(m)});
        mEvaluations += uint64_t(m);
        for (int k = 0; k < m; ++k) {
            float value;
            if constexpr (kLattice)
                value = checkedDistance(out[k], mDomain, pts[k]);
            else
                value = checkedDistance(out[k], pts[k]);
            mValues[todoAt[k]] = value;
            if (mHandsOverBorder && onTileFace(todo[k])) recordBorder(todo[k], value);
        }
        m = 0;
    };
    const glm::dvec3 origin = mDomain.originWorld;
    const double cell = mDomain.finestCellSize();
    for (int k = 0; k < n; ++k) {
        const uint32_t i = index(local[k]);
        if (valid(i)) continue;
        mStamp[i] = mCurrent;  // claims it, so a duplicate in this list is skipped
        const glm::uvec3 p = mBase + local[k];
        if constexpr (kLattice)
            pts[m] = p;
        else
            pts[m] = Domain::latticeToWorld(origin, cell, p);
        todo[m] = local[k];
        todoAt[m++] = i;
        if (m == kBatch) flush();
    }
    if (m > 0) flush();
}

// ---- subdivision ----

void TileGenerator::subdivide(uint32_t nodeIndex, glm::uvec3 o, uint32_t s, int level,
                              bool keepChecked, bool prefetched, const OldCell& old) {
    Split split;
    if (!decide(nodeIndex, o, s, level, keepChecked, prefetched, old, split)) children(nodeIndex, o, s, level, split);
}

void TileGenerator::children(uint32_t nodeIndex, glm::uvec3 o, uint32_t s, int level, const Split& split) {
    const bool prefetched = level + 1 < mDomain.maxLevel;
    if (prefetched) prefetchChildren(o, s / 2, level + 1, split.keep);
    const auto first = uint32_t(mNodes.size());
    const std::size_t leafMark = mLeafCorners.size();
    mNodes.resize(first + 8);
    for (int c = 0; c < 8; ++c) child(first + uint32_t(c), o, s / 2, level + 1, c, split, prefetched);
    finishParent(nodeIndex, first, leafMark, split);
}

bool TileGenerator::decide(uint32_t nodeIndex, glm::uvec3 o, uint32_t s, int level,
                           bool keepChecked, bool prefetched, const OldCell& old, Split& split) {
    // (A tile's root: its children are checked by their parent.)
    if (!keepChecked && keepsOld(o, s, level, old) == Keep::Copy && copyOld(nodeIndex, old)) return true;
    float* v = split.v;
    const uint32_t base = index(o), dy = mDim * s, dz = mDim * mDim * s;
    const uint32_t cornerAt[8] = {base, base + s, base + dy, base + s + dy, base + dz, base + s + dz, base + dy + dz, base + s + dy + dz};
    float corners[8];
    for (int c = 0; c < 8; ++c) {
        assert(valid(cornerAt[c]));
        corners[c] = v[cornerToGrid(c)] = mValues[cornerAt[c]];
    }
    auto leaf = [&] {
        makeLeaf(nodeIndex, corners);
        return true;
    };
    if (level == mDomain.maxLevel) return leaf();

    const uint32_t half = s / 2;
    ensure(o, half, &kCentre, 1, v, prefetched);
    const CellRule::FirstLook look = mRule.firstLook(v[kCentre], level);
    if (look.leaf) return leaf();

    // (prefetchChildren makes these two tests for the face and edge points: keep them in step.)
    auto hides = [&] { return mRule.hidesFeature(mSource, mBase + o, level); };  // asked last: it may query the source
    if (mRule.farFromSurfaceAtFirstLook(corners, v[kCentre], level) && !hides()) return leaf();
    ensure(o, half, kFaceEdgePoints.data(), 18, v, prefetched);
    if ((mRule.farFromSurface(v, level) || CellRule::error(v) <= look.threshold) && !hides()) return leaf();

    for (int c = 0; c < 8; ++c) {
        if (mOld) split.old[c] = oldChild(old, c);
        split.keep[c] = keepsOld(o + childOffset(c) * half, half, level + 1, split.old[c]);
    }
    split.nearBand = look.nearBand;
    if (level + 1 == mDomain.maxLevel && std::all_of(split.keep, split.keep + 8, [](Keep k) { return k == Keep::No; })) {
        finestChildren(nodeIndex, v, corners, look.nearBand);
        return true;
    }
    return false;
}

void TileGenerator::child(uint32_t nodeIndex, glm::uvec3 o, uint32_t half, int childLevel, int c,
                          const Split& split, bool prefetched) {
    const glm::uvec3 co = o + childOffset(c) * half;
    if (split.keep[c] == Keep::Leaf) {
        float childCorners[8];
        for (int k = 0; k < 8; ++k) childCorners[k] = split.v[brickPoint(c, k)];
        makeLeaf(nodeIndex, childCorners);
    } else if (!(split.keep[c] == Keep::Copy && copyOld(nodeIndex, split.old[c]))) {
        subdivide(nodeIndex, co, half, childLevel, true, prefetched && split.keep[c] == Keep::No, split.old[c]);
    }
}

void TileGenerator::finishParent(uint32_t nodeIndex, uint32_t first, std::size_t leafMark, const Split& split) {
    float corners[8];
    for (int c = 0; c < 8; ++c) corners[c] = split.v[cornerToGrid(c)];
    if (!split.nearBand && sameNonBoundaryLeaves(first)) {
        // Coalesce (Kizamu 5.1): the surface did not pass through after all.
        mNodes.resize(first);
        dropLeaves(leafMark);
        return makeLeaf(nodeIndex, corners);
    }
    if (allLeaves(first)) {
        // Brick: the 8 children were the last 8 nodes and 8 leaves appended; their corners
        // are exactly this cell's 27 half-grid values.
        mNodes.resize(first);
        dropLeaves(leafMark);
        return makeBrick(nodeIndex, split.v);
    }
    mNodes[nodeIndex] = first;
}

void TileGenerator::finestChildren(uint32_t nodeIndex, const float* v, const float* corners, bool nearBand) {
    if (!nearBand) {
        auto childType = [&](int c) {
            float childCorners[8];
            for (int k = 0; k < 8; ++k) childCorners[k] = v[brickPoint(c, k)];
            return cellTypeOf(std::span<const float, 8>(childCorners, 8));
        };
        const CellType first = childType(0);
        bool same = first != CellType::Boundary;
        for (int c = 1; c < 8 && same; ++c) same = childType(c) == first;
        if (same) return makeLeaf(nodeIndex, corners);
    }
    makeBrick(nodeIndex, v);
}

bool TileGenerator::allLeaves(uint32_t first) const {
    for (int c = 0; c < 8; ++c)
        if (!node::isLeaf(mNodes[first + c])) return false;
    return true;
}

bool TileGenerator::sameNonBoundaryLeaves(uint32_t first) const {
    const uint32_t w0 = mNodes[first];
    if (!node::isLeaf(w0) || node::leafType(w0) == CellType::Boundary) return false;
    for (int c = 1; c < 8; ++c) {
        const uint32_t w = mNodes[first + c];
        if (!node::isLeaf(w) || node::leafType(w) != node::leafType(w0)) return false;
    }
    return true;
}

}  // namespace kizamu::adf::detail
