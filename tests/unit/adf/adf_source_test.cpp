// SPDX-License-Identifier: Apache-2.0
// AdfSource: a snapshot read as a distance source answers, at every lattice point, the stored
// corner of the first leaf (octant order) that has the point as a corner, and elsewhere the
// trilinear field of the leaf holding the point, whether it answers point by point or from a
// block it filled at once; its per-thread caches never let one source's leaves answer for
// another's. The reference below maps every finest cube to its leaf by walking all tiles,
// sharing no lookup code with the source.
#include "adf/adf_source.h"
#include "adf/generate.h"

#include <gtest/gtest.h>

#include <random>
#include <vector>

using namespace kizamu;
using namespace kizamu::adf;

namespace {

Domain smallDomain(int maxLevel = 5, int tileSpanLevels = 3) {
    Domain d;
    d.originWorld = glm::dvec3(-0.5);
    d.maxLevel = maxLevel;
    d.tileSpanLevels = tileSpanLevels;
    return d;
}

/// A box with a ball bitten out of one corner and a ball on top: leaves of every size, bricks
/// and lone leaves, and tiles of several depths side by side.
AdfPtr makeShape(double ballRadius, const Domain& domain = smallDomain()) {
    const SourcePtr box = makeBox(glm::dvec3(0.27, 0.22, 0.19));
    const SourcePtr bite = makeTranslated(makeSphere(ballRadius), glm::dvec3(0.25, 0.2, 0.2));
    const SourcePtr top = makeTranslated(makeSphere(0.13), glm::dvec3(-0.05, 0.0, 0.2));
    GenerationSettings s;
    s.bandCells = 3.0;
    return generate(*makeCsg(CsgOp::Union, makeCsg(CsgOp::Difference, box, bite), top), domain, s);
}

/// Every finest cube's leaf, by walking all tiles.
class CubeLeaves {
public:
    explicit CubeLeaves(const Adf& adf) : mTop(adf.domain().latticeSize()), mLeaves(std::size_t(mTop) * mTop * mTop) {
        adf.forEachTile([&](const Tile& t) {
            forEachLeaf(t, adf.domain().maxLevel, [&](const LeafRef& r) {
                for (uint32_t z = 0; z < r.latticeSize; ++z)
                    for (uint32_t y = 0; y < r.latticeSize; ++y)
                        for (uint32_t x = 0; x < r.latticeSize; ++x) at(r.latticeOrigin + glm::uvec3(x, y, z)) = r;
            });
        });
    }
    /// The field AdfSource must answer at lattice point p.
    float expected(glm::uvec3 p) const {
        for (uint32_t o = 0; o < 8; ++o) {
            const glm::uvec3 off(o & 1, (o >> 1) & 1, o >> 2);
            if (glm::any(glm::lessThan(p, off))) continue;
            const glm::uvec3 cube = p - off;
            if (glm::any(glm::greaterThanEqual(cube, glm::uvec3(mTop)))) continue;
            const LeafRef& r = at(cube);
            const glm::uvec3 rel = p - r.latticeOrigin;
            int corner = 0;
            bool isCorner = true;
            for (int k = 0; k < 3; ++k) {
                if (rel[k] == r.latticeSize) corner |= 1 << k;
                else if (rel[k] != 0) isCorner = false;
            }
            if (isCorner) return r.corners[corner];
        }
        const LeafRef& r = at(p);  // a corner of no leaf: inside the leaf holding it
        return trilinear(r.corners, (glm::vec3(p) - glm::vec3(r.latticeOrigin)) / float(r.latticeSize)).distance;
    }
    uint32_t top() const { return mTop; }

private:
    LeafRef& at(glm::uvec3 c) { return mLeaves[(std::size_t(c.z) * mTop + c.y) * mTop + c.x]; }
    const LeafRef& at(glm::uvec3 c) const { return mLeaves[(std::size_t(c.z) * mTop + c.y) * mTop + c.x]; }
    uint32_t mTop;
    std::vector<LeafRef> mLeaves;
};

}  // namespace

class AdfSourceAtEveryPoint : public ::testing::TestWithParam<std::pair<int, int>> {};

