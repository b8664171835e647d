// SPDX-License-Identifier: Apache-2.0
/// @file generate.cpp
/// @brief Tiled generation: the upper pass (above the tile level), tile phases, coalescing.
#include "adf/generate.h"

#include "adf/lattice.h"
#include "util/thread_pool.h"

#include <glm/common.hpp>

#include <algorithm>
#include <array>
#include <atomic>
#include <cassert>
#include <cmath>
#include <limits>
#include <memory>
#include <mutex>
#include <span>
#include <stdexcept>
#include <thread>
#include <type_traits>
#include <utility>
#include <vector>

namespace kizamu::adf {

namespace {

// ---- the 3x3x3 half grid of a cell: point g = i + 3j + 9k, i, j, k in {0, 1, 2} ----

/// Half-grid point of corner c, by table: subdivide() looks up all 8 for every cell.
constexpr std::array<int, 8> kCornerGrid = {0, 2, 6, 8, 18, 20, 24, 26};
constexpr int cornerToGrid(int c) { return kCornerGrid[c]; }
constexpr int kCentre = 13;  // a variable, not an enum: ensure() takes its address

/// Half the diagonal of a unit cube.
constexpr double kHalfDiagonal = 0.8660254037844386;

/// Fraction of ε̂ the 19-point test allows (see CellRule::firstLook).
constexpr double kCriterionMargin = 0.75;

/// The 18 half-grid points that are neither corners nor the centre.
constexpr std::array<int, 18> kFaceEdgePoints = [] {
    std::array<int, 18> out{};
    int n = 0;
    for (int g = 0; g < 27; ++g) {
        const int i = g % 3, j = (g / 3) % 3, k = g / 9;
        const bool corner = i != 1 && j != 1 && k != 1;
        if (!corner && g != kCentre) out[n++] = g;
    }
    return out;
}();

/// (i, j, k) of half-grid point g, by table: the generator turns it into the points it lists.
constexpr std::array<glm::uvec3, 27> kGridOffset = [] {
    std::array<glm::uvec3, 27> t{};
    for (int g = 0; g < 27; ++g) t[g] = {uint32_t(g % 3), uint32_t((g / 3) % 3), uint32_t(g / 9)};
    return t;
}();
constexpr glm::uvec3 gridOffset(int g) { return kGridOffset[g]; }
constexpr glm::uvec3 childOffset(int c) { return {uint32_t(c & 1), uint32_t((c >> 1) & 1), uint32_t(c >> 2)}; }


/// The subdivision rule shared by the upper pass and the tiles (Kizamu 5.1 with 5.2).
struct CellRule {
    CellRule(const Domain& d, const GenerationSettings& s, const DistanceSource& src)
        : domain(d), bound(s.errorBound(d)), band(s.bandWorld(d)),
          // Cells no larger than the smallest feature anywhere never need the per-cell query.
          smallestFeature(src.smallestFeature()) {}

    const Domain& domain;
    ErrorBound bound;
    double band;
    double smallestFeature;  ///< m

    struct FirstLook {
        bool leaf;      ///< trivially interior or exterior, outside the band: stop here
        bool nearBand;  ///< some of the cell lies within the accurate band
        float threshold;
    };
    /// Decision from the centre distance alone. The threshold is the bound at the cell point
    /// nearest the surface, so every point of the cell gets at least its own ε̂, times a
    /// margin: the 19 test points see the largest error of a smooth field, but 16-bit
    /// quantisation and the curvature seams of rounded shapes add a little elsewhere.
    FirstLook firstLook(float centre, int level) const {
        const double halfDiag = double(domain.cellLattice(level)) * domain.finestCellSize() * kHalfDiagonal;
        const double dc = std::abs(double(centre));
        const bool mayContainSurface = dc <= halfDiag;
        const bool nearBand = band > 0.0 && dc - halfDiag < band;
        return {!mayContainSurface && !nearBand, nearBand,
                float(kCriterionMargin * bound(std::max(0.0, dc - halfDiag)))};
    }
    /// True when a feature of the source smaller than the cell may cross it (see
    /// DistanceSource::featureSize): the cell must be split whatever its test points say.
    bool hidesFeature(const DistanceSource& src, glm::uvec3 latticeOrigin, int level) const {
        if (level >= domain.maxLevel) return false;
        const double size = double(domain.cellLattice(level)) * domain.finestCellSize();
        if (size <= smallestFeature) return false;
        const double half = 0.5 * double(domain.cellLattice(level));
        const glm::dvec3 c = domain.originWorld + (glm::dvec3(latticeOrigin) + half) * domain.finestCellSize();
        return src.featureSize(c, size * kHalfDiagonal) < size;
    }

    /// Distance grading at the finest level: true when a cell one level above the finest has
    /// all 27 half-grid samples at least one finest cell from the surface. Such a cell holds
    /// no surface (every point of it is within sqrt(3)/2 finest cells of a sample) and fails
    /// the error test only across a kink of the field (a medial sheet from a sharp edge) or
    /// a focal point, where finest children miss the bound as well: splitting would halve an
    /// error the accuracy contract already leaves out (within two finest cells of a crease,
    /// ARCHITECTURE.md "Accuracy at creases"), at 8 times the cells. Not applied higher up:
    /// a cell four finest cells wide across a kink is off by half a cell two cells from it
    /// (|x - 1| on [0, 4], at x = 3), beyond that allowance, as the CSG accuracy test shows.
    bool farFromSurface(const float* v, int level) const {
        return finestParent(level) && atLeastCells(nearestOf(v, 27), 1.0);
    }
    /// The same from the 8 corners and the centre, before the other 18 samples are taken:
    /// all at least 3 finest cells from the surface puts every face and edge centre (one
    /// cell from a corner or the centre) a cell or more from it, for any field no steeper
    /// than 2. Most cells a dab's crease sheet leaves at that level are settled here. Both
    /// tests assume a 1-Lipschitz field (the DistanceSource contract); a steeper tool field
    /// (build, heat gun) is covered by hidesFeature, which callers ask first.
    bool farFromSurfaceAtFirstLook(const float* corners, float centre, int level) const {
        return finestParent(level) && atLeastCells(std::min(nearestOf(corners, 8), std::abs(centre)), 3.0);
    }
    bool finestParent(int level) const { return level + 1 == domain.maxLevel; }
    bool atLeastCells(float distance, double cells) const { return double(distance) >= cells * domain.finestCellSize(); }
    /// Smallest |v[i]|: the sample nearest the surface.
    static float nearestOf(const float* v, int n) {
        float nearest = std::abs(v[0]);
        for (int i = 1; i < n; ++i) nearest = std::min(nearest, std::abs(v[i]));
        return nearest;
    }

