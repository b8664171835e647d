// SPDX-License-Identifier: Apache-2.0
/// @file generate_tile.h
/// @brief Generation inside one tile: the tile job, its scratch volume, the border samples it
/// hands to its neighbours, and TileGenerator.
///
/// A TileGenerator takes a tile job (its slot, its 8 corner samples from the upper pass, and in a
/// regeneration the base snapshot's tile there) and produces the tile: it subdivides the tile's
/// root depth first with the cell rule (generate_rule.h), evaluating each lattice point of the
/// tile at most once in a scratch volume, and stores the leaves and bricks it settles on. Its
/// phases live in their own files: the subdivision and sampling in generate_tile.cpp, the
/// exchange of border samples with neighbouring tiles in generate_border.cpp, and
/// regeneration's keep and copy checks in generate_keep.cpp. The run that schedules tiles is
/// generate.cpp.
/// Complexity: O(cells of the tile + lattice points evaluated). Threading: one TileGenerator per
/// task; tiles run in parallel, each on its own generator and scratch volume.
/// Internal to generation: namespace kizamu::adf::detail.
#pragma once

#include "adf/distance_source.h"
#include "adf/domain.h"
#include "adf/generate_rule.h"
#include "adf/tile.h"

#include <glm/vec3.hpp>

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <utility>
#include <vector>

namespace kizamu::adf::detail {

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

/// Samples a tile evaluated itself on its border, filed once under the face or edge they lie on
/// (named by the neighbour across it); read by the neighbours of higher colours, generated after it
/// (an edge neighbour reads its edge, a face neighbour its face and the 4 edges around it, see
/// kBorderLists). Points are packed local coordinates. One array grouped by face and edge,
/// filled once when the tile is done, rather than 18 growing lists: a small tile (a LOD's) would
/// spend most of its allocations on them.
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

/// What a regenerated cell keeps of the old tile (TileGenerator::keepsOld).
enum class Keep : uint8_t { No, Copy, Leaf };

/// Generates one tile; lives for one tile, borrowing a scratch volume from the pool.
class TileGenerator {
public:
    /// `regionMin`/`regionMax`: the lattice box being regenerated; cells of a job's old tile that
    /// lie outside it are copied rather than generated.
    TileGenerator(const Domain& d, const GenerationSettings& s, const DistanceSource& src, glm::uvec3 regionMin,
                  glm::uvec3 regionMax);
    ~TileGenerator();
    TileGenerator(const TileGenerator&) = delete;
    TileGenerator& operator=(const TileGenerator&) = delete;

    /// Builds the tile for `job`; reads its neighbours' border samples, writes its own to `border`.
    TilePtr build(const TileJob& job, const std::array<const BorderSamples*, kNeighbours>& neighbours,
                  BorderSamples& border, uint64_t version);

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
    TilePtr planRoot(const TileJob& job, Split& split, uint64_t version);

    /// Child `c` of the tile root that `split` describes.
    Part buildChild(const TileJob& job, const Split& split, int c);

    /// The tile from the root's `split`, its children generated here one after another (what
    /// build() does after the root's decision).
    TilePtr buildChildren(const TileJob& job, const Split& split, uint64_t version);

    /// The tile from the root's `split` and its 8 children's parts.
    TilePtr join(const TileJob& job, const Split& split, const Part* parts, uint64_t version);

    uint64_t evaluations() const { return mEvaluations; }

private:
    // ---- the tile's frame and scratch volume (generate_tile.cpp) ----

    /// Starts a tile: a fresh stamp, the job's old tile and corners, empty arrays.
    void begin(const TileJob& job);
    /// Starts a tile below its root: the root's 27 samples, taken by planRoot, are valid again.
    void beginBelowRoot(const TileJob& job, const Split& split);
    TilePtr finish(uint64_t version) const;

    uint32_t index(glm::uvec3 p) const { return (p.z * mDim + p.y) * mDim + p.x; }
    bool valid(uint32_t i) const { return mStamp[i] == mCurrent; }
    void set(uint32_t i, float v) {
        mValues[i] = v;
        mStamp[i] = mCurrent;
    }

    // ---- the border exchange between tiles (generate_border.cpp) ----

    /// Copies the samples neighbour `n` (the `neighbour`-th offset from us) evaluated on our
    /// shared border.
    void importFrom(const BorderSamples& n, int neighbour);

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
    void groupBorder(BorderSamples& border) const;

    // ---- sampling (generate_tile.cpp) ----

    /// Makes the half-grid points `gs` of the cell at `o` (half size `half`) valid, evaluating
    /// the missing ones in one batch, and loads them into v. Indices by table (mGridStep): a
    /// cell's points are nearly all valid already (prefetchChildren), so finding them is the
    /// common cost, and a table step per point is cheaper than working out its coordinates
    /// (docs/decisions/0014-generation-flat-map-and-scratch.md). `prefetched`: they are all
    /// valid (the parent's prefetchChildren took them), so they are only loaded.
    void ensure(glm::uvec3 o, uint32_t half, const int* gs, int n, float* v, bool prefetched);