TEST_P(AdfSourceAtEveryPoint, AnswersTheFirstStoredCornerOrTheHoldingLeaf) {
    // Tiles of 4, 8 and 16 cells against the source's blocks of 8^3 points: blocks that span
    // several tiles, one tile, or half of one, each reading the leaves of the tiles below it;
    // and a domain 4 cells across, smaller than one block.
    const AdfPtr adf = makeShape(0.12, smallDomain(GetParam().first, GetParam().second));
    const CubeLeaves ref(*adf);
    const Domain& d = adf->domain();
    // Interior points only (the upper domain faces take the clamped Adf::sample path), in
    // batches along x as the generator asks, and one at a time in reverse.
    std::vector<glm::dvec3> row(ref.top());
    std::vector<double> out(ref.top());
    auto inBatches = [&](const SourcePtr& src) {
        int mismatches = 0;
        for (uint32_t z = 0; z < ref.top(); ++z)
            for (uint32_t y = 0; y < ref.top(); ++y) {
                for (uint32_t x = 0; x < ref.top(); ++x) row[x] = d.latticeToWorld(x, y, z);
                src->distances(row, out);
                for (uint32_t x = 0; x < ref.top(); ++x) mismatches += out[x] != double(ref.expected({x, y, z}));
            }
        return mismatches;
    };
    auto inReverse = [&](const SourcePtr& src) {
        int mismatches = 0;
        for (uint32_t z = ref.top(); z-- > 0;)
            for (uint32_t y = ref.top(); y-- > 0;)
                for (uint32_t x = ref.top(); x-- > 0;)
                    mismatches += src->distance(d.latticeToWorld(x, y, z)) != double(ref.expected({x, y, z}));
        return mismatches;
    };
    // A fresh source answers a block's first points one by one and fills it once they are
    // many; asked again, every point comes from a filled block.
    const SourcePtr src = makeAdfSource(adf);
    EXPECT_EQ(inBatches(src), 0);
    EXPECT_EQ(inReverse(src), 0);
    EXPECT_EQ(inReverse(makeAdfSource(adf)), 0);
    // At lattice points (how an edit's generation asks): the same values, and on the upper
    // domain faces what the world positions give.
    const SourcePtr byLattice = makeAdfSource(adf);
    ASSERT_TRUE(byLattice->answersLattice(d));
    std::vector<glm::uvec3> lattice(ref.top() + 1);
    std::vector<double> values(lattice.size());
    int latticeMismatches = 0;
    for (uint32_t z = 0; z <= ref.top(); ++z)
        for (uint32_t y = 0; y <= ref.top(); ++y) {
            for (uint32_t x = 0; x <= ref.top(); ++x) lattice[x] = {x, y, z};
            byLattice->latticeDistances(d, lattice, values);
            for (uint32_t x = 0; x <= ref.top(); ++x)
                latticeMismatches += values[x] != (x < ref.top() && y < ref.top() && z < ref.top()
                                                       ? double(ref.expected({x, y, z}))
                                                       : makeAdfSource(adf)->distance(d.latticeToWorld(x, y, z)));
        }
    EXPECT_EQ(latticeMismatches, 0);
    // Asked once per block, from a fresh source each time: every point point by point.
    int pointByPoint = 0;
    for (uint32_t z = 0; z < ref.top(); ++z)
        for (uint32_t y = 0; y < ref.top(); ++y)
            for (uint32_t x = 0; x < ref.top(); ++x)
                if (((x | y | z) & 7u) == 3u)
                    pointByPoint += makeAdfSource(adf)->distance(d.latticeToWorld(x, y, z)) != double(ref.expected({x, y, z}));
    EXPECT_EQ(pointByPoint, 0);
}

INSTANTIATE_TEST_SUITE_P(TileSpans, AdfSourceAtEveryPoint,
                         ::testing::Values(std::pair{5, 3}, std::pair{5, 2}, std::pair{6, 4}, std::pair{2, 6}));