    /// Largest |computed - reconstructed| over the 19 centre, face and edge points. The
    /// trilinear value at a half-grid point is the mean of the corners it lies between, built
    /// up edge -> face -> centre.
    static float error(const float* v) {
        auto g = [](int i, int j, int k) { return i + 3 * j + 9 * k; };
        float err = 0.0f;
        auto test = [&](int at, float recon) { err = std::max(err, std::abs(v[at] - recon)); };
        float ex[3][3], ey[3][3];  // x-edge centres at (j, k), y-edge centres at (i, k)
        for (int a = 0; a <= 2; a += 2)
            for (int b = 0; b <= 2; b += 2) {
                ex[a][b] = 0.5f * (v[g(0, a, b)] + v[g(2, a, b)]);
                ey[a][b] = 0.5f * (v[g(a, 0, b)] + v[g(a, 2, b)]);
                test(g(1, a, b), ex[a][b]);
                test(g(a, 1, b), ey[a][b]);
                test(g(a, b, 1), 0.5f * (v[g(a, b, 0)] + v[g(a, b, 2)]));
            }
        const float fz0 = 0.5f * (ex[0][0] + ex[2][0]), fz2 = 0.5f * (ex[0][2] + ex[2][2]);
        test(g(1, 1, 0), fz0);
        test(g(1, 1, 2), fz2);
        test(g(1, 0, 1), 0.5f * (ex[0][0] + ex[0][2]));
        test(g(1, 2, 1), 0.5f * (ex[2][0] + ex[2][2]));
        test(g(0, 1, 1), 0.5f * (ey[0][0] + ey[0][2]));
        test(g(2, 1, 1), 0.5f * (ey[2][0] + ey[2][2]));
        test(kCentre, 0.5f * (fz0 + fz2));
        return err;
    }
};

/// A source's value as stored, or a domain_error naming the point if it is NaN or infinite.
float checkedDistance(double d, const glm::dvec3& p) {
    if (!std::isfinite(d))
        throw std::domain_error("the distance source returned a non-finite value at (" + std::to_string(p.x) + ", " +
                                std::to_string(p.y) + ", " + std::to_string(p.z) + ")");
    return float(d);
}
/// The same at lattice point `p` of `d` (its world position is only needed for the message).
inline float checkedDistance(double v, const Domain& d, glm::uvec3 p) {
    return std::isfinite(v) ? float(v) : checkedDistance(v, d.latticeToWorld(p.x, p.y, p.z));
}

TilePtr makeSingleCellTile(int level, glm::uvec3 origin, const float* corners, uint64_t version, double finestCell) {
    const CellType t = cellTypeOf(std::span<const float, 8>(corners, 8));
    const uint32_t nodeWord = node::makeLeaf(0, t);
    return Tile::create(level, origin, {&nodeWord, 1}, {corners, 8}, {}, version, finestCell);
}

/// The face and edge neighbours of a tile (corners are shared through the upper pass).
constexpr int kNeighbours = 18;
constexpr std::array<glm::ivec3, kNeighbours> kNeighbourOffsets = [] {
    std::array<glm::ivec3, kNeighbours> out{};
    int n = 0;
    for (int z = -1; z <= 1; ++z)
        for (int y = -1; y <= 1; ++y)
            for (int x = -1; x <= 1; ++x) {
                const int nonzero = (x != 0) + (y != 0) + (z != 0);
                if (nonzero == 1 || nonzero == 2) out[n++] = {x, y, z};
            }
    return out;
}();
/// Index into kNeighbourOffsets of offset o, by table (-1 for the centre and the corners).
constexpr std::array<int8_t, 27> kNeighbourOfOffset = [] {
    std::array<int8_t, 27> t{};
    for (auto& v : t) v = -1;
    for (int i = 0; i < kNeighbours; ++i) {
        const glm::ivec3 o = kNeighbourOffsets[i];
        t[(o.x + 1) + 3 * (o.y + 1) + 9 * (o.z + 1)] = int8_t(i);
    }
    return t;
}();
constexpr int neighbourIndex(glm::ivec3 o) { return kNeighbourOfOffset[(o.x + 1) + 3 * (o.y + 1) + 9 * (o.z + 1)]; }

/// The border lists (BorderSamples) a tile reads from the neighbour at offset n from it: those
/// of the neighbour's face or edge at -n, and for a face the 4 edges around it.
struct BorderLists {
    int count = 0;
    std::array<int, 5> lists{};
};
constexpr std::array<BorderLists, kNeighbours> kBorderLists = [] {
    auto nonzero = [](glm::ivec3 o) { return (o.x != 0) + (o.y != 0) + (o.z != 0); };
    std::array<BorderLists, kNeighbours> t{};
    for (int n = 0; n < kNeighbours; ++n) {
        const glm::ivec3 back = -kNeighbourOffsets[n];
        for (int m = 0; m < kNeighbours; ++m) {
            const glm::ivec3 e = kNeighbourOffsets[m];
            const bool edgeOfFace =
                nonzero(back) == 1 && nonzero(e) == 2 && e.x * back.x + e.y * back.y + e.z * back.z == 1;
            if (e == back || edgeOfFace) t[n].lists[t[n].count++] = m;
        }
    }
    return t;
}();

/// Open-addressing map from packed lattice keys to values: the tile pass looks up 18
/// neighbours per tile and the upper pass caches its samples here, both hot enough that
/// std::unordered_map's node allocations showed in profiles.
template <class V>
class FlatKeyMap {
public:
    /// Pointer to the value of `key`, inserting `fresh` first if absent; `inserted` says which.
    V* findOrInsert(uint64_t key, V fresh, bool& inserted) {
        if ((mSize + 1) * 2 > mKeys.size()) grow();
        std::size_t i = slotOf(key);
        while (mKeys[i] != kEmpty) {
            if (mKeys[i] == key) {
                inserted = false;
                return &mValues[i];
            }
            i = (i + 1) & (mKeys.size() - 1);
        }
        mKeys[i] = key;
        mValues[i] = fresh;
        ++mSize;
        inserted = true;
        return &mValues[i];
    }
    const V* find(uint64_t key) const {
        if (mKeys.empty()) return nullptr;
        for (std::size_t i = slotOf(key);; i = (i + 1) & (mKeys.size() - 1)) {
            if (mKeys[i] == key) return &mValues[i];
            if (mKeys[i] == kEmpty) return nullptr;
        }
    }
    void reserve(std::size_t n) {
        while (mKeys.size() < 2 * n + 2) grow();
    }

private:
    static constexpr uint64_t kEmpty = ~uint64_t(0);
    std::size_t slotOf(uint64_t key) const {
        return std::size_t((key * 0x9e3779b97f4a7c15ull) >> 20) & (mKeys.size() - 1);
    }
    void grow() {
        std::vector<uint64_t> keys = std::move(mKeys);
        std::vector<V> values = std::move(mValues);
        mKeys.assign(std::max<std::size_t>(64, keys.size() * 2), kEmpty);
        mValues.assign(mKeys.size(), V{});
        mSize = 0;
        bool inserted;
        for (std::size_t i = 0; i < keys.size(); ++i)
            if (keys[i] != kEmpty) *findOrInsert(keys[i], values[i], inserted) = values[i];
    }
    std::vector<uint64_t> mKeys;
    std::vector<V> mValues;
    std::size_t mSize = 0;
};

/// Samples a tile evaluated itself on its border, filed once under the face or edge they lie on
/// (named by the neighbour across it); read by the neighbours of higher colours, generated after it
/// (an edge neighbour reads its edge, a face neighbour its face and the 4 edges around it, see
/// kBorderLists). Points are packed local coordinates. One array grouped by face and edge,
/// filled once when the tile is done: 18 growing lists cost a small tile (a LOD's) dozens of
/// allocations, most of its generation's.
struct BorderSamples {
    std::vector<std::pair<uint32_t, float>> entries;
    std::array<uint32_t, kNeighbours + 1> begin{};  ///< face or edge n's: [begin[n], begin[n + 1])
    std::span<const std::pair<uint32_t, float>> on(int n) const {
        return {entries.data() + begin[n], entries.data() + begin[n + 1]};
    }
};

/// A border sample as recorded during a tile's generation, before grouping.
struct BorderRecord {
    uint32_t key;
    float value;
    int list;  ///< face or edge, by the neighbour across it
};

constexpr uint32_t packLocal(glm::uvec3 p) { return p.x | (p.y << 11) | (p.z << 22); }
constexpr glm::uvec3 unpackLocal(uint32_t k) { return {k & 2047u, (k >> 11) & 2047u, k >> 22}; }

struct TileJob {
    glm::uvec3 slot;
    std::array<float, 8> corners;
    const Tile* old = nullptr;  ///< the base snapshot's tile at this slot (regeneration), if it has one
};

/// Working memory of one tile generation: the (2^span+1)^3 sample volume with validity
/// stamps (a new stamp per tile instead of clearing), and the node and corner arrays.
struct TileScratch {
    explicit TileScratch(uint32_t d) : dim(d), values(std::size_t(d) * d * d), stamp(values.size(), 0) {}
    uint32_t dim;
    std::vector<float> values;
    std::vector<uint32_t> stamp;
    uint32_t current = 0;
    std::vector<uint32_t> nodes;
    std::vector<float> leafCorners;
    std::vector<float> brickValues;
    std::vector<uint32_t> leafFrom, brickFrom;  ///< per leaf and brick: the old tile's it copies (TileCopies)
    std::vector<BorderRecord> border;
};

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
    /// core's caches, where the shared list handed them to either thread (a line written by the
    /// other core took about 250 ns to reach on the 2-vCPU machine).
    static std::unique_ptr<TileScratch>& threadsOwn() {
        thread_local std::unique_ptr<TileScratch> own;
        return own;
    }
    static constexpr std::size_t kKeep = 8;
    std::mutex mMutex;
    std::vector<std::unique_ptr<TileScratch>> mFree;
};

/// What a regenerated cell keeps of the old tile (TileGenerator::keepsOld).
enum class Keep : uint8_t { No, Copy, Leaf };

/// Generates one tile; lives for one tile, borrowing a scratch volume from the pool.
class TileGenerator {
public:
    /// `regionMin`/`regionMax`: the lattice box being regenerated; cells of a job's old tile that
    /// lie outside it are copied rather than generated.
    TileGenerator(const Domain& d, const GenerationSettings& s, const DistanceSource& src, glm::uvec3 regionMin,
                  glm::uvec3 regionMax)
        : mDomain(d), mRule(d, s, src), mSource(src), mLatticeSource(src.answersLattice(d)),
          mRegionMin(regionMin), mRegionMax(regionMax),
          mSpan(d.cellLattice(d.tileLevel())), mDim(mSpan + 1),
          mScratch(ScratchPool::instance().acquire(mDim)), mValues(mScratch->values),
          mStamp(mScratch->stamp), mCurrent(mScratch->current), mNodes(mScratch->nodes),
          mLeafCorners(mScratch->leafCorners), mBrickValues(mScratch->brickValues), mLeafFrom(mScratch->leafFrom),
          mBrickFrom(mScratch->brickFrom), mRecorded(mScratch->border) {
        for (int g = 0; g < 27; ++g) mGridStep[g] = index(gridOffset(g));
    }
    ~TileGenerator() { ScratchPool::instance().release(std::move(mScratch)); }
    TileGenerator(const TileGenerator&) = delete;
    TileGenerator& operator=(const TileGenerator&) = delete;

