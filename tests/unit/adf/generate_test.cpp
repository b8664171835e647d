// SPDX-License-Identifier: Apache-2.0
// Generation: accuracy against the analytic field within Bremer's bound, gradients, determinism,
// the compute-once evaluation count, coalescing, and local regeneration == full generation.
#include "adf/adf_source.h"
#include "adf/generate.h"

#include "adf/test_part.h"
#include "tests/support/surface_points.h"
#include "tests/util/adf_compare.h"
#include "util/thread_pool.h"

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>
#define GLM_ENABLE_EXPERIMENTAL
#include <glm/gtx/string_cast.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <limits>
#include <random>
#include <string>

using namespace kizamu;
using namespace kizamu::adf;

namespace {

Domain unitDomain(int level, int span = 5) {
    Domain d;
    d.originWorld = glm::dvec3(-0.5);
    d.maxLevel = level;
    d.tileSpanLevels = span;
    return d;
}

struct ErrorReport {
    double worstRatio = 0.0;  ///< max |adf - source| / ε̂(d) away from creases
    int checked = 0;
};

/// Random points within the band around the surface, away from creases.
ErrorReport checkBand(const Adf& adf, const DistanceSource& src, uint64_t seed, int count) {
    const Domain& d = adf.domain();
    const double h = d.finestCellSize();
    const ErrorBound bound = adf.settings().errorBound(d);
    const double band = adf.settings().bandWorld(d);
    const BoxWorld box{d.originWorld + glm::dvec3(2 * h), d.originWorld + glm::dvec3(d.sizeWorld - 2 * h)};
    const auto surface = randomSurfacePoints(src, box, std::size_t(count), seed, h * 0.25);
    std::mt19937_64 rng(seed + 1);
    std::uniform_real_distribution<double> offset(-band, band);
    ErrorReport r;
    for (const auto& s : surface) {
        const glm::dvec3 n = glm::normalize(sourceGradient(src, s, h * 0.25));
        const glm::dvec3 p = s + n * offset(rng);
        const double exact = src.distance(p);
        if (std::abs(exact) > band || nearCrease(src, p, 2.0 * h)) continue;
        const double err = std::abs(double(adf.distance(glm::vec3(p))) - exact);
        const double ratio = err / bound(exact);
        if (ratio > r.worstRatio) r.worstRatio = ratio;
        ++r.checked;
        if (ratio > 1.0) {
 const LeafRef leaf = adf.findLeaf(glm::uvec3((glm::vec3(p) - adf.originWorldF()) * adf.latticePerMetre()));
            ADD_FAILURE() << "error " << err / h << " cells in a leaf of level " << leaf.level << " at " << p.x << "," << p.y << "," << p.z
                          << " (d = " << exact / h << " cells, bound " << bound(exact) / h << ", seed " << seed << ")";
            return r;
        }
    }
    return r;
}

struct NamedSource {
    const char* name;
    SourcePtr source;
};

std::vector<NamedSource> primitives() {
    const glm::dquat tilt = glm::angleAxis(0.4, glm::normalize(glm::dvec3(1, 2, 3)));
    return {
        {"sphere", makeSphere(0.3)},
        {"box", makeTransformed(makeBox({0.25, 0.15, 0.2}), {0.01, -0.02, 0.03}, tilt)},
        {"rounded_box", makeTransformed(makeRoundedBox({0.25, 0.2, 0.15}, 0.06), {0, 0, 0}, tilt)},
        {"capsule", makeCapsule({-0.2, -0.1, 0.0}, {0.2, 0.15, 0.05}, 0.12)},
        {"cylinder", makeTransformed(makeCylinder(0.15, 0.25), {0, 0, 0}, tilt)},
        {"torus", makeTransformed(makeTorus(0.25, 0.08), {0, 0, 0}, tilt)},
        {"half_space", makeHalfSpace({0.2, 0.3, 1.0}, 0.05)},
    };
}

TEST(Trilinear, ThePackedFormGivesTheSameBits) {
    // Random corners (both signs, magnitudes across the float range a tile uses, exact zeros)
    // and points of the cell, its corners and edges included.
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> value(-1.0f, 1.0f), at(0.0f, 1.0f);
    std::uniform_int_distribution<int> exponent(-30, 2), pick(0, 9);
    for (int i = 0; i < 200000; ++i) {
        float v[8];
        for (float& c : v) c = pick(rng) == 0 ? 0.0f : std::ldexp(value(rng), exponent(rng));
        glm::vec3 f(at(rng), at(rng), at(rng));
        for (int k = 0; k < 3; ++k)
            if (pick(rng) < 2) f[k] = float(pick(rng) & 1);
        const Sample a = trilinear(v, f), b = trilinearPacked(v, f);
        ASSERT_EQ(std::bit_cast<uint32_t>(a.distance), std::bit_cast<uint32_t>(b.distance)) << i;
        for (int k = 0; k < 3; ++k)
            ASSERT_EQ(std::bit_cast<uint32_t>(a.gradient[k]), std::bit_cast<uint32_t>(b.gradient[k])) << i << " axis " << k;
    }
}

TEST(Generate, EveryPrimitiveIsWithinTheAdaptiveBoundInTheBand) {
    util::ThreadPool pool(2);
    for (const auto& [name, src] : primitives()) {
        SCOPED_TRACE(name);
        const Domain d = unitDomain(7, 4);
        GenerationStats stats;
        const AdfPtr adf = generate(*src, d, GenerationSettings{}, &pool, &stats);
        EXPECT_GT(stats.cells, 0u);
        const ErrorReport r = checkBand(*adf, *src, 11, 5000);  // the box keeps ~30 % off its creases
        EXPECT_GT(r.checked, 1000) << "too few points away from creases";
    }
}

TEST(Generate, CsgTreesAreWithinTheBoundNearTheSurface) {
    util::ThreadPool pool(2);
    const Domain d = testPartDomain(8);
    const SourcePtr part = makeTestPart(d);
    const AdfPtr adf = generate(*part, d, testPartSettings(), &pool);
    const ErrorReport r = checkBand(*adf, *part, 5, 4000);
    EXPECT_GT(r.checked, 2000);
    // A smooth-blended tree too.
    const SourcePtr blended = makeCsg(CsgOp::Union, makeSphere(0.2),
                                      makeTranslated(makeBox({0.1, 0.1, 0.3}), {0.2, 0, 0}), 0.05);
    const Domain d2 = unitDomain(8);
    const ErrorReport r2 = checkBand(*generate(*blended, d2, GenerationSettings{}, &pool), *blended, 9, 3000);
    EXPECT_GT(r2.checked, 1000);
    // Shallow and sharp edges (the gradient turns 40° and 140°), whose medial sheets distance
    // grading leaves in cells two finest cells wide.
    for (double turn : {40.0, 140.0}) {
        SCOPED_TRACE(turn);
        const double a = glm::radians(0.5 * turn);
        const SourcePtr wedge = makeCsg(CsgOp::Intersection, makeHalfSpace({std::sin(a), 0.0, std::cos(a)}, 0.05),
                                        makeHalfSpace({-std::sin(a), 0.1, std::cos(a)}, 0.05));
        const ErrorReport r3 = checkBand(*generate(*wedge, d2, GenerationSettings{}, &pool), *wedge, 13, 3000);
        EXPECT_GT(r3.checked, 1000);
    }
}

TEST(Generate, GradientMatchesTheSourceAwayFromCreases) {
    const Domain d = unitDomain(8);
    const SourcePtr src = makeTransformed(makeTorus(0.25, 0.1), {0, 0, 0}, glm::angleAxis(0.5, glm::dvec3(1, 0, 0)));
    const AdfPtr adf = generate(*src, d, GenerationSettings{});
    const double h = d.finestCellSize();
    const auto pts = randomSurfacePoints(*src, {glm::dvec3(-0.45), glm::dvec3(0.45)}, 2000, 3, h * 0.25);
    std::mt19937_64 rng(4);
    std::uniform_real_distribution<double> off(-4 * h, 4 * h);
    AdfAccessor acc(*adf);
    std::vector<double> errors;
    for (const auto& s : pts) {
        const glm::dvec3 n = glm::normalize(sourceGradient(*src, s, h * 0.25));
        const glm::dvec3 p = s + n * off(rng);
        const glm::dvec3 exact = sourceGradient(*src, p, h * 0.01);
        const Sample a = adf->sample(glm::vec3(p));
        const Sample b = acc.sample(glm::vec3(p));
        ASSERT_EQ(a.distance, b.distance);
        ASSERT_EQ(a.gradient, b.gradient);
        // Trilinear cells sized for ε = 0.25 finest cell have gradient error ~ sqrt(2 ε κ).
        const double err = glm::length(glm::dvec3(a.gradient) - exact);
        ASSERT_LT(err, 0.2) << "at " << p.x << "," << p.y << "," << p.z;
        errors.push_back(err);
    }
    std::nth_element(errors.begin(), errors.begin() + errors.size() / 2, errors.end());
    EXPECT_LT(errors[errors.size() / 2], 0.05) << "median gradient error";
}

TEST(Generate, IsDeterministicSerialOrParallel) {
    const Domain d = testPartDomain(8);
    const SourcePtr part = makeTestPart(d);
    util::ThreadPool pool(3);
    const AdfPtr serial = generate(*part, d, testPartSettings());
    const AdfPtr again = generate(*part, d, testPartSettings());
    const AdfPtr parallel = generate(*part, d, testPartSettings(), &pool);
    EXPECT_TRUE(test::sameAdf(*serial, *again));
    EXPECT_TRUE(test::sameAdf(*serial, *parallel));
}

TEST(Generate, ProgressCountsEveryTileOnceAndChangesNothing) {
    util::ThreadPool pool(3);
    // Level 8 spans many tiles (coloured runs); a tile span of level - 1 gives 2^3 tiles, a
    // small run (roots, parts and joins).
    for (const int span : {4, 7}) {
        Domain d = testPartDomain(8);
        d.tileSpanLevels = span;
        const SourcePtr part = makeTestPart(d);
        const AdfPtr plain = generate(*part, d, testPartSettings(), &pool);
        for (util::ThreadPool* p : {static_cast<util::ThreadPool*>(nullptr), &pool}) {
            GenerationProgress progress;
            GenerationStats stats;
            const AdfPtr a = generate(*part, d, testPartSettings(), p, &stats, &progress);
            EXPECT_TRUE(test::sameAdf(*plain, *a)) << span;
            EXPECT_GT(stats.tilesGenerated, 0u) << span;
            EXPECT_EQ(progress.tilesTotal.load(), stats.tilesGenerated) << span;
            EXPECT_EQ(progress.tilesDone.load(), stats.tilesGenerated) << span;
        }
    }
}

TEST(Generate, SmallGenerationsAreTheSameOnAnyNumberOfThreads) {
    // Fewer tiles than 8 per thread (a LOD's 2^3) run at once, each from its root, whole or in
    // parts: the same bits as a serial generation.
    util::ThreadPool two(2), three(3);
    for (const int level : {6, 8}) {
        Domain d = testPartDomain(level);
        d.tileSpanLevels = level - 1;  // 2^3 tiles
        const SourcePtr part = makeTestPart(d);
        const AdfPtr serial = generate(*part, d, testPartSettings());
        EXPECT_TRUE(test::sameAdf(*serial, *generate(*part, d, testPartSettings(), &two))) << level;
        EXPECT_TRUE(test::sameAdf(*serial, *generate(*part, d, testPartSettings(), &three))) << level;
    }
}

TEST(Generate, EvaluatesEachDistinctLatticePointOnce) {
    const Domain d = testPartDomain(8);
    util::ThreadPool pool(3);
    for (util::ThreadPool* p : {static_cast<util::ThreadPool*>(nullptr), &pool}) {
        test::CountingSource counting(makeTestPart(d));
        GenerationStats stats;
        generate(counting, d, testPartSettings(), p, &stats);
        EXPECT_GE(stats.tilesGenerated, 8u * pool.threadCount()) << "a run in colours, not a small one";
        EXPECT_EQ(counting.evaluations(), counting.distinctPoints()) << (p ? "parallel" : "serial");
        EXPECT_EQ(stats.samples, counting.evaluations());
        EXPECT_GT(stats.samples, 1000u);
    }
    // Same count in serial and parallel runs.
    GenerationStats s1, s2;
    generate(*makeTestPart(d), d, testPartSettings(), nullptr, &s1);
    generate(*makeTestPart(d), d, testPartSettings(), &pool, &s2);
    EXPECT_EQ(s1.samples, s2.samples);
}

class SurfaceOnly : public ::testing::TestWithParam<int> {};

TEST_P(SurfaceOnly, GenerationCoalescesCellsWithoutSurface) {
    const Domain d = unitDomain(8, GetParam());
    // A thin torus and a tiny sphere: big cells near them may hold surface, and many turn out
    // not to, above and below the tile level.
    const SourcePtr src = makeCsg(CsgOp::Union, makeTorus(0.25, 0.02), makeTranslated(makeSphere(0.01), {0.31, 0.3, 0.29}));
    GenerationSettings surfaceOnly;
    surfaceOnly.bandCells = 0.0;
    GenerationStats band, bare;
    const AdfPtr banded = generate(*src, d, GenerationSettings{}, nullptr, &band);
    const AdfPtr coalesced = generate(*src, d, surfaceOnly, nullptr, &bare);
    EXPECT_LT(bare.cells, band.cells);
    // No brick (a cell whose 8 children are leaves) holds children all interior or all exterior.
    std::size_t bricks = 0;
    coalesced->forEachTile([&](const Tile& t) {
        for (uint32_t b = 0; b < t.brickCount(); ++b) {
            ++bricks;
            CellType types[8];
            for (int child = 0; child < 8; ++child) {
                float c[8];
                for (int k = 0; k < 8; ++k) c[k] = t.brickCorner(b, child, k);
                types[child] = cellTypeOf(std::span<const float, 8>(c, 8));
            }
            bool allSame = types[0] != CellType::Boundary;
            for (CellType ty : types) allSame = allSame && ty == types[0];
            ASSERT_FALSE(allSame) << "uncoalesced brick in tile at level " << t.level();
        }
    });
    EXPECT_GT(bricks, 0u);
    // Nor any cell above the tile level whose 8 children are such leaves (merges cascade).
    for (int level = d.tileLevel() - 1; level >= 0; --level) {
        const uint32_t cells = 1u << level, child = d.cellLattice(level + 1);
        for (uint32_t z = 0; z < cells; ++z)
            for (uint32_t y = 0; y < cells; ++y)
                for (uint32_t x = 0; x < cells; ++x) {
                    const glm::uvec3 o = glm::uvec3(x, y, z) * d.cellLattice(level);
                    CellType type = CellType::Boundary;
                    bool allSame = true;
                    for (int c = 0; c < 8 && allSame; ++c) {
                        const glm::uvec3 co = o + glm::uvec3(c & 1, (c >> 1) & 1, c >> 2) * child;
                        const Tile* t = coalesced->tileAtSlot(co >> uint32_t(d.tileSpan()));
                        allSame = t->level() == level + 1 && t->singleLeaf() && t->rootType() != CellType::Boundary &&
                                  (c == 0 || t->rootType() == type);
                        type = t->rootType();
                    }
                    ASSERT_FALSE(allSame) << "uncoalesced cell at level " << level << ", " << x << "," << y << "," << z;
                }
    }
}

INSTANTIATE_TEST_SUITE_P(TileSpans, SurfaceOnly, ::testing::Values(2, 5));

TEST(Generate, BricksAndLoneLeavesReconstructTheSameField) {
    // Every leaf found by lookup matches the leaf enumeration, bricks included.
    const Domain d = testPartDomain(7);
    const AdfPtr adf = generate(*makeTestPart(d), d, testPartSettings());
    std::size_t leaves = 0, inBricks = 0;
    adf->forEachTile([&](const Tile& t) {
        forEachLeaf(t, d.maxLevel, [&](const LeafRef& leaf) {
            ++leaves;
            inBricks += leaf.brickChild >= 0;
            const LeafRef found = adf->findLeaf(leaf.latticeOrigin + leaf.latticeSize / 2);
            ASSERT_EQ(found.latticeOrigin, leaf.latticeOrigin);
            ASSERT_EQ(found.level, leaf.level);
            ASSERT_EQ(found.brickChild, leaf.brickChild);
            for (int c = 0; c < 8; ++c) ASSERT_EQ(found.corners[c], leaf.corners[c]);
        });
    });
    EXPECT_EQ(leaves, adf->computeStats().cells);
    EXPECT_GT(inBricks, leaves / 4);
}

TEST(Generate, FinestCellsStayWithinACellOfTheSurface) {
    // A box with a notch: sharp convex and concave edges, whose medial sheets cross the band.
    // A finest leaf exists only where its parent has a sample within one finest cell of the
    // surface (CellRule::farFromSurface); parents farther out stay leaves even where the
    // 19-point test fails them, and such leaves must exist, but never nearer (the test on 9
    // samples before the other 18, farFromSurfaceAtFirstLook, must not settle more).
    const SourcePtr src = makeCsg(CsgOp::Difference, makeBox({0.3, 0.3, 0.2}),
                                  makeTranslated(makeBox({0.1, 0.4, 0.1}), {0.05, 0.0, 0.2}));
    const Domain d = unitDomain(8, 4);
    const AdfPtr adf = generate(*src, d, GenerationSettings{});
    const ErrorBound bound = adf->settings().errorBound(d);
    const double h = d.finestCellSize();
    auto at = [&](glm::uvec3 p) { return src->distance(d.latticeToWorld(p.x, p.y, p.z)); };
    auto halfGrid = [](uint32_t g) { return glm::uvec3(g % 3, (g / 3) % 3, g / 9); };
    std::size_t finest = 0, graded = 0;
    adf->forEachTile([&](const Tile& t) {
        forEachLeaf(t, d.maxLevel, [&](const LeafRef& leaf) {
            if (leaf.latticeSize == 1) {
                ++finest;
                const glm::uvec3 parent = leaf.latticeOrigin & ~glm::uvec3(1);
                double nearest = std::numeric_limits<double>::max();
                for (uint32_t g = 0; g < 27; ++g) nearest = std::min(nearest, std::abs(at(parent + halfGrid(g))));
                ASSERT_LT(nearest, h * (1 + 1e-6)) << "a finest leaf more than a cell from the surface";
            }
            if (leaf.latticeSize != 2) return;
            // Would the 19-point test have split this leaf? Its largest error at the half grid.
            double nearest = std::numeric_limits<double>::max(), err = 0.0;
            for (uint32_t g = 0; g < 27; ++g) {
                const glm::uvec3 o = halfGrid(g);
                const double exact = at(leaf.latticeOrigin + o);
                nearest = std::min(nearest, std::abs(exact));
                const double recon = trilinear(leaf.corners, glm::vec3(o) * 0.5f).distance;
                err = std::max(err, std::abs(recon - exact));
            }
            if (err > bound(nearest)) {  // the 19-point test failed it: graded, so far from the surface
                ++graded;
                ASSERT_GE(nearest, h * (1 - 1e-6)) << "a failing leaf of 2 cells near the surface";
            }
        });
    });
    EXPECT_GT(finest, 1000u);
    EXPECT_GT(graded, 10u) << "no leaf was kept from splitting: the rule was not exercised";
}

TEST(Generate, LatticeDistanceReadsTheStoredCornersAndInterpolatesBetweenThem) {
    const Domain d = testPartDomain(7);
    const AdfPtr adf = generate(*makeTestPart(d), d, testPartSettings());
    const uint32_t top = d.latticeSize();
    std::size_t interpolated = 0;
    adf->forEachTile([&](const Tile& t) {
        forEachLeaf(t, d.maxLevel, [&](const LeafRef& leaf) {
            // A leaf owns its lower corner, and its upper ones on the domain's far faces.
            for (int c = 0; c < 8; ++c) {
                const glm::uvec3 o(c & 1, (c >> 1) & 1, c >> 2);
                const glm::uvec3 p = leaf.latticeOrigin + o * leaf.latticeSize;
                if ((o.x && p.x != top) || (o.y && p.y != top) || (o.z && p.z != top)) continue;
                ASSERT_EQ(adf->latticeDistance(p), leaf.corners[c]);
            }
            if (leaf.latticeSize < 2) return;
            // Inside the leaf: its trilinear value, as a world-space sample finds it.
            const glm::uvec3 mid = leaf.latticeOrigin + leaf.latticeSize / 2;
            const float s = adf->sample(glm::vec3(d.latticeToWorld(mid.x, mid.y, mid.z))).distance;
            ASSERT_NEAR(adf->latticeDistance(mid), s, 1e-6);
            ++interpolated;
        });
    });
    EXPECT_GT(interpolated, 100u);
}

TEST(Generate, LatticeDistancesInBatchesEqualOneByOne) {
    // Batches of every size up to past two groups of lanes (64 each), over random lattice points
    // (the far faces included) and the corners and centres of leaves: the same bits as
    // latticeDistance.
    const Domain d = testPartDomain(8);
    const AdfPtr adf = generate(*makeTestPart(d), d, testPartSettings());
    const uint32_t top = d.latticeSize();
    std::vector<glm::uvec3> points;
    std::mt19937 rng(7);
    std::uniform_int_distribution<uint32_t> coord(0, top);
    for (int i = 0; i < 4000; ++i) points.emplace_back(coord(rng), coord(rng), coord(rng));
    adf->forEachTile([&](const Tile& t) {
        forEachLeaf(t, d.maxLevel, [&](const LeafRef& leaf) {
            if (points.size() < 20000) {
                points.push_back(leaf.latticeOrigin);
                points.push_back(leaf.latticeOrigin + leaf.latticeSize / 2);
            }
        });
    });
    points.push_back(glm::uvec3(top));
    std::size_t at = 0;
    for (std::size_t batch = 1; at < points.size(); batch = batch % 140 + 1) {
        const std::size_t n = std::min(batch, points.size() - at);
        std::vector<float> out(n, std::numeric_limits<float>::quiet_NaN());
        adf->latticeDistances({points.data() + at, n}, out);
        for (std::size_t i = 0; i < n; ++i)
            ASSERT_EQ(std::bit_cast<uint32_t>(out[i]), std::bit_cast<uint32_t>(adf->latticeDistance(points[at + i])))
                << "point " << glm::to_string(points[at + i]) << " in a batch of " << n;
        at += n;
    }
}

TEST(Generate, RandomLocalRegenerationsGiveTheFullGenerationsFieldUpToQuantisation) {
    // Bit for bit only holds where no cell mixes copied and regenerated children: with an exact
    // source (not the old field), a copied lone leaf's rounded corners differ from a fresh
    // sibling's exact ones, so the tile keeps them apart where a fresh generation groups them
    // (tile.h), and a copied value and a resampled one can round apart. The field must not care.
    util::ThreadPool pool(2);
    for (int span : {3, 5}) {
        SCOPED_TRACE(span);
        Domain ds = testPartDomain(8);
        ds.tileSpanLevels = span;
        const SourcePtr part = makeTestPart(ds);
        const AdfPtr base = generate(*part, ds, testPartSettings(), &pool);
        std::mt19937 rng(7);
        std::uniform_real_distribution<double> u(0.2, 0.8);
        int changed = 0;
        for (int k = 0; k < 8; ++k) {
            const glm::dvec3 c(u(rng), u(rng), u(rng));
            const double r = 0.03 + 0.04 * u(rng);
            const double pad = r + 2 * ds.finestCellSize();
            const BoxWorld region{c - pad, c + pad};
            const auto carved =
                makeRegionLimited(part, makeCsg(CsgOp::Difference, part, makeTranslated(makeSphere(r), c)), region);
            const AdfPtr edited = regenerate(*base, *carved, region, &pool);
            const AdfPtr full = generate(*carved, ds, testPartSettings(), &pool);
            EXPECT_TRUE(test::sameFieldUpToQuantisation(*edited, *full))
                << "carving " << k << " at " << c.x << " " << c.y << " " << c.z << " radius " << r;
            changed += !test::sameFieldUpToQuantisation(*edited, *base);
        }
        EXPECT_GE(changed, 4) << "most carvings must reach the part";
    }
}

TEST(Generate, LocalRegenerationEqualsFullGeneration) {
    util::ThreadPool pool(2);
    for (int span : {3, 5}) {
        SCOPED_TRACE(span);
        const Domain d = testPartDomain(8);
        Domain ds = d;
        ds.tileSpanLevels = span;
        const SourcePtr part = makeTestPart(ds);
        const AdfPtr base = generate(*part, ds, testPartSettings(), &pool);
        // A carve that straddles a tile corner: the rounded corner of the part at (0.75, 0.75,
        // 0.75), a slot corner for every span used here. The tool acts inside a box only (as a
        // band-limited tool does), so the new source equals the old one outside the region.
        const glm::dvec3 c(0.75);
        const double r = 0.06;
        const double pad = r + 2 * ds.finestCellSize();
        const BoxWorld region{c - pad, c + pad};
        const auto carved = makeRegionLimited(
            part, makeCsg(CsgOp::Difference, part, makeTranslated(makeSphere(r), c)), region);
        GenerationStats stats;
        const AdfPtr edited = regenerate(*base, *carved, region, &pool, &stats);
        const AdfPtr full = generate(*carved, ds, testPartSettings(), &pool);
        // The same field up to quantisation: rebuilt tiles keep their old quantisation scale
        // where the values fit it (a fresh generation picks each tile's own). The storage may
        // differ in one way only: a leaf copied from a far group (its values rounded to two
        // leaf steps) beside freshly sampled siblings disagrees with them at a shared corner,
        // so they stay apart where the fresh generation groups them (an edit, whose source is
        // the old field, keeps them agreeing). Elsewhere the tiles are the same bit for bit.
        EXPECT_TRUE(test::sameFieldUpToQuantisation(*edited, *full));
        const uint32_t n = ds.slotsPerAxis();
        for (uint32_t z = 0; z < n; ++z)
            for (uint32_t y = 0; y < n; ++y)
                for (uint32_t x = 0; x < n; ++x) {
                    const Tile &te = *edited->tileAtSlot({x, y, z}), &tf = *full->tileAtSlot({x, y, z});
                    const char* why = test::tileDifference(te, tf, true);
                    if (!why || te.groupedLeafCount() == tf.groupedLeafCount()) {
                        EXPECT_EQ(why, nullptr) << "slot " << x << "," << y << "," << z;
                        continue;
                    }
                    EXPECT_LT(te.groupedLeafCount(), tf.groupedLeafCount()) << "slot " << x << "," << y << "," << z;
                    EXPECT_EQ(te.cellCount(), tf.cellCount());
                    // Every brick, and every leaf grouped in neither tile, still the same bits.
                    ASSERT_EQ(te.scale(), tf.scale());
                    ASSERT_EQ(te.nodeCount(), tf.nodeCount());
                    std::size_t comparedLeaves = 0;
                    for (uint32_t i = 0; i < te.nodeCount(); ++i) {
                        const uint32_t we = te.node(i), wf = tf.node(i);
                        ASSERT_EQ(node::isLeaf(we), node::isLeaf(wf));
                        ASSERT_EQ(node::isBrick(we), node::isBrick(wf));
                        if (node::isBrick(we)) {
                            int16_t ve[27], vf[27];
                            te.brickValues(node::brickIndex(we), ve);
                            tf.brickValues(node::brickIndex(wf), vf);
                            EXPECT_TRUE(std::equal(ve, ve + 27, vf)) << "brick, node " << i;
                        } else if (node::isLeaf(we) && node::leafIndex(we) >= 8 * te.groupCount() &&
                                   node::leafIndex(wf) >= 8 * tf.groupCount()) {
                            int16_t ve[8], vf[8];
                            te.leafValues(node::leafIndex(we), ve);
                            tf.leafValues(node::leafIndex(wf), vf);
                            EXPECT_TRUE(std::equal(ve, ve + 8, vf)) << "lone leaf, node " << i;
                            ++comparedLeaves;
                        }
                    }
                    EXPECT_GT(comparedLeaves + te.brickCount(), 0u);
                }
        EXPECT_EQ(edited->version(), base->version() + 1);
        EXPECT_GE(stats.tilesGenerated, 8u) << "the edit should straddle 8 tiles";
        EXPECT_LT(stats.tilesGenerated, base->computeStats().tiles / 4);
        // Untouched tiles are shared, not copied.
        EXPECT_EQ(edited->tileAtSlot({0, 0, 0}), base->tileAtSlot({0, 0, 0}));
    }
}

TEST(Generate, RegeneratingAnUnchangedRegionChangesNothing) {
    const Domain d = testPartDomain(7);
    const SourcePtr part = makeTestPart(d);
    const AdfPtr base = generate(*part, d, testPartSettings());
    const AdfPtr again = regenerate(*base, *part, {glm::dvec3(0.1), glm::dvec3(0.6)});
    EXPECT_TRUE(test::sameAdf(*base, *again));
}

TEST(Generate, RegeneratesFromTheOldFieldCombinedWithATool) {
    // The edit primitive as the sculpting engine uses it: old snapshot as a source, CSG with a
    // tool, limited to the region being regenerated.
    const Domain d = testPartDomain(8);
    const AdfPtr base = generate(*makeTestPart(d), d, testPartSettings());
    const glm::dvec3 c(0.35, 0.2, 0.65);  // on the -y face of the part, clear of its hole
    const double r = 0.03, pad = r + 3 * d.finestCellSize();
    const BoxWorld region{c - pad, c + pad};
    const SourcePtr old = makeAdfSource(base);
    EXPECT_EQ(old->distance({0.31, 0.42, 0.53}), double(base->distance({0.31f, 0.42f, 0.53f})));
    const SourcePtr carved = makeRegionLimited(old, makeCsg(CsgOp::Difference, old, makeTranslated(makeSphere(r), c)), region);
    GenerationStats stats;
    const AdfPtr edited = regenerate(*base, *carved, region, nullptr, &stats);
    EXPECT_LT(base->distance(glm::vec3(c + glm::dvec3(0, 0.01, 0))), 0.0f);  // was material
    EXPECT_NEAR(edited->distance(glm::vec3(c + glm::dvec3(0, 0.01, 0))), r - 0.01, 0.25 * d.finestCellSize());
    EXPECT_GT(stats.tilesGenerated, 0u);
    // Far away nothing changed, down to the tile pointers.
    EXPECT_EQ(edited->tileAtSlot({0, 0, 0}), base->tileAtSlot({0, 0, 0}));
    EXPECT_EQ(edited->distance({0.5f, 0.8f, 0.5f}), base->distance({0.5f, 0.8f, 0.5f}));
}

TEST(Generate, SubTileRegenerationSamplesOnlyTheRegion) {
    // A rebuilt tile copies its cells outside the region from the old tile: a small dab samples
    // a fraction of what regenerating the same tile over its whole box does, and agrees with it.
    const Domain d = testPartDomain(8);
    const AdfPtr base = generate(*makeTestPart(d), d, testPartSettings());
    const glm::dvec3 c(0.35, 0.2, 0.65);
    const double r = 0.012, pad = r + 3 * d.finestCellSize();
    const SourcePtr old = makeAdfSource(base);
    const SourcePtr dab = makeCsg(CsgOp::Difference, old, makeTranslated(makeSphere(r), c));
    const BoxWorld region{c - pad, c + pad};
    const double tileSize = d.finestCellSize() * double(1u << d.tileSpan());
    const glm::dvec3 tileMin = d.originWorld + glm::floor((c - d.originWorld) / tileSize) * tileSize;
    const double inset = 1.5 * d.finestCellSize();  // clear of the neighbours (regions are closed, in whole cells)
    const BoxWorld wholeTile{tileMin + inset, tileMin + tileSize - inset};
    GenerationStats small, whole;
    const AdfPtr a = regenerate(*base, *makeRegionLimited(old, dab, region), region, nullptr, &small);
    const AdfPtr b = regenerate(*base, *makeRegionLimited(old, dab, wholeTile), wholeTile, nullptr, &whole);
    ASSERT_EQ(small.tilesGenerated, 1u);
    ASSERT_EQ(whole.tilesGenerated, 1u);
    EXPECT_LT(double(small.samples), 0.3 * double(whole.samples)) << small.samples << " vs " << whole.samples;
    // Both carved the dab; outside the region the copied cells reproduce the old field (up to
    // re-quantisation), over a grid through the whole tile.
    EXPECT_GT(a->distance(glm::vec3(c + glm::dvec3(0, 0.005, 0))), 0.0f);
    const BoxWorld grown{region.min - 2.0 * d.finestCellSize(), region.max + 2.0 * d.finestCellSize()};
    const glm::uvec3 slot((tileMin - d.originWorld) / tileSize + 0.5);
    // A copied packed brick or leaf is rounded to the new tile's step when the scale changed.
    // A cell near the region is sampled again from the old field, which at a corner two old
    // items share answers with one item's value; the other rounded the same point within a
    // leaf step of the sample too, so the two may differ by two leaf steps, and the new item
    // rounds that answer once more: three leaf steps in all.
    const Tile* ta = a->tileAtSlot(slot);
    const double quanta = double(ta->scale()) * double(3 * ta->leafStep() + 1) + double(base->tileAtSlot(slot)->scale());
    ASSERT_NE(a->tileAtSlot(slot), base->tileAtSlot(slot));
    // The dab's values fit the old scale, so the rebuilt tile keeps it (and copied cells their bits).
    EXPECT_EQ(a->tileAtSlot(slot)->scale(), base->tileAtSlot(slot)->scale());
    int compared = 0;
    for (int i = 0; i <= 20; ++i)
        for (int j = 0; j <= 20; ++j)
            for (int k = 0; k <= 20; ++k) {
                const glm::dvec3 p = tileMin + glm::dvec3(i, j, k) * (tileSize / 20.0) * 0.999;
                if (grown.contains(p)) continue;
                ++compared;
                ASSERT_NEAR(a->distance(glm::vec3(p)), base->distance(glm::vec3(p)), quanta) << i << "," << j << "," << k;
            }
    EXPECT_GT(compared, 8000);
}

/// A carve that says where it leaves the old field alone (as the sculptor's edits do): the
/// same field and features as `carve`, plus the unchanged range of old values.
class DeclaredCarve final : public DistanceSource {
public:
    DeclaredCarve(SourcePtr carve, glm::dvec3 centre, double radius, double slack)
        : mCarve(std::move(carve)), mCentre(centre), mRadius(radius), mSlack(slack) {
        mSmallestFeature = mCarve->smallestFeature();
    }
    double distance(const glm::dvec3& p) const override { return mCarve->distance(p); }
    void distances(std::span<const glm::dvec3> p, std::span<double> out) const override { mCarve->distances(p, out); }
    double featureSize(const glm::dvec3& c, double r) const override { return mCarve->featureSize(c, r); }
    Range unchangedRange(const glm::dvec3& c, double r) const override {
        return {r + mSlack - (glm::distance(c, mCentre) - mRadius), std::numeric_limits<double>::infinity()};
    }

private:
    SourcePtr mCarve;
    glm::dvec3 mCentre;
    double mRadius, mSlack;
};

/// A dab carving a sphere of radius r at c from `old`, declaring where it leaves it alone,
/// limited to the cube of half-width pad around c: what a sculptor's carve hands regenerate.
struct DeclaredDab {
    BoxWorld region;
    SourcePtr edit;
};
DeclaredDab declaredDab(const SourcePtr& old, glm::dvec3 c, double r, double pad, double finestCell) {
    const BoxWorld region{c - pad, c + pad};
    const auto declaring = std::make_shared<DeclaredCarve>(makeCsg(CsgOp::Difference, old, makeTranslated(makeSphere(r), c)), c,
                                                           r, 0.05 * finestCell);
    return {region, makeRegionLimited(old, declaring, region)};
}

TEST(Generate, CellsAnEditLeavesUnchangedAreCopiedNotSampled) {
    // Inside the region, cells where the source declares the old field unchanged keep the old
    // tile's cells: far fewer samples, and there the field is the old one (up to quantisation).
    const Domain d = testPartDomain(8);
    const AdfPtr base = generate(*makeTestPart(d), d, testPartSettings());
    const glm::dvec3 c(0.35, 0.2, 0.65);
    const double r = 0.03, pad = r + 10 * d.finestCellSize();
    const SourcePtr old = makeAdfSource(base);
    const SourcePtr sphere = makeTranslated(makeSphere(r), c);
    const SourcePtr carve = makeCsg(CsgOp::Difference, old, sphere);
    const BoxWorld region{c - pad, c + pad};
    GenerationStats plain, declared;
    const AdfPtr a = regenerate(*base, *makeRegionLimited(old, carve, region), region, nullptr, &plain);
    const auto declaring = std::make_shared<DeclaredCarve>(carve, c, r, 0.05 * d.finestCellSize());
    const AdfPtr b = regenerate(*base, *makeRegionLimited(old, declaring, region), region, nullptr, &declared);
    EXPECT_LT(double(declared.samples), 0.92 * double(plain.samples)) << declared.samples << " vs " << plain.samples;
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    const ErrorBound bound = testPartSettings().errorBound(d);
    int unchanged = 0, changed = 0;
    for (int i = 0; i < 20000; ++i) {
        const glm::dvec3 p = c + pad * glm::dvec3(u(rng), u(rng), u(rng));
        const double was = base->distance(glm::vec3(p)), tool = sphere->distance(p);
        if (was + tool > 4.0 * d.finestCellSize()) {
            // Clear of the tool's reach: the old field (kept cells reproduce it up to
            // quantisation; cells whose ball reaches the tool were re-derived from the same
            // values, within the error bound).
            ++unchanged;
            ASSERT_NEAR(b->distance(glm::vec3(p)), was, bound(std::abs(was))) << p.x << "," << p.y << "," << p.z;
        } else if (tool < -d.finestCellSize()) {
            ++changed;
            ASSERT_GT(b->distance(glm::vec3(p)), 0.0f);  // carved in both
            ASSERT_GT(a->distance(glm::vec3(p)), 0.0f);
        }
    }
    EXPECT_GT(unchanged, 5000);
    EXPECT_GT(changed, 100);
}

TEST(Generate, SmallRegenerationsAreTheSameOnAnyNumberOfThreads) {
    // A dab's few tiles run in one phase, without handing border samples over, and each tile
    // in parts (its root, its 8 children side by side, joined): the result must still be the
    // serial one, bit for bit, at a tile corner (8 tiles), inside one, and at dabs of several
    // sizes on the part's surface (crossing children's borders, or filling one child).
    const Domain d = testPartDomain(8);
    util::ThreadPool two(2), three(3);
    const AdfPtr base = generate(*makeTestPart(d), d, testPartSettings(), &two);
    const SourcePtr old = makeAdfSource(base);
    std::vector<std::pair<glm::dvec3, double>> dabs{{glm::dvec3(0.75), 0.03}, {glm::dvec3(0.35, 0.2, 0.65), 0.03}};
    const std::vector<glm::dvec3> surface =
        randomSurfacePoints(*makeTestPart(d), {d.originWorld, d.originWorld + d.sizeWorld}, 10, 12, 0.25 * d.finestCellSize());
    std::mt19937 rng(12);
    for (const glm::dvec3& p : surface) dabs.emplace_back(p, std::uniform_real_distribution<double>(0.005, 0.05)(rng));
    for (const auto& [c, r] : dabs) {
        const auto [region, edit] = declaredDab(old, c, r, r + 10 * d.finestCellSize(), d.finestCellSize());
        GenerationStats stats;
        const AdfPtr serial = regenerate(*base, *edit, region, nullptr, &stats);
        EXPECT_LT(stats.tilesGenerated, 16u) << "small enough for one phase";
        EXPECT_TRUE(test::sameAdf(*serial, *regenerate(*base, *edit, region, &two)));
        EXPECT_TRUE(test::sameAdf(*serial, *regenerate(*base, *edit, region, &three)));
    }
}

TEST(Generate, SmallRegenerationsOfSmallTilesAreTheSameOnAnyNumberOfThreads) {
    // Tiles of 4 and 8 finest cells: a split root's children are often all leaves, so the join
    // has to coalesce the root or make it a brick, as a whole-tile generation does.
    util::ThreadPool two(2);
    int regenerations = 0;
    for (const int span : {2, 3}) {
        Domain d = testPartDomain(7);
        d.tileSpanLevels = span;
        const AdfPtr base = generate(*makeTestPart(d), d, testPartSettings(), &two);
        const SourcePtr old = makeAdfSource(base);
        const double h = d.finestCellSize();
        const std::vector<glm::dvec3> surface =
            randomSurfacePoints(*makeTestPart(d), {d.originWorld, d.originWorld + d.sizeWorld}, 24, uint64_t(span), 0.25 * h);
        std::mt19937 rng{uint32_t(span)};
        for (const glm::dvec3& c : surface) {
            const double r = std::uniform_real_distribution<double>(0.5, 3.0)(rng) * h;
            const auto [region, edit] = declaredDab(old, c, r, r + 1.5 * h, h);
            GenerationStats stats;
            const AdfPtr serial = regenerate(*base, *edit, region, nullptr, &stats);
            if (stats.tilesGenerated >= 16u) continue;  // not a small regeneration on two threads
            ++regenerations;
            EXPECT_TRUE(test::sameAdf(*serial, *regenerate(*base, *edit, region, &two))) << "span " << span;
        }
    }
    EXPECT_GT(regenerations, 20);
}

TEST(Generate, SmallFeaturesOnFlatSurfacesAreNotMissed) {
    // A bump 3 finest cells in radius on a plane: the plane alone passes every 19-point test in
    // big cells, so only the feature-size rule makes generation look closer.
    const Domain d = unitDomain(8);
    const double h = d.finestCellSize();
    const glm::dvec3 c(0.1 + 0.3 * h, -0.2 + 0.7 * h, 0.0);
    const SourcePtr bumpy = makeCsg(CsgOp::Union, makeHalfSpace({0, 0, 1}, 0.0), makeTranslated(makeSphere(3 * h), c));
    const AdfPtr adf = generate(*bumpy, d, GenerationSettings{});
    EXPECT_LT(adf->distance(glm::vec3(c + glm::dvec3(0, 0, 2 * h))), 0.0f) << "the bump is missing";
    EXPECT_NEAR(adf->distance(glm::vec3(c + glm::dvec3(0, 0, 4 * h))), h, 0.25 * h);
}

TEST(Generate, ChainsOfEditsStayLinear) {
    // Each edit wraps the previous source twice (outside, and inside the CSG): feature queries
    // must not fan out over both copies, or 40 dabs at one spot would take 2^40 steps.
    const Domain d = unitDomain(6);
    SourcePtr current = makeSphere(0.3);
    const glm::dvec3 c(0.3, 0.0, 0.0);
    const BoxWorld region{c - 0.06, c + 0.06};
    for (int i = 0; i < 40; ++i)
        current = makeRegionLimited(current, makeCsg(CsgOp::Difference, current, makeTranslated(makeSphere(0.05), c)), region);
    EXPECT_EQ(current->smallestFeature(), 0.05);
    EXPECT_EQ(current->featureSize(c, 0.1), 0.05);
    const AdfPtr adf = generate(*current, d, GenerationSettings{});
    EXPECT_GT(adf->distance(glm::vec3(c)), 0.0f) << "the carve is missing";
}

/// Generating `source`, NaN in the slab 0.2 < x < 0.3 of the unit domain (which only tiles
/// sample), fails with an error naming a point of the slab in world coordinates.
void expectErrorNamesAPointOfTheNanSlab(const DistanceSource& source) {
    try {
        generate(source, unitDomain(6), GenerationSettings{});
    } catch (const std::domain_error& e) {
        const std::string what = e.what();
        const std::size_t open = what.find('(');
        ASSERT_NE(open, std::string::npos) << what;
        const double x = std::stod(what.substr(open + 1));
        EXPECT_GT(x, 0.2) << what;
        EXPECT_LT(x, 0.3) << what;
        return;
    }
    ADD_FAILURE() << "no error";
}

TEST(Generate, ANonFiniteSourceIsAnErrorNotAnAdf) {
    // NaN in a slab that only the tiles sample (the pass above them samples x = -0.5, 0, 0.5).
    class NanSource final : public DistanceSource {
    public:
        double distance(const glm::dvec3& p) const override {
            return p.x > 0.2 && p.x < 0.3 ? std::numeric_limits<double>::quiet_NaN() : glm::length(p) - 0.3;
        }
    };
    util::ThreadPool pool(2);
    EXPECT_THROW(generate(NanSource{}, unitDomain(6), GenerationSettings{}, &pool), std::domain_error);
    expectErrorNamesAPointOfTheNanSlab(NanSource{});
}

/// A source answering lattice points itself (as a LOD's sampler of a snapshot does): `inner`
/// through the default lattice path, or NaN inside the slab 0.2 < x < 0.3 when `nanSlab`.
class LatticeAnswering final : public DistanceSource {
public:
    LatticeAnswering(SourcePtr inner, bool nanSlab) : mInner(std::move(inner)), mNanSlab(nanSlab) {
        mSmallestFeature = mInner->smallestFeature();
    }
    double distance(const glm::dvec3& p) const override {
        return mNanSlab && p.x > 0.2 && p.x < 0.3 ? std::numeric_limits<double>::quiet_NaN() : mInner->distance(p);
    }
    double featureSize(const glm::dvec3& c, double radius) const override { return mInner->featureSize(c, radius); }
    bool answersLattice(const Domain&) const override { return true; }
    void latticeDistances(const Domain& d, std::span<const glm::uvec3> lattice, std::span<double> out) const override {
        ++asked;
        DistanceSource::latticeDistances(d, lattice, out);
    }
    mutable std::atomic<int> asked{0};  ///< latticeDistances calls

private:
    SourcePtr mInner;
    bool mNanSlab;
};

TEST(Generate, ASourceAnsweringLatticePointsGivesTheSameAdf) {
    // Asked for lattice points or for their world positions, a source gives the same values,
    // so the same ADF, byte for byte, on one thread and on two.
    const Domain d = testPartDomain(7);
    const SourcePtr part = makeTestPart(d);
    const LatticeAnswering answering(part, false);
    util::ThreadPool pool(2);
    for (util::ThreadPool* p : {static_cast<util::ThreadPool*>(nullptr), &pool}) {
        GenerationStats world, lattice;
        const AdfPtr viaWorld = generate(*part, d, testPartSettings(), p, &world);
        const AdfPtr viaLattice = generate(answering, d, testPartSettings(), p, &lattice);
        EXPECT_TRUE(test::sameAdf(*viaWorld, *viaLattice));
        EXPECT_EQ(lattice.samples, world.samples) << "each point evaluated once, shared as before";
    }
    EXPECT_GT(answering.asked.load(), 0) << "generation never took the lattice path";
}

TEST(Generate, ANonFiniteValueAtALatticePointNamesItsWorldPosition) {
    const LatticeAnswering nan(makeSphere(0.3), true);
    expectErrorNamesAPointOfTheNanSlab(nan);
    EXPECT_GT(nan.asked.load(), 0);
}

TEST(Generate, ATileThatFailsStopsTheTilesWaitingForIt) {
    // Tiles wait for their lower-colour neighbours; one whose neighbour threw must stop, not
    // wait forever or read the unfilled border. The NaN lies on the sphere, half an upper-pass
    // step (1/32) from every point the pass above the tiles samples, so only a tile meets it.
    class NanSpot final : public DistanceSource {
    public:
        double distance(const glm::dvec3& p) const override {
            const glm::dvec3 spot(-0.5 + 12.5 / 16.0, 0.0, 0.0);
            return glm::distance(p, spot) < 0.01 ? std::numeric_limits<double>::quiet_NaN() : glm::length(p) - spot.x;
        }
    };
    for (const unsigned threads : {1u, 2u, 3u}) {
        util::ThreadPool pool(threads);
        EXPECT_THROW(generate(NanSpot{}, unitDomain(7, 3), GenerationSettings{}, &pool), std::domain_error) << threads;
    }
}

TEST(Generate, QueriesAtTheEdgesOfTheDomainStayInside) {
    const Domain d = unitDomain(6);
    const AdfPtr adf = generate(*makeSphere(0.3), d, GenerationSettings{});
    AdfAccessor acc(*adf);
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    for (const glm::vec3 p : {glm::vec3(0.5f), glm::vec3(-0.5f), glm::vec3(0.5f, -0.5f, 0.5f), glm::vec3(2.0f, 0.0f, 0.0f),
                              glm::vec3(inf, 0.0f, 0.0f), glm::vec3(-inf, 0.0f, 0.0f)}) {
        EXPECT_GT(acc.sample(p).distance, 0.0f);
        EXPECT_GT(adf->sample(p).distance, 0.0f);
    }
    EXPECT_NEAR(acc.sample({1.5f, 0.0f, 0.0f}).distance, 1.2f, 0.01f);  // 1 m outside + 0.2 inside
    EXPECT_TRUE(std::isnan(acc.sample({nan, 0.0f, 0.0f}).distance));
    EXPECT_TRUE(std::isnan(adf->sample({0.0f, nan, 0.0f}).distance));
}

TEST(Generate, RejectsBadParameters) {
    Domain d = unitDomain(7);
    d.maxLevel = 40;
    EXPECT_THROW(generate(*makeSphere(0.2), d, GenerationSettings{}), std::invalid_argument);
    GenerationSettings s;
    s.epsilonCells = -1;
    EXPECT_THROW(generate(*makeSphere(0.2), unitDomain(6), s), std::invalid_argument);
}

}  // namespace