    /// Evaluates, in two large batches, what the 8 children of a cell will ask for first: their
    /// centres, then the face and edge centres of those the centre does not settle. The set of
    /// evaluated points is the one the children would evaluate one by one (each child still
    /// looks at its centre first), but a source call covers up to 144 points instead of 1 or
    /// 18, which spreads a CSG tree's per-call cost over many more points.
    /// Children that will be copied from the old tile (`keep`) need no samples (if the copy
    /// turns out impossible, subdivide evaluates them itself: only the batching differs).
    void prefetchChildren(glm::uvec3 o, uint32_t childSize, int childLevel, const Keep* keep);

    /// Evaluates the listed local points that are not valid yet (duplicates allowed), in
    /// batches of up to 64.
    void evaluate(const glm::uvec3* local, int n);

    /// evaluate() asking the source at lattice points (Point = glm::uvec3) or at their world
    /// positions (glm::dvec3).
    template <class Point>
    void evaluateAt(const glm::uvec3* local, int n);

    // ---- the tile's arrays ----

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

    // ---- regeneration: what a cell keeps of the old tile (generate_keep.cpp) ----

    /// True when the cell is clear of the region by half its size: then its circumscribed ball
    /// (radius 0.87 s about its centre: what featureSize is asked about, and it holds every
    /// sub-cell's ball) misses the region, so a full generation would decide for it as the base
    /// did, and copying it changes nothing.
    bool outsideRegion(glm::uvec3 o, uint32_t s) const;

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
    /// `cell`: where the old tile holds it. Inline for the common answer: no old tile.
    Keep keepsOld(glm::uvec3 o, uint32_t s, int level, const OldCell& cell) const {
        if (!mOld) return Keep::No;
        return keepsOldFrom(o, s, level, cell);
    }
    /// keepsOld where there is an old tile.
    Keep keepsOldFrom(glm::uvec3 o, uint32_t s, int level, const OldCell& cell) const;

    /// Whether every value the old tile stores for the cell at `o` (its subtree, or the coarser
    /// leaf holding it) lies in `range`: then so does the old field over the cell, which is
    /// trilinear between them. Says which way the cell can be kept.
    Keep oldValuesWithin(const OldCell& cell, const DistanceSource::Range& range) const;

    /// Sub-tile regeneration: a cell outside the region keeps the old tile's cells there, when
    /// the old tile has this cell (or it is one of an old brick's children). The source equals
    /// the old field outside the region, so generating would only re-derive them, at the cost
    /// of every sample; copying also keeps their structure exactly. False: generate it.
    bool copyOld(uint32_t nodeIndex, const OldCell& cell);
    void copySubtree(uint32_t nodeIndex, uint32_t w);

    // ---- subdivision (generate_tile.cpp) ----

    /// `keepChecked`: the parent already asked keepsOld for this cell (and was told no, or
    /// the copy failed). `prefetched`: the parent's prefetchChildren evaluated what this cell
    /// looks at (decide then only loads it).
    /// `old`: where the old tile holds the cell (its parent's Split::old; oldRoot at the root).
    void subdivide(uint32_t nodeIndex, glm::uvec3 o, uint32_t s, int level, bool keepChecked, bool prefetched,
                   const OldCell& old);

    /// The children of the cell at `o` (node `nodeIndex`) that `split` describes, appended as
    /// the next 8 nodes with their subtrees, then the cell finished (finishParent).
    void children(uint32_t nodeIndex, glm::uvec3 o, uint32_t s, int level, const Split& split);

    /// The cell's own decision: true when settled (node `nodeIndex` written), else `split` says
    /// what its children need.
    bool decide(uint32_t nodeIndex, glm::uvec3 o, uint32_t s, int level, bool keepChecked, bool prefetched, const OldCell& old,
                Split& split);

    /// Child `c` (at node `nodeIndex`, size `half`) of the cell at `o`, as `split` says;
    /// `prefetched`: prefetchChildren ran for the children.
    void child(uint32_t nodeIndex, glm::uvec3 o, uint32_t half, int childLevel, int c, const Split& split, bool prefetched);

    /// After the children (nodes first..first + 7, leaves from `leafMark` on): coalesce them,
    /// store them as a brick, or point the parent at them.
    void finishParent(uint32_t nodeIndex, uint32_t first, std::size_t leafMark, const Split& split);

    /// A cell one level above the finest splits into finest leaves on its 27 half-grid values
    /// `v`: it becomes a brick of them, or one leaf on `corners` when they share a type other
    /// than Boundary outside the band. What subdividing the children and coalescing them gives,
    /// without making 8 leaves to drop them again.
    void finestChildren(uint32_t nodeIndex, const float* v, const float* corners, bool nearBand);

    bool allLeaves(uint32_t first) const;
    bool sameNonBoundaryLeaves(uint32_t first) const;

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

}  // namespace kizamu::adf::detail