    /// Builds the tile for `job`; reads its neighbours' border samples, writes its own to `border`.
    TilePtr build(const TileJob& job, const std::array<const BorderSamples*, kNeighbours>& neighbours,
                  BorderSamples& border, uint64_t version) {
        begin(job);
        for (int i = 0; i < kNeighbours; ++i)
            if (neighbours[i]) importFrom(*neighbours[i], i);
        mHandsOverBorder = true;
        subdivide(0, glm::uvec3(0), mSpan, mDomain.tileLevel(), false, false, oldRoot());
        groupBorder(border);
        return finish(version);
    }

    // ---- a tile generated in parts: its root here, its 8 children side by side, then joined ----
    // (Run::generateSmall does it for small runs, where one tile may hold most of the work.)
    // The arrays come out as build() makes them: a child's subtree is a contiguous, depth-first
    // run of nodes, leaves and bricks, so the parts are joined by moving their indices.

    /// Where the old tile holds a cell: its node word `word`, the child `brickChild` of a brick
    /// (-1: the word itself), and whether that is a leaf coarser than the cell (then the cell
    /// lies inside it).
    struct OldCell {
        uint32_t word = 0;
        int brickChild = -1;
        bool coarser = false;
    };

    /// What a cell needs once its own samples are in: nothing more (it was settled as a leaf, a
    /// copy, or a brick of finest children), or its children generated as `keep` says.
    struct Split {
        float v[27];  ///< the cell's half-grid values: its children's corners
        Keep keep[8];
        OldCell old[8];  ///< where the old tile holds each child (when there is an old tile)
        bool nearBand;
    };

    /// A child's subtree on its own: node 0 is the child's word.
    struct Part {
        std::vector<uint32_t> nodes;
        std::vector<float> leafCorners, brickValues;
        std::vector<uint32_t> leafFrom, brickFrom;
    };

    /// The tile root's decision. Returns the finished tile when the root needs no children
    /// generated, else null and fills `split`.
    TilePtr planRoot(const TileJob& job, Split& split, uint64_t version) {
        begin(job);
        if (decide(0, glm::uvec3(0), mSpan, mDomain.tileLevel(), false, false, oldRoot(), split)) return finish(version);
        return nullptr;
    }

    /// Child `c` of the tile root that `split` describes.
    Part buildChild(const TileJob& job, const Split& split, int c) {
        beginBelowRoot(job, split);
        child(0, glm::uvec3(0), mSpan / 2, mDomain.tileLevel() + 1, c, split, false);
        return {mNodes, mLeafCorners, mBrickValues, mLeafFrom, mBrickFrom};
    }

