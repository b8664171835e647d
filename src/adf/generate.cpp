// SPDX-License-Identifier: Apache-2.0
/// @file generate.cpp
/// @brief A generation or regeneration run: the upper pass above the tile level, the tiles
/// scheduled on the pool, and the coalescing of the upper cells.
///
/// Takes a distance source, the domain and settings (and for a regeneration the base snapshot
/// and the lattice box of the edited region) and produces the new snapshot. The upper pass
/// subdivides from the domain's root down to the tile level with the cell rule, caching its
/// samples by lattice point; each cell reaching the tile level becomes a tile job. The jobs run
/// on the pool in 8 colours (generateTiles: each tile after its neighbours of lower colours, so
/// border samples are handed over without a race) or, for a small run, all at once with the
/// large tiles in parts (generateSmall). Upper cells whose 8 children came out as single leaves
/// of one type then coalesce, children before parents.
/// Complexity: O(upper cells + tiles' cells and samples). Threading: the upper pass and the
/// coalescing run on the caller's thread; tiles run in parallel on `pool` (any order: each
/// tile's bytes depend only on its job and the border samples it reads, which the colours fix).
#include "adf/generate.h"

#include "adf/generate_rule.h"
#include "adf/generate_tile.h"
#include "adf/lattice.h"
#include "util/flat_map.h"
#include "util/thread_pool.h"

#include <glm/common.hpp>

#include <algorithm>
#include <array>
#include <atomic>
#include <cassert>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <thread>
#include <utility>
#include <vector>

namespace kizamu::adf {

namespace {

using namespace detail;

TilePtr makeSingleCellTile(int level, glm::uvec3 origin, const float* corners, uint64_t version, double finestCell) {
    const CellType t = cellTypeOf(std::span<const float, 8>(corners, 8));
    const uint32_t nodeWord = node::makeLeaf(0, t);
    return Tile::create(level, origin, {&nodeWord, 1}, {corners, 8}, {}, version, finestCell);
}

/// One generation or regeneration run.
class Run {
public:
    Run(const Domain& d, const GenerationSettings& s, const DistanceSource& src, const Adf* base,
        glm::uvec3 regionMin, glm::uvec3 regionMax, util::ThreadPool* pool,
        GenerationProgress* progress)
        : mDomain(d), mSettings(s), mRule(d, s, src), mSource(src),
          mBase(base), mRegionMin(regionMin), mRegionMax(regionMax), mPool(pool),
          mProgress(progress),
          mVersion(base ? base->version() + 1 : 1),
          mBuilder(base ? AdfBuilder(*base) : AdfBuilder(d, s)) {}

    AdfPtr execute(GenerationStats* stats) {
        visitUpper(glm::uvec3(0), 0);
        if (mProgress) mProgress->tilesTotal.store(mJobs.size(), std::memory_order_relaxed);
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
        const auto [v, fresh] = mUpperSamples.tryInsert(packLattice(p), 0.0f);
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

    /// One more tile built (any thread).
    void countTile() {
        if (mProgress) mProgress->tilesDone.fetch_add(1, std::memory_order_relaxed);
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
        util::FlatMap64 jobOfSlot;
        jobOfSlot.reserve(mJobs.size());
        for (std::size_t j = 0; j < mJobs.size(); ++j) jobOfSlot.assign(packLattice(mJobs[j].slot), uint32_t(j));
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
        // exactly the borders it would read with a barrier per colour, so the result and the
        // evaluation count are the same; a barrier would make each of the 8 colours wait for
        // its slowest tile (docs/decisions/0016-generation-colours-without-barriers.md).
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
                countTile();
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
    /// usually holds most of the crater), so whole tiles would leave the other threads idle
    /// (docs/decisions/0017-small-runs-in-parts.md). Parts evaluate the points they share again: the
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
            if (tiles[j]) countTile();
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
        // a thread's share; in a generation (spread over the domain, even: a LOD's 2^3 tiles)
        // half a thread's share, which keeps even tiles whole up to 4 threads. The others
        // continue from their roots whole, one task each, so their children share one scratch
        // volume and evaluate no point twice; even tiles in parts would evaluate their shared
        // points again for no gain in balance (docs/decisions/0017-small-runs-in-parts.md).
        const uint64_t sharesPerThread = mBase ? 4 : 2;
        std::vector<std::size_t> split, whole;  // jobs whose root waits for its children
        for (std::size_t j = 0; j < n; ++j) {
            if (tiles[j]) continue;
            (sharesPerThread * work[j] * threads > total ? split : whole).push_back(j);
        }
        // Items heaviest first, parts and whole tiles alike: a heavy one handed out late (a dab's
        // crater child, or its heaviest whole tile) would keep a thread busy alone after the
        // others ran out of items (docs/decisions/0021-heaviest-first-scheduling.md).
        std::vector<Part> parts(8 * split.size());
        auto weight = [&](std::size_t i) {
            return i < parts.size() ? childWork(split[i / 8], int(i % 8)) : work[whole[i - parts.size()]];
        };
        // The task finishing a tile's last part joins them, while the other threads go on with
        // the items left: a loop of joins after all parts would leave the other threads idle for
        // as long as the largest join takes.
        const std::unique_ptr<std::atomic<int>[]> partsLeft(new std::atomic<int>[split.size()]);
        for (std::size_t k = 0; k < split.size(); ++k) partsLeft[k].store(8, std::memory_order_relaxed);
        util::parallelForHeaviestFirst(mPool, parts.size() + whole.size(), weight, [&](std::size_t item) {
            if (item >= parts.size()) {
                const std::size_t j = whole[item - parts.size()];
                TileGenerator g = generator();
                tiles[j] = g.buildChildren(mJobs[j], splits[j], mVersion);
                evaluations.fetch_add(g.evaluations(), std::memory_order_relaxed);
                countTile();
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
                countTile();
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
    GenerationProgress* mProgress;  ///< null: not reported
    uint64_t mVersion;
    AdfBuilder mBuilder;
    util::FlatMap<float> mUpperSamples;  ///< the upper pass's samples by packed lattice point
    std::vector<TileJob> mJobs;
    std::vector<Candidate> mCoalesceCandidates;
    uint64_t mEvaluations = 0, mCoarseTiles = 0, mCells = 0;
};

}  // namespace

AdfPtr generate(const DistanceSource& source, const Domain& domain,
                const GenerationSettings& settings, util::ThreadPool* pool, GenerationStats* stats,
                GenerationProgress* progress) {
    if (!domain.valid()) throw std::invalid_argument("invalid ADF domain");
    if (!settings.valid()) throw std::invalid_argument("invalid generation settings");
    const uint32_t n = domain.latticeSize();
    Run run(domain, settings, source, nullptr, glm::uvec3(0), glm::uvec3(n), pool, progress);
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
            toLattice(regionWorld.max, true), pool, nullptr);
    return run.execute(stats);
}

}  // namespace kizamu::adf
