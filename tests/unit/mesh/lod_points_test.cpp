// SPDX-License-Identifier: Apache-2.0
#include "mesh/lod.h"
#include "mesh/point_cloud.h"

#include "adf/generate.h"
#include "adf/test_part.h"
#include "tests/util/adf_compare.h"
#include "tests/util/mesh_check.h"
#include "tests/util/painted.h"
#include "util/thread_pool.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <random>
#include <span>
#include <vector>

namespace kizamu {
namespace {

using namespace adf;

TEST(Lod, CoarserErrorGivesFewerTrianglesStillClosedManifoldAndWithinTheError) {
    util::ThreadPool pool;
    const Domain d = testPartDomain(9);
    const SourcePtr part = makeTestPart(d);
    const AdfPtr fine = generate(*part, d, testPartSettings(), &pool);
    const std::size_t full = mesh::meshAdf(fine, &pool).triangleCount();
    std::size_t previous = full + 1;
    for (double e : {0.002, 0.004, 0.008, 0.016}) {
        const mesh::MeshBuffers m = mesh::meshLod(fine, e, &pool);
        ASSERT_TRUE(test::closedOrientedManifold(m)) << "error " << e;
        EXPECT_LT(m.triangleCount(), previous) << "error " << e;
        previous = m.triangleCount();
        double worst = 0.0;
        for (const glm::vec3& p : m.positions) worst = std::max(worst, std::abs(part->distance(glm::dvec3(p))));
        EXPECT_LT(worst, 2.0 * e + d.finestCellSize()) << "error " << e;
    }
    EXPECT_LT(previous, full / 10);
}

TEST(Lod, ErrorForATriangleCountHitsIt) {
    util::ThreadPool pool;
    const Domain d = testPartDomain(9);
    const AdfPtr fine = generate(*makeTestPart(d), d, testPartSettings(), &pool);
    for (std::size_t target : {2000u, 20000u}) {
        const double e = mesh::lodErrorForTriangles(fine, target, &pool);
        const std::size_t n = mesh::meshLod(fine, e, &pool).triangleCount();
        EXPECT_NEAR(double(n), double(target), 0.15 * double(target));
    }
    EXPECT_THROW(mesh::meshLod(fine, 0.0), std::invalid_argument);
}

TEST(Lod, CoarseCornersAreTheFineFieldAtTheSameLatticePoints) {
    const Domain d = testPartDomain(8);
    const AdfPtr fine = generate(*makeTestPart(d), d, testPartSettings());
    const AdfPtr coarse = mesh::coarsenAdf(fine, 6.0 * d.finestCellSize());
    const Domain& cd = coarse->domain();
    ASSERT_LT(cd.maxLevel, d.maxLevel);
    const uint32_t shift = uint32_t(d.maxLevel - cd.maxLevel);
    // Stored values are rounded to 16 bits, packed ones to a leaf step (4/127 finest cell).
    const double tolerance = 0.05 * cd.finestCellSize();
    std::size_t leaves = 0;
    coarse->forEachTile([&](const Tile& t) {
        forEachLeaf(t, cd.maxLevel, [&](const LeafRef& leaf) {
            ASSERT_NEAR(leaf.corners[0], fine->latticeDistance(leaf.latticeOrigin << shift), tolerance);
            ++leaves;
        });
    });
    EXPECT_GT(leaves, 500u);
}

TEST(Lod, TheFineFieldAnswersLatticePointsAsAtTheirWorldPositions) {
    const Domain d = testPartDomain(8);
    const AdfPtr fine = generate(*makeTestPart(d), d, testPartSettings());
    const SourcePtr sampler = mesh::makeFineFieldSource(fine);
    Domain coarse = d;
    coarse.maxLevel = 6;
    coarse.tileSpanLevels = 4;
    ASSERT_TRUE(sampler->answersLattice(coarse));
    Domain shifted = coarse;
    shifted.originWorld.x += 0.25 * d.sizeWorld;
    EXPECT_FALSE(sampler->answersLattice(shifted)) << "another lattice";
    // Random points and the far corner, past two batches.
    std::mt19937 rng(5);
    std::uniform_int_distribution<uint32_t> u(0, coarse.latticeSize());
    std::vector<glm::uvec3> points(150, glm::uvec3(coarse.latticeSize()));
    for (std::size_t i = 1; i < points.size(); ++i) points[i] = {u(rng), u(rng), u(rng)};
    std::vector<double> out(points.size());
    sampler->latticeDistances(coarse, points, out);
    for (std::size_t i = 0; i < points.size(); ++i)
        ASSERT_EQ(out[i], sampler->distance(coarse.latticeToWorld(points[i].x, points[i].y, points[i].z))) << i;
    // So a coarse generation asked at lattice points is the one asked at world positions, byte
    // for byte.
    class WorldOnly final : public DistanceSource {
    public:
        explicit WorldOnly(SourcePtr s) : mS(std::move(s)) {}
        double distance(const glm::dvec3& p) const override { return mS->distance(p); }
        void distances(std::span<const glm::dvec3> p, std::span<double> v) const override { mS->distances(p, v); }

    private:
        SourcePtr mS;
    };
    GenerationSettings s = testPartSettings();
    s.bandCells = 0.0;
    s.epsilonCells = 0.6;
    const AdfPtr viaLattice = generate(*sampler, coarse, s);
    const AdfPtr viaWorld = generate(WorldOnly(sampler), coarse, s);
    EXPECT_TRUE(test::sameAdf(*viaLattice, *viaWorld));
}

TEST(Lod, SameBytesOnAnyThreadCount) {
    util::ThreadPool two(2), three(3);
    const Domain d = testPartDomain(9);
    const AdfPtr fine = generate(*makeTestPart(d), d, testPartSettings(), &two);
    for (double cells : {2.0, 17.0}) {
        const mesh::MeshBuffers serial = mesh::meshLod(fine, cells * d.finestCellSize(), nullptr);
        for (util::ThreadPool* pool : {&two, &three}) {
            const mesh::MeshBuffers m = mesh::meshLod(fine, cells * d.finestCellSize(), pool);
            EXPECT_EQ(m.positions, serial.positions) << cells;
            EXPECT_EQ(m.normals, serial.normals) << cells;
            EXPECT_EQ(m.indices, serial.indices) << cells;
        }
    }
}

TEST(PointCloud, PointsLieOnTheSurfaceWithNormalsAndFollowTheArea) {
    util::ThreadPool pool;
    Domain d;
    d.maxLevel = 8;
    const glm::dvec3 c(0.503, 0.49, 0.51);
    const double r = 0.3;
    const AdfPtr a = generate(*makeTranslated(makeSphere(r), c), d, GenerationSettings{}, &pool);
    const std::size_t n = 200000;
    const mesh::PointCloud pc = mesh::surfacePointCloud(*a, n, 7, &pool);
    ASSERT_EQ(pc.positions.size(), n);
    ASSERT_EQ(pc.normals.size(), n);
    const double h = d.finestCellSize();
    double worst = 0.0, worstNormal = 1.0;
    std::vector<double> errors;
    std::size_t octant[8] = {};
    for (std::size_t i = 0; i < n; ++i) {
        const glm::dvec3 p(pc.positions[i]);
        errors.push_back(std::abs(double(a->distance(pc.positions[i]))));  // the field's own zero set
        worst = std::max(worst, std::abs(glm::length(p - c) - r));
        worstNormal = std::min(worstNormal, glm::dot(glm::dvec3(pc.normals[i]), glm::normalize(p - c)));
        octant[(p.x > c.x) | ((p.y > c.y) << 1) | ((p.z > c.z) << 2)]++;
    }
    // One projection step (Kizamu 6.1): exact for a plane, a fraction of a cell where the
    // trilinear field curves.
    std::nth_element(errors.begin(), errors.begin() + n / 2, errors.end());
    EXPECT_LT(errors[n / 2], 0.02 * h);
    EXPECT_LT(*std::max_element(errors.begin(), errors.end()), 0.5 * h);
    EXPECT_LT(worst, 0.75 * h);  // plus the ADF's own error against the sphere
    EXPECT_GT(worstNormal, 0.95);
    // Area-proportional: each octant of the sphere gets an eighth of the points.
    for (std::size_t o : octant) EXPECT_NEAR(double(o), n / 8.0, 0.02 * n / 8.0);
    // Deterministic, and the same without threads.
    const mesh::PointCloud serial = mesh::surfacePointCloud(*a, n, 7, nullptr);
    EXPECT_EQ(serial.positions, pc.positions);
    EXPECT_EQ(serial.normals, pc.normals);
}

TEST(Paint, MeshesLodsAndPointsCarryTheLayersColoursAndUnpaintedClayNone) {
    util::ThreadPool pool(3);
    Domain d;
    d.maxLevel = 6;
    d.tileSpanLevels = 3;
    const AdfPtr plain = generate(*makeTranslated(makeSphere(0.3), glm::dvec3(0.5)), d, GenerationSettings{}, &pool);
    const Rgb8 red(220, 20, 20);
    const AdfPtr painted = test::paintedAbove(plain, red, 0.5);
    const float h = float(d.finestCellSize());
    // Above z = 0.5 + a cell every blended corner is painted; below 0.5 - a cell none is.
    auto check = [&](std::span<const glm::vec3> positions, const std::vector<glm::u8vec3>& colours, const char* what) {
        ASSERT_EQ(colours.size(), positions.size()) << what;
        std::size_t above = 0, below = 0;
        for (std::size_t i = 0; i < positions.size(); ++i) {
            if (positions[i].z > 0.5f + h) {
                EXPECT_EQ(colours[i], red) << what << " vertex " << i;
                ++above;
            } else if (positions[i].z < 0.5f - h) {
                EXPECT_EQ(colours[i], kClayColour) << what << " vertex " << i;
                ++below;
            }
        }
        EXPECT_GT(above, 10u) << what;
        EXPECT_GT(below, 10u) << what;
    };
    const mesh::MeshBuffers full = mesh::meshAdf(painted, &pool);
    check(full.positions, full.colours, "mesh");
    EXPECT_TRUE(test::canonical(full) == test::canonical(mesh::meshAdf(painted, nullptr))) << "threads change nothing";
    const mesh::MeshBuffers lod = mesh::meshLod(painted, 3.0 * h, &pool);
    EXPECT_LT(lod.vertexCount(), full.vertexCount());
    check(lod.positions, lod.colours, "lod");
    const mesh::PointCloud points = mesh::surfacePointCloud(*painted, 5000, 1, &pool);
    check(points.positions, points.colours, "points");
    // Unpainted clay: no colours at all, as before paint existed.
    EXPECT_TRUE(mesh::meshAdf(plain, &pool).colours.empty());
    EXPECT_TRUE(mesh::meshLod(plain, 3.0 * h, &pool).colours.empty());
    EXPECT_TRUE(mesh::surfacePointCloud(*plain, 100, 1, &pool).colours.empty());
}

}  // namespace
}  // namespace kizamu