    /// The tile from the root's `split`, its children generated here one after another (what
    /// build() does after the root's decision).
    TilePtr buildChildren(const TileJob& job, const Split& split, uint64_t version) {
        beginBelowRoot(job, split);
        children(0, glm::uvec3(0), mSpan, mDomain.tileLevel(), split);
        return finish(version);
    }

    /// The tile from the root's `split` and its 8 children's parts.
    TilePtr join(const TileJob& job, const Split& split, const Part* parts, uint64_t version) {
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

    uint64_t evaluations() const { return mEvaluations; }

private:
    /// Starts a tile: a fresh stamp, the job's old tile and corners, empty arrays.
    void begin(const TileJob& job) {
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

    /// Starts a tile below its root: the root's 27 samples, taken by planRoot, are valid again.
    void beginBelowRoot(const TileJob& job, const Split& split) {
        begin(job);
        const uint32_t half = mSpan / 2;
        for (int g = 0; g < 27; ++g) set(index(gridOffset(g) * half), split.v[g]);
    }

    TilePtr finish(uint64_t version) const {
        return Tile::create(mDomain.tileLevel(), mBase, mNodes, mLeafCorners, mBrickValues, version, mDomain.finestCellSize(),
                            mOld ? mOld->scale() : 0.0f, {mOld, mLeafFrom, mBrickFrom});
    }

    uint32_t index(glm::uvec3 p) const { return (p.z * mDim + p.y) * mDim + p.x; }
    bool valid(uint32_t i) const { return mStamp[i] == mCurrent; }
    void set(uint32_t i, float v) {
        mValues[i] = v;
        mStamp[i] = mCurrent;
    }

    /// Copies the samples neighbour `n` (the `neighbour`-th offset from us) evaluated on our
    /// shared border.
    void importFrom(const BorderSamples& n, int neighbour) {
        const glm::ivec3 shift = kNeighbourOffsets[neighbour] * int(mSpan);
        const BorderLists& from = kBorderLists[neighbour];
        for (int l = 0; l < from.count; ++l)
            for (const auto& [key, v] : n.on(from.lists[l])) {
                const uint32_t i = index(glm::uvec3(glm::ivec3(unpackLocal(key)) + shift));
                if (!valid(i)) set(i, v);
            }
    }

    /// True when `p` lies on a face of the tile. Unsigned wrap: false when 1 <= coordinate <=
    /// span - 1 on every axis (interior).
    bool onTileFace(glm::uvec3 p) const {
        return !(p.x - 1 < mSpan - 1 && p.y - 1 < mSpan - 1 && p.z - 1 < mSpan - 1);
    }

    /// Files a freshly evaluated point on the tile's faces under the face or edge it lies on.
    void recordBorder(glm::uvec3 p, float v) {
        const glm::ivec3 side(p.x == 0 ? -1 : (p.x == mSpan ? 1 : 0), p.y == 0 ? -1 : (p.y == mSpan ? 1 : 0),
                              p.z == 0 ? -1 : (p.z == mSpan ? 1 : 0));
        const int list = neighbourIndex(side);  // -1: interior, or a tile corner (upper pass)
        if (list >= 0) mRecorded.push_back({packLocal(p), v, list});
    }

    /// Hands the recorded border samples out grouped by face and edge, in recording order.
    void groupBorder(BorderSamples& border) const {
        border.begin.fill(0);
        for (const BorderRecord& r : mRecorded) ++border.begin[std::size_t(r.list) + 1];
        for (int n = 0; n < kNeighbours; ++n) border.begin[n + 1] += border.begin[n];
        border.entries.resize(mRecorded.size());
        std::array<uint32_t, kNeighbours> at;
        std::copy(border.begin.begin(), border.begin.end() - 1, at.begin());
        for (const BorderRecord& r : mRecorded) border.entries[at[r.list]++] = {r.key, r.value};
    }

    /// Makes the half-grid points `gs` of the cell at `o` (half size `half`) valid, evaluating
    /// the missing ones in one batch, and loads them into v. Indices by table (mGridStep): a
    /// cell's points are nearly all valid already (prefetchChildren), and working out each one's
    /// coordinates to look it up cost a full generation 7 % of its instructions. `prefetched`:
    /// they are all valid (the parent's prefetchChildren took them), so they are only loaded.
    void ensure(glm::uvec3 o, uint32_t half, const int* gs, int n, float* v, bool prefetched) {
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

    /// Evaluates, in two large batches, what the 8 children of a cell will ask for first: their
    /// centres, then the face and edge centres of those the centre does not settle. The set of
    /// evaluated points is the one the children would evaluate one by one (each child still
    /// looks at its centre first), but a source call now covers up to 144 points instead of
    /// 1 or 18, which halves the per-point cost of a CSG tree.
    /// Children that will be copied from the old tile (`keep`) need no samples (if the copy
    /// turns out impossible, subdivide evaluates them itself: only the batching differs).
    void prefetchChildren(glm::uvec3 o, uint32_t childSize, int childLevel, const Keep* keep) {
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

    /// Evaluates the listed local points that are not valid yet (duplicates allowed), in
    /// batches of up to 64.
    void evaluate(const glm::uvec3* local, int n) {
        // One loop per way of asking: a branch per point cost a full generation 1.7 % more
        // instructions.
        if (mLatticeSource)
            evaluateAt<glm::uvec3>(local, n);
        else
            evaluateAt<glm::dvec3>(local, n);
    }

    /// evaluate() asking the source at lattice points (Point = glm::uvec3) or at their world
    /// positions (glm::dvec3).
    template <class Point>
    void evaluateAt(const glm::uvec3* local, int n) {
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

    /// `from`: the old tile's leaf it copies, if it does (the tile then takes its packing).
    void makeLeaf(uint32_t nodeIndex, const float* corners, uint32_t from = TileCopies::kNotCopied) {
        const auto leaf = uint32_t(mLeafCorners.size() / 8);
        mLeafCorners.insert(mLeafCorners.end(), corners, corners + 8);
        mLeafFrom.push_back(from);
        mNodes[nodeIndex] = node::makeLeaf(leaf, cellTypeOf(std::span<const float, 8>(corners, 8)));
    }
    /// `from` as for makeLeaf.
    void makeBrick(uint32_t nodeIndex, const float* values, uint32_t from = TileCopies::kNotCopied) {
        mNodes[nodeIndex] = node::makeBrick(uint32_t(mBrickValues.size() / 27));
        mBrickValues.insert(mBrickValues.end(), values, values + 27);
        mBrickFrom.push_back(from);
    }
    /// Drops the leaves made since there were `leafMark` corners.
    void dropLeaves(std::size_t leafMark) {
        mLeafCorners.resize(leafMark);
        mLeafFrom.resize(leafMark / 8);
    }

    /// True when the cell is clear of the region by half its size: then its circumscribed ball
    /// (radius 0.87 s about its centre: what featureSize is asked about, and it holds every
    /// sub-cell's ball) misses the region, so a full generation would decide for it as the base
    /// did, and copying it changes nothing.
    bool outsideRegion(glm::uvec3 o, uint32_t s) const {
        const glm::ivec3 a(mBase + o);
        const int margin = int((s + 1) / 2);
        const glm::ivec3 lo = glm::ivec3(mRegionMin) - margin, hi = glm::ivec3(mRegionMax) + margin;
        return a.x > hi.x || a.y > hi.y || a.z > hi.z || a.x + int(s) < lo.x || a.y + int(s) < lo.y || a.z + int(s) < lo.z;
    }

    /// Where the old tile holds the tile's root: its root word. Below, each cell's comes from its
    /// parent's (oldChild), never a descent.
    OldCell oldRoot() const { return mOld ? OldCell{mOld->node(0), -1, false} : OldCell{}; }
    /// Where the old tile holds child `c` of the cell it holds at `parent`.
    OldCell oldChild(const OldCell& parent, int c) const {
        if (parent.coarser || parent.brickChild >= 0) return {parent.word, parent.brickChild, true};
        if (node::isInternal(parent.word)) return {mOld->node(parent.word + uint32_t(c)), -1, false};
        if (node::isLeaf(parent.word)) return {parent.word, -1, true};
        return {parent.word, c, false};  // a brick: the child is one of its children
    }

    /// Sub-tile regeneration: what a cell keeps of the old tile. `Copy`: the old tile's cells
    /// there. `Leaf`: the cell lies inside a coarser old leaf, whose trilinear field it
    /// inherits as one leaf on the parent's half-grid values (a fresh generation would find it
    /// exact and stop there too). Cells clear of the region are copied; inside it, cells where
    /// the source says it equals the old field for every value the old cells hold there, and
    /// where no new feature asks for finer cells, are kept too.
    /// `cell`: where the old tile holds it.
    Keep keepsOld(glm::uvec3 o, uint32_t s, int level, const OldCell& cell) const {
        if (!mOld) return Keep::No;
        if (outsideRegion(o, s)) return Keep::Copy;
        if (level >= mDomain.maxLevel) return Keep::No;  // its corners are sampled already
        const double size = double(s) * mDomain.finestCellSize();
        const glm::dvec3 centre = mDomain.originWorld + (glm::dvec3(mBase + o) + 0.5 * double(s)) * mDomain.finestCellSize();
        DistanceSource::Range range = mSource.unchangedRange(centre, size * kHalfDiagonal);
        // The old tile's values are rounded (16-bit steps, and within a leaf step for packed
        // leaves, groups and bricks, far ones too): stay clear of the range's ends by that much.
        const double rounding = double(mOld->scale()) * double(std::max(1, mOld->leafStep()) + 1);
        range.lo += rounding;
        range.hi -= rounding;
        if (range.lo > range.hi || mRule.hidesFeature(mSource, mBase + o, level)) return Keep::No;
        return oldValuesWithin(cell, range);
    }

    /// Whether every value the old tile stores for the cell at `o` (its subtree, or the coarser
    /// leaf holding it) lies in `range`: then so does the old field over the cell, which is
    /// trilinear between them. Says which way the cell can be kept.
    Keep oldValuesWithin(const OldCell& cell, const DistanceSource::Range& range) const {
        const float scale = mOld->scale();
        // value(k) is a quantised value; all n must decode into the range
        auto inRange = [&](int n, const auto& value) {
            for (int k = 0; k < n; ++k) {
                const double v = double(float(value(k)) * scale);
                if (!(range.lo <= v && v <= range.hi)) return false;
            }
            return true;
        };
        // A leaf's 8 corners decoded at once (one branch on its form: own or grouped, packed or not).
        auto leafValues = [&](uint32_t leaf) {
            std::array<int16_t, 8> q;
            mOld->leafValues(leaf, q.data());
            return [q](int c) { return q[std::size_t(c)]; };
        };
        if (cell.brickChild >= 0) {
            const uint32_t brick = node::brickIndex(cell.word);
            if (!inRange(8, [&](int c) { return mOld->brickValue(brick, brickPoint(cell.brickChild, c)); })) return Keep::No;
            return cell.coarser ? Keep::Leaf : Keep::Copy;
        }
        if (cell.coarser) return inRange(8, leafValues(node::leafIndex(cell.word))) ? Keep::Leaf : Keep::No;
        uint32_t stack[8 * kMaxTileSpan + 8];  // depth-first: at most 7 pending siblings per level
        int top = 0;
        stack[top++] = cell.word;
        while (top > 0) {
            const uint32_t w = stack[--top];
            if (node::isLeaf(w)) {
                if (!inRange(8, leafValues(node::leafIndex(w)))) return Keep::No;
            } else if (node::isBrick(w)) {
                const uint32_t brick = node::brickIndex(w);
                if (!inRange(27, [&](int g) { return mOld->brickValue(brick, g); })) return Keep::No;
            } else {
                for (uint32_t c = 0; c < 8; ++c) stack[top++] = mOld->node(w + c);
            }
        }
        return Keep::Copy;
    }

    /// Sub-tile regeneration: a cell outside the region keeps the old tile's cells there, when
    /// the old tile has this cell (or it is one of an old brick's children). The source equals
    /// the old field outside the region, so generating would only re-derive them, at the cost
    /// of every sample; copying also keeps their structure exactly. False: generate it.
    bool copyOld(uint32_t nodeIndex, const OldCell& cell) {
        if (cell.coarser) return false;
        if (cell.brickChild >= 0) {
            float corners[8];
            for (int c = 0; c < 8; ++c) corners[c] = mOld->brickCorner(node::brickIndex(cell.word), cell.brickChild, c);
            makeLeaf(nodeIndex, corners);
            return true;
        }
        copySubtree(nodeIndex, cell.word);
        return true;
    }

    void copySubtree(uint32_t nodeIndex, uint32_t w) {
        const float scale = mOld->scale();
        if (node::isLeaf(w)) {
            float corners[8];
            mOld->leafCorners(node::leafIndex(w), corners);
            makeLeaf(nodeIndex, corners, node::leafIndex(w));
        } else if (node::isBrick(w)) {
            int16_t q[27];
            mOld->brickValues(node::brickIndex(w), q);  // one branch on the brick's form for all
            float values[27];
            for (int g = 0; g < 27; ++g) values[g] = float(q[g]) * scale;
            makeBrick(nodeIndex, values, node::brickIndex(w));
        } else {
            const auto first = uint32_t(mNodes.size());
            mNodes.resize(first + 8);
            for (int c = 0; c < 8; ++c) copySubtree(first + uint32_t(c), mOld->node(w + uint32_t(c)));
            mNodes[nodeIndex] = first;
        }
    }

    /// `keepChecked`: the parent already asked keepsOld for this cell (and was told no, or
    /// the copy failed). `prefetched`: the parent's prefetchChildren evaluated what this cell
    /// looks at (decide then only loads it).
    /// `old`: where the old tile holds the cell (its parent's Split::old; oldRoot at the root).
    void subdivide(uint32_t nodeIndex, glm::uvec3 o, uint32_t s, int level, bool keepChecked, bool prefetched,
                   const OldCell& old) {
        Split split;
        if (!decide(nodeIndex, o, s, level, keepChecked, prefetched, old, split)) children(nodeIndex, o, s, level, split);
    }

    /// The children of the cell at `o` (node `nodeIndex`) that `split` describes, appended as
    /// the next 8 nodes with their subtrees, then the cell finished (finishParent).
    void children(uint32_t nodeIndex, glm::uvec3 o, uint32_t s, int level, const Split& split) {
        const bool prefetched = level + 1 < mDomain.maxLevel;
        if (prefetched) prefetchChildren(o, s / 2, level + 1, split.keep);
        const auto first = uint32_t(mNodes.size());
        const std::size_t leafMark = mLeafCorners.size();
        mNodes.resize(first + 8);
        for (int c = 0; c < 8; ++c) child(first + uint32_t(c), o, s / 2, level + 1, c, split, prefetched);
        finishParent(nodeIndex, first, leafMark, split);
    }

    /// The cell's own decision: true when settled (node `nodeIndex` written), else `split` says
    /// what its children need.
    bool decide(uint32_t nodeIndex, glm::uvec3 o, uint32_t s, int level, bool keepChecked, bool prefetched, const OldCell& old,
                Split& split) {
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

    /// Child `c` (at node `nodeIndex`, size `half`) of the cell at `o`, as `split` says;
    /// `prefetched`: prefetchChildren ran for the children.
    void child(uint32_t nodeIndex, glm::uvec3 o, uint32_t half, int childLevel, int c, const Split& split, bool prefetched) {
        const glm::uvec3 co = o + childOffset(c) * half;
        if (split.keep[c] == Keep::Leaf) {
            float childCorners[8];
            for (int k = 0; k < 8; ++k) childCorners[k] = split.v[brickPoint(c, k)];
            makeLeaf(nodeIndex, childCorners);
        } else if (!(split.keep[c] == Keep::Copy && copyOld(nodeIndex, split.old[c]))) {
            subdivide(nodeIndex, co, half, childLevel, true, prefetched && split.keep[c] == Keep::No, split.old[c]);
        }
    }

    /// After the children (nodes first..first + 7, leaves from `leafMark` on): coalesce them,
    /// store them as a brick, or point the parent at them.
    void finishParent(uint32_t nodeIndex, uint32_t first, std::size_t leafMark, const Split& split) {
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

    /// A cell one level above the finest splits into finest leaves on its 27 half-grid values
    /// `v`: it becomes a brick of them, or one leaf on `corners` when they share a type other
    /// than Boundary outside the band. What subdividing the children and coalescing them gives,
    /// without making 8 leaves to drop them again.
    void finestChildren(uint32_t nodeIndex, const float* v, const float* corners, bool nearBand) {
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

    bool allLeaves(uint32_t first) const {
        for (int c = 0; c < 8; ++c)
            if (!node::isLeaf(mNodes[first + c])) return false;
        return true;
    }

    bool sameNonBoundaryLeaves(uint32_t first) const {
        const uint32_t w0 = mNodes[first];
        if (!node::isLeaf(w0) || node::leafType(w0) == CellType::Boundary) return false;
        for (int c = 1; c < 8; ++c) {
            const uint32_t w = mNodes[first + c];
            if (!node::isLeaf(w) || node::leafType(w) != node::leafType(w0)) return false;
        }
        return true;
    }

    const Domain& mDomain;
    CellRule mRule;
    const DistanceSource& mSource;
    bool mLatticeSource;  ///< ask it for lattice points (DistanceSource::answersLattice)
    glm::uvec3 mRegionMin, mRegionMax;
    const Tile* mOld = nullptr;
    uint32_t mSpan, mDim;
    uint32_t mGridStep[27];  ///< index(gridOffset(g)): the step to half-grid point g per unit of half
    std::unique_ptr<TileScratch> mScratch;
    std::vector<float>& mValues;
    std::vector<uint32_t>& mStamp;
    uint32_t& mCurrent;
    std::vector<uint32_t>& mNodes;
    std::vector<float>& mLeafCorners;
    std::vector<float>& mBrickValues;
    std::vector<uint32_t>& mLeafFrom;
    std::vector<uint32_t>& mBrickFrom;
    glm::uvec3 mBase{0};
    std::vector<BorderRecord>& mRecorded;
    /// Whether the tile's face samples go to its neighbours (build(): tiles in colour phases);
    /// a small run's tiles and parts evaluate their shared points themselves.
    bool mHandsOverBorder = false;
    uint64_t mEvaluations = 0;
};

/// One generation or regeneration run.
class Run {
public:
    Run(const Domain& d, const GenerationSettings& s, const DistanceSource& src, const Adf* base,
        glm::uvec3 regionMin, glm::uvec3 regionMax, util::ThreadPool* pool)
        : mDomain(d), mSettings(s), mRule(d, s, src), mSource(src),
          mBase(base), mRegionMin(regionMin), mRegionMax(regionMax), mPool(pool),
          mVersion(base ? base->version() + 1 : 1),
          mBuilder(base ? AdfBuilder(*base) : AdfBuilder(d, s)) {}

    AdfPtr execute(GenerationStats* stats) {
        visitUpper(glm::uvec3(0), 0);
        generateTiles();
        coalesceUpper();
        if (stats) {
            stats->samples = mEvaluations;
            stats->tilesGenerated = mJobs.size();
            stats->coarseTiles = mCoarseTiles;
            stats->cells = mCells;
        }
        return mBuilder.build(mVersion);
    }

private:
    /// A tile generator for this run's source, settings and region.
    TileGenerator generator() const { return TileGenerator(mDomain, mSettings, mSource, mRegionMin, mRegionMax); }

    float sample(glm::uvec3 p) {
        bool fresh;
        float* v = mUpperSamples.findOrInsert(packLattice(p), 0.0f, fresh);
        if (fresh) {
            const glm::dvec3 w = mDomain.latticeToWorld(p.x, p.y, p.z);
            *v = checkedDistance(mSource.distance(w), w);
            ++mEvaluations;
        }
        return *v;
    }

    bool overlapsRegion(glm::uvec3 o, uint32_t s) const {
        return o.x <= mRegionMax.x && o.y <= mRegionMax.y && o.z <= mRegionMax.z &&
               o.x + s >= mRegionMin.x && o.y + s >= mRegionMin.y && o.z + s >= mRegionMin.z;
    }
    /// True when the base snapshot has no cell of its own here (a coarser tile covers it).
    bool baseIsCoarser(glm::uvec3 o, int level) const {
        if (!mBase) return true;
        return mBase->tileAtSlot(o >> uint32_t(mDomain.tileSpan()))->level() < level;
    }

    void addTile(TilePtr t) {
        mCells += t->cellCount();
        mBuilder.setTile(std::move(t));
    }

    void visitUpper(glm::uvec3 o, int level) {
        const uint32_t s = mDomain.cellLattice(level);
        if (!overlapsRegion(o, s) && !baseIsCoarser(o, level)) return;  // keep the base's cells
        std::array<float, 8> corners;
        for (int c = 0; c < 8; ++c) corners[c] = sample(o + childOffset(c) * s);
        if (level == mDomain.tileLevel()) {
            const glm::uvec3 slot = o / mDomain.cellLattice(mDomain.tileLevel());
            mJobs.push_back({slot, corners, mBase ? mBase->tileAtSlot(slot) : nullptr});
            return;
        }
        const uint32_t half = s / 2;
        float v[27];
        v[kCentre] = sample(o + gridOffset(kCentre) * half);
        const CellRule::FirstLook look = mRule.firstLook(v[kCentre], level);
        // The same order as in tiles (centre first), so the set of sampled points does not
        // depend on where the tile level sits.
        if (!look.leaf)
            for (int g = 0; g < 27; ++g) v[g] = sample(o + gridOffset(g) * half);
        // (farFromSurface never holds here: the tile level is at least one above the finest.)
        if (look.leaf ||
            ((mRule.farFromSurface(v, level) || CellRule::error(v) <= look.threshold) && !mRule.hidesFeature(mSource, o, level))) {
            ++mCoarseTiles;
            addTile(makeSingleCellTile(level, o, corners.data(), mVersion, mDomain.finestCellSize()));
            return;
        }
        for (int c = 0; c < 8; ++c) visitUpper(o + childOffset(c) * half, level + 1);
        if (!look.nearBand) mCoalesceCandidates.push_back({o, level, corners});
    }

    void generateTiles() {
        if (mJobs.empty()) return;
        // A small run (a dab: a few tiles, often one per colour; a LOD's 2^3 tiles) would run its
        // colours one after another on one thread: generateSmall runs them all at once instead.
        const unsigned threads = mPool ? mPool->threadCount() : 1u;
        if (threads > 1 && mJobs.size() < 8u * threads) return generateSmall(threads);
        FlatKeyMap<uint32_t> jobOfSlot;
        jobOfSlot.reserve(mJobs.size());
        bool inserted;
        for (std::size_t j = 0; j < mJobs.size(); ++j) jobOfSlot.findOrInsert(packLattice(mJobs[j].slot), uint32_t(j), inserted);
        std::vector<BorderSamples> borders(mJobs.size());
        std::vector<TilePtr> tiles(mJobs.size());
        std::vector<int> colour(mJobs.size());
        std::array<std::vector<std::size_t>, 8> byColour;
        for (std::size_t j = 0; j < mJobs.size(); ++j) {
            const glm::uvec3 s = mJobs[j].slot;
            colour[j] = int((s.x & 1u) | ((s.y & 1u) << 1) | ((s.z & 1u) << 2));
            byColour[colour[j]].push_back(j);
        }
        // Colour by colour, but without a barrier between colours: tiles are handed out in colour
        // order, and a tile waits only for its neighbours of lower colours (already handed out,
        // so running or done: no cycle), not for the whole colour before it. A tile reads
        // exactly the borders it read with barriers, so the result and the evaluation count are
        // unchanged. With barriers, each of the 8 colours waited for its slowest tile: a LOD's
        // 64 tiles spent a fifth of their coarsening waiting (docs/PERFORMANCE.md).
        std::vector<std::size_t> order;
        order.reserve(mJobs.size());
        for (const auto& items : byColour) order.insert(order.end(), items.begin(), items.end());
        const std::unique_ptr<std::atomic<bool>[]> done(new std::atomic<bool>[mJobs.size()]);
        for (std::size_t j = 0; j < mJobs.size(); ++j) done[j].store(false, std::memory_order_relaxed);
        std::atomic<bool> failed{false};
        std::atomic<uint64_t> evaluations{0};
        util::parallelFor(mPool, order.size(), [&](std::size_t k) {
            const std::size_t j = order[k];
            const int c = colour[j];
            // Set even when this tile throws, after `failed`: a neighbour waiting for it then
            // stops instead of reading a border that was never filled.
            struct MarkDone {
                std::atomic<bool>& flag;
                ~MarkDone() { flag.store(true, std::memory_order_release); }
            } markDone{done[j]};
            std::array<const BorderSamples*, kNeighbours> neighbours{};
            const glm::ivec3 slot(mJobs[j].slot);
            for (int i = 0; i < kNeighbours; ++i) {
                const glm::ivec3 n = slot + kNeighbourOffsets[i];
                if (glm::any(glm::lessThan(n, glm::ivec3(0)))) continue;
                const uint32_t* job = jobOfSlot.find(packLattice(glm::uvec3(n)));
                if (!job || colour[*job] >= c) continue;
                while (!done[*job].load(std::memory_order_acquire)) std::this_thread::yield();
                neighbours[i] = &borders[*job];
            }
            if (failed.load(std::memory_order_relaxed)) return;  // the loop rethrows the first error
            try {
                TileGenerator g = generator();
                tiles[j] = g.build(mJobs[j], neighbours, borders[j], mVersion);
                evaluations.fetch_add(g.evaluations(), std::memory_order_relaxed);
            } catch (...) {
                failed.store(true, std::memory_order_relaxed);
                throw;
            }
        });
        mEvaluations += evaluations.load();
        for (auto& t : tiles) addTile(std::move(t));
    }

    /// A small generation or regeneration: every tile at once (no colours), each evaluating the
    /// border points it shares with a neighbour itself, and each from its root: the roots
    /// first, then the large tiles' 8 children as parts side by side with the other tiles, each
    /// tile's parts joined by the task finishing its last one. A dab's tiles are uneven (one
    /// usually holds most of the crater: 1-2.8 ms against under 0.5 ms for the rest), so whole
    /// tiles left the second thread idle. Parts evaluate the points they share again: the
    /// values are the same (the source is a function of the point), and the tiles come out as
    /// build() makes them (tested: the same bits on 1, 2 and 3 threads); only the evaluation
    /// count depends on the thread count.
    void generateSmall(unsigned threads) {
        using Split = TileGenerator::Split;
        using Part = TileGenerator::Part;
        const std::size_t n = mJobs.size();
        std::vector<TilePtr> tiles(n);
        std::vector<Split> splits(n);
        std::atomic<uint64_t> evaluations{0};
        util::parallelFor(mPool, n, [&](std::size_t j) {
            TileGenerator g = generator();
            tiles[j] = g.planRoot(mJobs[j], splits[j], mVersion);
            evaluations.fetch_add(g.evaluations(), std::memory_order_relaxed);
        });
        // What a child still to generate costs, about: the part of the region it covers, plus one
        // so that a child just outside the region (inside its margin) still weighs something. A
        // full generation's region covers every child: then a tile weighs in proportion to its
        // child count.
        const uint32_t half = mDomain.cellLattice(mDomain.tileLevel() + 1);
        auto childWork = [&](std::size_t j, int c) -> uint64_t {
            if (tiles[j] || splits[j].keep[c] != Keep::No) return 0;
            const glm::uvec3 lo = mJobs[j].slot * (2 * half) + childOffset(c) * half;
            const glm::uvec3 a = glm::max(lo, mRegionMin), b = glm::min(lo + half, mRegionMax);
            return 1 + (glm::all(glm::lessThan(a, b)) ? uint64_t(b.x - a.x) * (b.y - a.y) * (b.z - a.z) : 0);
        };
        std::vector<uint64_t> work(n, 0);
        uint64_t total = 0;
        for (std::size_t j = 0; j < n; ++j) {
            for (int c = 0; c < 8; ++c) work[j] += childWork(j, c);
            total += work[j];
        }
        // A tile goes in parts when it holds more than a share of that work: in a regeneration
        // (an edit's region, uneven: a dab's crater tile and its heavy neighbours) a quarter of
        // a thread's share (with half a share, a dab's threads idled a fifth longer, for 0.4 %
        // fewer samples); in a generation (spread over the domain, even: a LOD's 2^3 tiles) half
        // a thread's share, which keeps even tiles whole up to 4 threads. The others continue
        // from their roots whole, one task each, so their children share one scratch volume and
        // evaluate no point twice (a LOD's 2^3 even tiles took 31 % more samples in parts, and
        // 20 % more time).
        const uint64_t sharesPerThread = mBase ? 4 : 2;
        std::vector<std::size_t> split, whole;  // jobs whose root waits for its children
        for (std::size_t j = 0; j < n; ++j) {
            if (tiles[j]) continue;
            (sharesPerThread * work[j] * threads > total ? split : whole).push_back(j);
        }
        // Items heaviest first, parts and whole tiles alike: one handed out late kept a thread
        // busy alone after the other had run out of items (a dab's crater child; a dab's
        // heaviest whole tile, when whole tiles went last in index order: up to 1 ms of thread
        // time idle in a 2.4 ms dab).
        std::vector<Part> parts(8 * split.size());
        auto weight = [&](std::size_t i) {
            return i < parts.size() ? childWork(split[i / 8], int(i % 8)) : work[whole[i - parts.size()]];
        };
        // The task finishing a tile's last part joins them, while the other threads go on with
        // the items left: a loop of joins after all parts left one thread idle for as long as
        // the largest join took (a dab's crater tile: 0.1-0.25 ms of its 2.3).
        const std::unique_ptr<std::atomic<int>[]> partsLeft(new std::atomic<int>[split.size()]);
        for (std::size_t k = 0; k < split.size(); ++k) partsLeft[k].store(8, std::memory_order_relaxed);
        util::parallelForHeaviestFirst(mPool, parts.size() + whole.size(), weight, [&](std::size_t item) {
            if (item >= parts.size()) {
                const std::size_t j = whole[item - parts.size()];
                TileGenerator g = generator();
                tiles[j] = g.buildChildren(mJobs[j], splits[j], mVersion);
                evaluations.fetch_add(g.evaluations(), std::memory_order_relaxed);
                return;
            }
            const std::size_t k = item / 8, j = split[k];
            {
                TileGenerator g = generator();
                parts[item] = g.buildChild(mJobs[j], splits[j], int(item % 8));
                evaluations.fetch_add(g.evaluations(), std::memory_order_relaxed);
            }
            if (partsLeft[k].fetch_sub(1, std::memory_order_acq_rel) == 1) {
                TileGenerator g = generator();
                tiles[j] = g.join(mJobs[j], splits[j], &parts[8 * k], mVersion);
            }
        });
        mEvaluations += evaluations.load();
        for (auto& t : tiles) addTile(std::move(t));
    }

    void coalesceUpper() {
        // Candidates were recorded after their children (post-order), so walking forwards merges
        // children before their parents are looked at and merges cascade upwards.
        for (const Candidate& cand : mCoalesceCandidates) {
            const uint32_t half = mDomain.cellLattice(cand.level + 1);
            CellType first = CellType::Boundary;
            bool same = true;
            for (int c = 0; c < 8 && same; ++c) {
                const glm::uvec3 o = cand.origin + childOffset(c) * half;
                const Tile* t = mBuilder.tileAtSlot(o >> uint32_t(mDomain.tileSpan()));
                same = t->level() == cand.level + 1 && t->singleLeaf() &&
                       t->rootType() != CellType::Boundary && (c == 0 || t->rootType() == first);
                if (c == 0) first = t->rootType();
            }
            if (same) {
                ++mCoarseTiles;
                addTile(makeSingleCellTile(cand.level, cand.origin, cand.corners.data(), mVersion, mDomain.finestCellSize()));
            }
        }
    }

    struct Candidate {
        glm::uvec3 origin;
        int level;
        std::array<float, 8> corners;
    };

    const Domain& mDomain;
    const GenerationSettings& mSettings;
    CellRule mRule;
    const DistanceSource& mSource;
    const Adf* mBase;
    glm::uvec3 mRegionMin, mRegionMax;
    util::ThreadPool* mPool;
    uint64_t mVersion;
    AdfBuilder mBuilder;
    FlatKeyMap<float> mUpperSamples;
    std::vector<TileJob> mJobs;
    std::vector<Candidate> mCoalesceCandidates;
    uint64_t mEvaluations = 0, mCoarseTiles = 0, mCells = 0;
};

}  // namespace

AdfPtr generate(const DistanceSource& source, const Domain& domain, const GenerationSettings& settings,
                util::ThreadPool* pool, GenerationStats* stats) {
    if (!domain.valid()) throw std::invalid_argument("invalid ADF domain");
    if (!settings.valid()) throw std::invalid_argument("invalid generation settings");
    const uint32_t n = domain.latticeSize();
    Run run(domain, settings, source, nullptr, glm::uvec3(0), glm::uvec3(n), pool);
    return run.execute(stats);
}

AdfPtr regenerate(const Adf& base, const DistanceSource& source, const BoxWorld& regionWorld,
                  util::ThreadPool* pool, GenerationStats* stats) {
    const Domain& d = base.domain();
    const double n = double(d.latticeSize());
    auto toLattice = [&](const glm::dvec3& p, bool up) {
        glm::dvec3 u = (p - d.originWorld) / d.finestCellSize();
        u = up ? glm::ceil(u) : glm::floor(u);
        return glm::uvec3(glm::clamp(u, glm::dvec3(0.0), glm::dvec3(n)));
    };
    if (glm::any(glm::greaterThan(regionWorld.min, regionWorld.max)))
        throw std::invalid_argument("regeneration region is empty");
    Run run(d, base.settings(), source, &base, toLattice(regionWorld.min, false),
            toLattice(regionWorld.max, true), pool);
    return run.execute(stats);
}

}  // namespace kizamu::adf