TEST(AdfSource, OffTheLatticeItIsTheSnapshotsOwnField) {
    const AdfPtr adf = makeShape(0.12);
    const SourcePtr src = makeAdfSource(adf);
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(-0.49, 0.49);
    for (int i = 0; i < 20000; ++i) {
        const glm::dvec3 p(u(rng), u(rng), u(rng));
        ASSERT_EQ(src->distance(p), double(adf->sample(glm::vec3(p)).distance)) << i;
    }
}

TEST(AdfSource, RegionLimitedAtLatticePointsAnswersWhatItAnswersAtTheirWorldPositions) {
    const AdfPtr a = makeShape(0.12), b = makeShape(0.2);
    const Domain& d = a->domain();
    const BoxWorld region{glm::dvec3(-0.2, -0.1, 0.0), glm::dvec3(0.25, 0.3, 0.31)};
    const SourcePtr limited = makeRegionLimited(makeAdfSource(a), makeAdfSource(b), region);
    ASSERT_TRUE(limited->answersLattice(d));
    EXPECT_FALSE(makeRegionLimited(makeAdfSource(a), makeSphere(0.1), region)->answersLattice(d))
        << "a side that does not answer lattice points makes the whole answer world positions";
    const uint32_t top = d.latticeSize();
    std::vector<glm::uvec3> lattice;
    std::vector<glm::dvec3> world;
    for (uint32_t z = 0; z <= top; ++z)
        for (uint32_t y = 0; y <= top; ++y)
            for (uint32_t x = 0; x <= top; ++x) {
                lattice.push_back({x, y, z});
                world.push_back(d.latticeToWorld(x, y, z));
            }
    std::vector<double> byLattice(lattice.size()), byWorld(lattice.size());
    limited->distances(world, byWorld);
    // In runs of 5 along x (batches wholly inside, wholly outside and mixed), of a row, and
    // all at once.
    int mismatches = 0;
    for (const std::size_t run : {std::size_t(5), std::size_t(top + 1)}) {
        for (std::size_t first = 0; first < lattice.size(); first += run) {
            const std::size_t n = std::min(run, lattice.size() - first);
            limited->latticeDistances(d, std::span(lattice).subspan(first, n), std::span(byLattice).subspan(first, n));
        }
        for (std::size_t i = 0; i < lattice.size(); ++i) mismatches += byLattice[i] != byWorld[i];
    }
    EXPECT_EQ(mismatches, 0);
    limited->latticeDistances(d, lattice, byLattice);
    for (std::size_t i = 0; i < lattice.size(); ++i) mismatches += byLattice[i] != byWorld[i];
    EXPECT_EQ(mismatches, 0);
}

TEST(AdfSource, SourcesSharingAThreadNeverAnswerForEachOther) {
    // Two snapshots of different shapes, asked alternately on one thread, then a third
    // source made after one is gone: each answers its own field at every point.
    const AdfPtr a = makeShape(0.12), b = makeShape(0.2);
    const CubeLeaves refA(*a), refB(*b);
    const Domain& d = a->domain();
    int differing = 0, mismatches = 0;
    auto check = [&](const SourcePtr& src, const CubeLeaves& ref, glm::uvec3 p) {
        mismatches += src->distance(d.latticeToWorld(p.x, p.y, p.z)) != double(ref.expected(p));
    };
    SourcePtr srcA = makeAdfSource(a);
    const SourcePtr srcB = makeAdfSource(b);
    for (uint32_t z = 0; z < refA.top(); ++z)
        for (uint32_t y = 0; y < refA.top(); ++y)
            for (uint32_t x = 0; x < refA.top(); ++x) {
                differing += refA.expected({x, y, z}) != refB.expected({x, y, z});
                check(srcA, refA, {x, y, z});
                check(srcB, refB, {x, y, z});
            }
    srcA.reset();
    const SourcePtr again = makeAdfSource(b);
    for (uint32_t z = 0; z < refB.top(); ++z)
        for (uint32_t y = 0; y < refB.top(); ++y)
            for (uint32_t x = 0; x < refB.top(); ++x) check(again, refB, {x, y, z});
    EXPECT_GT(differing, 1000);  // the shapes really differ
    EXPECT_EQ(mismatches, 0);
}
