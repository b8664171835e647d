// SPDX-License-Identifier: Apache-2.0
#include "mesh/surface_nets.h"

#include "adf/adf_source.h"
#include "adf/generate.h"
#include "adf/test_part.h"
#include "mesh/mesh_untangle.h"
#include "tests/support/mesh_intersections.h"
#include "tests/util/dabbed.h"
#include "tests/util/mesh_check.h"
#include "tests/util/random_shape.h"
#include "util/thread_pool.h"

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <map>
#include <mutex>
#include <random>

namespace kizamu {
namespace {

using namespace adf;
using mesh::MeshBuffers;
using mesh::SurfaceMesher;
using mesh::SurfaceNetsStats;

Domain unitDomain(int level, int span) {
    Domain d;
    d.maxLevel = level;
    d.tileSpanLevels = span;
    return d;
}

MeshBuffers meshOf(const SourcePtr& s, const Domain& d, SurfaceNetsStats* st = nullptr, util::ThreadPool* pool = nullptr) {
    return mesh::meshAdf(generate(*s, d, GenerationSettings{}, pool), pool, st);
}

TEST(SurfaceNets, SphereIsClosedManifoldOnTheSurfaceWithRadialNormals) {
    const glm::dvec3 c(0.51, 0.48, 0.5);
    const double r = 0.3;
    const Domain d = unitDomain(7, 4);
    SurfaceNetsStats st;
    const MeshBuffers m = meshOf(makeTranslated(makeSphere(r), c), d, &st);
    ASSERT_GT(m.triangleCount(), 1000u);
    EXPECT_TRUE(m.valid());
    EXPECT_TRUE(test::closedOrientedManifold(m));
    EXPECT_EQ(test::eulerCharacteristic(m), 2);
    EXPECT_EQ(test::componentCount(m), 1u);
    EXPECT_EQ(st.oddFaces, 0u);
    EXPECT_EQ(st.openCrossings, 0u);
    const double h = d.finestCellSize();
    double worst = 0.0, worstNormal = 1.0;
    for (std::size_t i = 0; i < m.vertexCount(); ++i) {
        const glm::dvec3 p(m.positions[i]);
        worst = std::max(worst, std::abs(glm::length(p - c) - r));
        worstNormal = std::min(worstNormal, double(glm::dot(glm::dvec3(m.normals[i]), glm::normalize(p - c))));
    }
    EXPECT_LT(worst, 0.25 * h);
    EXPECT_GT(worstNormal, 0.97);
    // Outward orientation: the signed volume is positive and close to the sphere's.
    double volume = 0.0;
    for (std::size_t t = 0; t < m.triangleCount(); ++t) {
        const glm::dvec3 a(m.positions[m.indices[3 * t]]), b(m.positions[m.indices[3 * t + 1]]),
            e(m.positions[m.indices[3 * t + 2]]);
        volume += glm::dot(a - c, glm::cross(b - c, e - c)) / 6.0;
    }
    EXPECT_NEAR(volume, 4.0 / 3.0 * 3.14159265358979 * r * r * r, 0.02 * volume);  // chords cut inside
}

TEST(SurfaceNets, EulerCharacteristicMatchesTheGenus) {
    const Domain d = unitDomain(7, 4);
    {
        const MeshBuffers m = meshOf(makeTranslated(makeTorus(0.25, 0.08), glm::dvec3(0.5)), d);
        ASSERT_TRUE(test::closedOrientedManifold(m));
        EXPECT_EQ(test::eulerCharacteristic(m), 0) << "torus";
    }
    for (int holes = 1; holes <= 4; ++holes) {
        std::vector<SourcePtr> parts{makeTranslated(makeBox({0.35, 0.15, 0.1}), glm::dvec3(0.5))};
        for (int i = 0; i < holes; ++i)
            parts.push_back(makeTranslated(makeCylinder(0.05, 0.2), {0.5 - 0.25 + 0.5 * (i + 0.5) / holes, 0.5, 0.5}));
        const MeshBuffers m = meshOf(makeCsg(CsgOp::Difference, parts), d);
        ASSERT_TRUE(test::closedOrientedManifold(m)) << holes << " holes";
        EXPECT_EQ(test::eulerCharacteristic(m), 2 - 2 * holes) << holes << " holes";
        EXPECT_EQ(test::componentCount(m), 1u);
    }
    {
        // Two separate parts: two spheres.
        const MeshBuffers m = meshOf(makeCsg(CsgOp::Union, makeTranslated(makeSphere(0.15), {0.3, 0.5, 0.5}),
                                             makeTranslated(makeSphere(0.15), {0.7, 0.5, 0.5})),
                                     d);
        ASSERT_TRUE(test::closedOrientedManifold(m));
        EXPECT_EQ(test::eulerCharacteristic(m), 4);
        EXPECT_EQ(test::componentCount(m), 2u);
    }
}

TEST(SurfaceNets, ThousandRandomShapesAndCarvingsAreClosedOrientedManifold) {
    util::ThreadPool pool;
    std::mutex mutex;
    std::vector<std::string> failures;
    std::vector<std::pair<std::size_t, std::string>> embeddingFailures;  // (case, message)
    SurfaceNetsStats total;
    // Embedding (tests/support/mesh_intersections.h): per defect, the sum over meshes and the
    // number of meshes that have it; meshes whose welded form is not closed manifold.
    std::array<std::size_t, test::kMeshDefectKinds> defects{}, meshesWith{};
    std::size_t notWeldable = 0, tangled = 0;
    double largestMoveCells = 0.0;
    std::size_t meshes = 0, triangles = 0;
    const std::size_t kShapes = 700, kCarvings = 300;
    pool.parallelFor(kShapes + kCarvings, [&](std::size_t i) {
        std::mt19937_64 rng(1000 + i);
        std::uniform_real_distribution<double> u(0.0, 1.0);
        const Domain d = unitDomain(5 + int(i % 3), 2 + int(i % 2));
        SourcePtr shape = test::randomShape(rng);
        AdfPtr a = generate(*shape, d, GenerationSettings{});
        if (i >= kShapes) {
            // Random carvings and additions through local regeneration of the old field.
            const int edits = 1 + int(u(rng) * 4);
            for (int e = 0; e < edits; ++e) {
                const glm::dvec3 c(0.3 + 0.4 * u(rng), 0.3 + 0.4 * u(rng), 0.3 + 0.4 * u(rng));
                const double r = 0.02 + 0.1 * u(rng);
                const BoxWorld region{c - glm::dvec3(r + 0.02), c + glm::dvec3(r + 0.02)};
                const SourcePtr old = makeAdfSource(a);
                const SourcePtr tool = makeTranslated(makeSphere(r), c);
                const SourcePtr edited =
                    makeCsg(u(rng) < 0.7 ? CsgOp::Difference : CsgOp::Union, old, tool);
                a = regenerate(*a, *makeRegionLimited(old, edited, region), region);
            }
        }
        SurfaceNetsStats st;
        const MeshBuffers m = mesh::meshAdf(a, nullptr, &st);
        const ::testing::AssertionResult ok = test::closedOrientedManifold(m);
        // What an export writes: the mesh untangled (mesh/mesh_untangle.h).
        MeshBuffers written = m;
        const mesh::UntangleReport untangled = mesh::untangle(written);
        const test::MeshIntersections embedding = test::findMeshIntersections(written);
        const ::testing::AssertionResult welded = test::weldsToClosedManifold(written);
        const double moveCells = untangled.largestMove / d.finestCellSize();
        std::lock_guard lock(mutex);
        ++meshes;
        triangles += m.triangleCount();
        total.multiSheetCells += st.multiSheetCells;
        total.multiCrossingFaces += st.multiCrossingFaces;
        total.oddFaces += st.oddFaces;
        total.signlessCells += st.signlessCells;
        total.splitEdges += st.splitEdges;
        total.openCrossings += st.openCrossings;
        if (!ok) failures.push_back("case " + std::to_string(i) + ": " + ok.message());
        for (std::size_t k = 0; k < defects.size(); ++k) {
            defects[k] += embedding.count(test::MeshDefect(k));
            meshesWith[k] += embedding.count(test::MeshDefect(k)) > 0;
        }
        notWeldable += !welded;
        tangled += untangled.contacts + untangled.coincidentVertices > 0;
        largestMoveCells = std::max(largestMoveCells, moveCells);
        if (!embedding.clean() || !welded || moveCells > 8.0)
            embeddingFailures.emplace_back(i, "case " + std::to_string(i) + " (level " + std::to_string(d.maxLevel) +
                                                  "): " + (embedding.clean() ? "" : embedding.describe(written) + "\n") +
                                                  (welded ? "" : welded.message()) + " untangling moved a vertex " +
                                                  std::to_string(moveCells) + " cells");
    });
    EXPECT_EQ(meshes, kShapes + kCarvings);
    EXPECT_GT(triangles, 1000000u);
    for (std::size_t i = 0; i < std::min<std::size_t>(failures.size(), 10); ++i) ADD_FAILURE() << failures[i];
    EXPECT_TRUE(failures.empty()) << failures.size() << " of " << meshes << " meshes failed";
    // Embedded once untangled: no coincident vertices, no triangles meeting but along what they
    // share, and closed manifold once welded by position; the repair stays local.
    std::sort(embeddingFailures.begin(), embeddingFailures.end());
    for (std::size_t i = 0; i < std::min<std::size_t>(embeddingFailures.size(), 5); ++i)
        ADD_FAILURE() << embeddingFailures[i].second;
    EXPECT_TRUE(embeddingFailures.empty())
        << embeddingFailures.size() << " of " << meshes << " meshes are not embedded: " << defects[0]
        << " coincident vertex groups (" << meshesWith[0] << " meshes), " << defects[1] << " degenerate triangles ("
        << meshesWith[1] << "), " << defects[2] << " duplicate triangle pairs (" << meshesWith[2] << "), " << defects[3]
        << " folded edges (" << meshesWith[3] << "), " << defects[4] << " pairs meeting beside a shared vertex ("
        << meshesWith[4] << "), " << defects[5] << " intersecting pairs (" << meshesWith[5] << "); " << notWeldable
        << " not closed manifold once welded";
    EXPECT_EQ(total.oddFaces, 0u);
    EXPECT_EQ(total.openCrossings, 0u);
    // The corpus exercises the hard cases, or the guarantee above would be untested.
    EXPECT_GT(total.multiSheetCells, 0u);
    EXPECT_GT(total.multiCrossingFaces, 0u);
    EXPECT_GT(total.signlessCells, 0u);
    EXPECT_GT(total.splitEdges, 0u);
    std::printf("%zu meshes, %zu triangles, %zu multi-sheet cells, %zu faces with 4+ crossings, %zu figure-9B cells, %zu split edges\n",
                meshes, triangles, total.multiSheetCells, total.multiCrossingFaces, total.signlessCells,
                total.splitEdges);
    std::printf("untangling: %zu meshes had contacts or coincident vertices; the largest move %.2f finest cells\n",
                tangled, largestMoveCells);
    std::printf("embedding: %zu meshes fail; coincident vertex groups %zu (%zu meshes), degenerate triangles %zu (%zu), "
                "duplicate pairs %zu (%zu), folded edges %zu (%zu), meeting beside a shared vertex %zu (%zu), "
                "intersecting pairs %zu (%zu); %zu not closed manifold once welded\n",
                embeddingFailures.size(), defects[0], meshesWith[0], defects[1], meshesWith[1], defects[2],
                meshesWith[2], defects[3], meshesWith[3], defects[4], meshesWith[4], defects[5], meshesWith[5],
                notWeldable);
}

TEST(SurfaceNets, SerialAndParallelMeshesAreIdentical) {
    util::ThreadPool pool(4);
    const Domain d = testPartDomain(8);
    const AdfPtr a = generate(*makeTestPart(d), d, testPartSettings(), &pool);
    const MeshBuffers s = mesh::meshAdf(a, nullptr), p = mesh::meshAdf(a, &pool);
    EXPECT_EQ(s.positions, p.positions);
    EXPECT_EQ(s.normals, p.normals);
    EXPECT_EQ(s.indices, p.indices);
    EXPECT_TRUE(test::closedOrientedManifold(s));
}

TEST(SurfaceNets, TestPartMeshIsClosedManifoldAndCloseToTheField) {
    const Domain d = testPartDomain(9);
    util::ThreadPool pool;
    const AdfPtr a = generate(*makeTestPart(d), d, testPartSettings(), &pool);
    const MeshBuffers m = mesh::meshAdf(a, &pool);
    ASSERT_TRUE(test::closedOrientedManifold(m));
    const SourcePtr part = makeTestPart(d);
    double worst = 0.0;
    for (const glm::vec3& p : m.positions) worst = std::max(worst, std::abs(part->distance(glm::dvec3(p))));
    EXPECT_LT(worst, 1.0 * d.finestCellSize());
}

TEST(SurfaceNets, IncrementalRemeshEqualsFullMeshAcrossTileCorners) {
    const Domain d = unitDomain(7, 3);  // 8-cell tiles: edits straddle many tile borders
    util::ThreadPool pool(3);
    const SourcePtr part = makeCsg(CsgOp::Union, makeTranslated(makeRoundedBox({0.3, 0.2, 0.15}, 0.03), glm::dvec3(0.5)),
                                   makeTranslated(makeSphere(0.12), {0.5, 0.5, 0.66}));
    AdfPtr a = generate(*part, d, GenerationSettings{}, &pool);
    SurfaceMesher mesher(&pool);
    mesher.build(a);
    const std::size_t allTiles = mesher.stats().tilesMeshed;
    const double cell = d.finestCellSize(), tile = 8 * cell;
    struct Edit {
        glm::dvec3 centre;
        double radius;
        CsgOp op;
    };
    // Centres on tile corners on the top face, a side face, an addition, and a cut that removes
    // the top of the sphere; each straddles 8 tiles.
    const std::vector<Edit> edits{{{8 * tile, 8 * tile, 0.65 + 0.0}, 0.05, CsgOp::Difference},
                                  {{6 * tile, 8 * tile, 0.5 + 0.15}, 0.03, CsgOp::Difference},
                                  {{0.8, 5 * tile, 7 * tile}, 0.04, CsgOp::Difference},
                                  {{10 * tile, 10 * tile, 0.67}, 0.05, CsgOp::Union},
                                  {{0.5, 0.5, 0.78}, 0.06, CsgOp::Difference}};
    for (std::size_t i = 0; i < edits.size(); ++i) {
        const Edit& e = edits[i];
        const BoxWorld region{e.centre - glm::dvec3(e.radius + 2 * cell), e.centre + glm::dvec3(e.radius + 2 * cell)};
        const SourcePtr old = makeAdfSource(a);
        const SourcePtr next = makeCsg(e.op, old, makeTranslated(makeSphere(e.radius), e.centre));
        a = regenerate(*a, *makeRegionLimited(old, next, region), region, &pool);
        mesher.update(a);
        const SurfaceNetsStats inc = mesher.stats();
        const MeshBuffers spliced = mesher.mesh();
        SurfaceNetsStats full;
        const MeshBuffers fresh = mesh::meshAdf(a, &pool, &full);
        ASSERT_TRUE(test::closedOrientedManifold(spliced)) << "edit " << i;
        EXPECT_EQ(spliced.triangleCount(), fresh.triangleCount()) << "edit " << i;
        EXPECT_TRUE(test::canonical(spliced) == test::canonical(fresh)) << "edit " << i;
        // Totals are carried by deltas over the visited tiles: they must still be the whole mesh's.
        EXPECT_EQ(inc.crossings, full.crossings) << "edit " << i;
        EXPECT_EQ(inc.vertices, full.vertices) << "edit " << i;
        EXPECT_EQ(inc.splitEdges, full.splitEdges) << "edit " << i;
        EXPECT_LT(inc.tilesMeshed, allTiles / 2) << "edit " << i << " re-meshed too much";
        EXPECT_GT(inc.tilesMeshed, 0u);
    }
}

TEST(SurfaceNets, UpdatesBetweenUnrelatedSnapshotsWithCoarseTilesEqualAFullMesh) {
    // Crossings do not store which tiles hold their ring cells: an update takes them from the
    // old snapshot for the crossings it removes and from the new one for those it adds. Here
    // whole regions go from coarse tiles (empty space) to fine ones and back.
    const Domain d = unitDomain(7, 3);
    util::ThreadPool pool(2);
    const SourcePtr left = makeTranslated(makeSphere(0.13), {0.3, 0.32, 0.3});
    const SourcePtr right = makeTranslated(makeTorus(0.12, 0.05), {0.68, 0.7, 0.66});
    const std::vector<SourcePtr> shapes{left, makeCsg(CsgOp::Union, left, right), right,
                                        makeTranslated(makeBox({0.45, 0.45, 0.04}), glm::dvec3(0.5)), left};
    SurfaceMesher mesher(&pool);
    std::size_t coarse = 0;
    for (std::size_t i = 0; i < shapes.size(); ++i) {
        const AdfPtr a = generate(*shapes[i], d, GenerationSettings{}, &pool);
        coarse += a->computeStats().coarseTiles;
        if (i == 0) {
            mesher.build(a);
            continue;
        }
        mesher.update(a);
        const MeshBuffers spliced = mesher.mesh();
        const MeshBuffers fresh = mesh::meshAdf(a, &pool);
        ASSERT_TRUE(test::closedOrientedManifold(spliced)) << "snapshot " << i;
        EXPECT_TRUE(test::canonical(spliced) == test::canonical(fresh)) << "snapshot " << i;
    }
    EXPECT_GT(coarse, 0u) << "no snapshot had coarse tiles: the case is untested";
}

TEST(SurfaceNets, AtLevelThirteenAndAboveNeighbouringTilesAreFoundByKey) {
    // A build finds a tile's neighbours through a table of every slot up to level 12, and
    // through a map of tile keys beyond (2^21 slots at level 13): a small sphere on the corner
    // of 8 tiles, meshed closed, shows the map finds them.
    const Domain d = unitDomain(13, 6);
    ASSERT_GT(uint64_t(d.slotsPerAxis()) * d.slotsPerAxis() * d.slotsPerAxis(), uint64_t(1) << 18);
    util::ThreadPool pool(2);
    const double tile = d.finestCellSize() * 64;
    SurfaceNetsStats st;
    const MeshBuffers m = meshOf(makeTranslated(makeSphere(0.004), {64 * tile + 1e-5, 64 * tile - 2e-5, 64 * tile + 3e-5}), d, &st, &pool);
    ASSERT_GT(m.triangleCount(), 1000u);
    EXPECT_GE(st.tilesMeshed, 8u);
    EXPECT_TRUE(test::closedOrientedManifold(m));
    EXPECT_EQ(test::eulerCharacteristic(m), 2);
}

TEST(SurfaceNets, TilesWiderThanSixtyFourLatticeUnitsMeshAndUpdateLikeAFreshBuild) {
    // Tiles of up to 64 lattice units a side number their cells and find their leaves through
    // a table of places; wider ones (7- and 8-level tiles) through a hash map and the leaf
    // locator alone. Those paths must give closed meshes, the same serially and in parallel,
    // and updates equal to fresh builds.
    util::ThreadPool pool(2);
    for (const auto& [level, span] : {std::pair{8, 7}, std::pair{9, 8}, std::pair{8, 8}}) {
        const Domain d = unitDomain(level, span);
        const SourcePtr shape = makeCsg(CsgOp::Union, makeTranslated(makeTorus(0.22, 0.07), {0.49, 0.5, 0.52}),
                                        makeTranslated(makeSphere(0.1), {0.5, 0.51, 0.5}));
        AdfPtr a = generate(*shape, d, GenerationSettings{}, &pool);
        const MeshBuffers serial = mesh::meshAdf(a, nullptr), parallel = mesh::meshAdf(a, &pool);
        ASSERT_TRUE(test::closedOrientedManifold(parallel)) << "level " << level << " span " << span;
        EXPECT_TRUE(test::canonical(serial) == test::canonical(parallel)) << "level " << level << " span " << span;
        SurfaceMesher mesher(&pool);
        mesher.build(a);
        const glm::dvec3 dabs[] = {{0.5, 0.5, 0.61}, {0.71, 0.5, 0.52}, {0.5, 0.29, 0.55}};
        for (std::size_t i = 0; i < 3; ++i) {
            a = dabbed(a, i == 1 ? CsgOp::Union : CsgOp::Difference, dabs[i], 0.04, &pool);
            mesher.update(a);
            const MeshBuffers spliced = mesher.mesh();
            EXPECT_TRUE(test::closedOrientedManifold(spliced)) << "level " << level << " span " << span << " dab " << i;
            EXPECT_TRUE(test::canonical(spliced) == test::canonical(mesh::meshAdf(a, &pool)))
                << "level " << level << " span " << span << " dab " << i;
        }
    }
}

TEST(SurfaceNets, ASurfaceLeavingTheDomainMeshesOpenThereAndUpdatesEqualAFullMesh) {
    // Spheres through the domain's faces and along an edge, and two smaller than a cell at its
    // corners: crossings there are left open, and a boundary leaf whose only sign changes lie
    // on the domain's border gets no vertex, nor an entry in its tile's cell index (one corner's
    // tile holds another sphere, so the tile stays, and the dab at that corner re-meshes the
    // cell: a stale entry would release the other sphere's vertex).
    const Domain d = unitDomain(6, 3);
    const double h = d.finestCellSize();
    util::ThreadPool pool(2);
    SourcePtr part = makeCsg(CsgOp::Union, makeTranslated(makeSphere(0.2), {0.5, 0.5, 0.03}),
                             makeTranslated(makeSphere(0.15), {0.0, 0.0, 0.5}));
    for (const glm::dvec3 corner : {glm::dvec3(0.0), glm::dvec3(1.0)})
        part = makeCsg(CsgOp::Union, part, makeTranslated(makeSphere(0.6 * h), corner));
    part = makeCsg(CsgOp::Union, part, makeTranslated(makeSphere(2.2 * h), glm::dvec3(4.5 * h)));
    AdfPtr a = generate(*part, d, GenerationSettings{}, &pool);
    SurfaceMesher mesher(&pool);
    mesher.build(a);
    EXPECT_GT(mesher.stats().openCrossings, 0u);
    const MeshBuffers built = mesher.mesh();
    ASSERT_GT(built.triangleCount(), 100u);
    EXPECT_TRUE(built.valid());
    for (std::size_t t = 0; t < built.triangleCount(); ++t) {
        const uint32_t* v = &built.indices[3 * t];
        EXPECT_TRUE(v[0] != v[1] && v[1] != v[2] && v[2] != v[0]) << "triangle " << t;
    }
    // Dabs across the faces, and at the corners: the cells that had no vertex get one.
    const std::vector<std::pair<glm::dvec3, double>> dabs{
        {{0.55, 0.5, 0.0}, 4 * h}, {{0.0, 0.1, 0.5}, 4 * h}, {{0.3, 0.5, 0.02}, 4 * h}, {glm::dvec3(0.0), 1.5 * h},
        {glm::dvec3(1.0), 1.5 * h}};
    for (const auto& [c, r] : dabs) {
        a = dabbed(a, r < 2 * h ? CsgOp::Union : CsgOp::Difference, c, r, &pool);
        mesher.update(a);
        const MeshBuffers spliced = mesher.mesh();
        const MeshBuffers fresh = mesh::meshAdf(a, &pool);
        EXPECT_EQ(spliced.triangleCount(), fresh.triangleCount());
        EXPECT_TRUE(test::canonical(spliced) == test::canonical(fresh)) << "dab at " << c.x << " " << c.y << " " << c.z;
    }
}

TEST(SurfaceNets, UpdateWithTheSameSnapshotChangesNothingAndEmptyFieldsGiveEmptyMeshes) {
    const Domain d = unitDomain(6, 3);
    const AdfPtr a = generate(*makeTranslated(makeSphere(0.2), glm::dvec3(0.5)), d, GenerationSettings{});
    SurfaceMesher mesher;
    mesher.build(a);
    const MeshBuffers before = mesher.mesh();
    mesher.update(a);
    EXPECT_EQ(mesher.stats().tilesMeshed, 0u);
    EXPECT_TRUE(test::canonical(mesher.mesh()) == test::canonical(before));
    // Everything carved away: the mesh becomes empty; and comes back.
    const AdfPtr empty = generate(*makeTranslated(makeSphere(0.2), glm::dvec3(5.0)), d, GenerationSettings{});
    mesher.update(empty);
    EXPECT_EQ(mesher.mesh().triangleCount(), 0u);
    mesher.update(a);
    EXPECT_TRUE(test::canonical(mesher.mesh()) == test::canonical(before));
}

/// Tiles of `b` that replace a tile of `a` at the same slot with another quantisation scale.
std::size_t tilesWithNewScale(const Adf& a, const Adf& b) {
    std::size_t n = 0;
    const uint32_t shift = uint32_t(b.domain().maxLevel - b.domain().tileLevel());
    b.forEachTile([&](const Tile& t) {
        const Tile* old = a.tileAtSlot(t.latticeOrigin() >> shift);
        if (old != &t && old->level() == t.level() && old->scale() != t.scale()) ++n;
    });
    return n;
}

/// After `mesher` (on a pool) and `serial` were both updated to `a`: the spliced mesh is closed
/// and manifold, equals a full mesh of `a` (counts, and canonically), and the two updates agree
/// bit for bit.
void expectSplicedEqualsFull(const SurfaceMesher& mesher, const SurfaceMesher& serial, const AdfPtr& a,
                             util::ThreadPool& pool, int edit) {
    SurfaceNetsStats full;
    const MeshBuffers spliced = mesher.mesh(), fresh = mesh::meshAdf(a, &pool, &full);
    ASSERT_TRUE(test::closedOrientedManifold(spliced)) << "edit " << edit;
    EXPECT_EQ(mesher.stats().crossings, full.crossings) << "edit " << edit;
    EXPECT_EQ(mesher.stats().vertices, full.vertices) << "edit " << edit;
    EXPECT_EQ(mesher.stats().splitEdges, full.splitEdges) << "edit " << edit;
    ASSERT_TRUE(test::canonical(spliced) == test::canonical(fresh)) << "edit " << edit;
    const MeshBuffers s = serial.mesh();
    ASSERT_EQ(s.positions, spliced.positions) << "edit " << edit;
    ASSERT_EQ(s.normals, spliced.normals) << "edit " << edit;
    ASSERT_EQ(s.indices, spliced.indices) << "edit " << edit;
}

/// A rounded block in 8-cell tiles, meshed by a mesher on a pool and by a serial one; each dab
/// edits it, updates both and checks the splice (expectSplicedEqualsFull).
struct DabbedBlock {
    explicit DabbedBlock(unsigned threads)
        : pool(threads),
          a(generate(*makeTranslated(makeRoundedBox({0.3, 0.25, 0.2}, 0.03), glm::dvec3(0.5)), d, GenerationSettings{},
                     &pool)),
          mesher(&pool) {
        mesher.build(a);
        serial.build(a);
    }
    void dab(CsgOp op, glm::dvec3 c, double r, int edit) {
        a = dabbed(a, op, c, r, &pool);
        mesher.update(a);
        serial.update(a);
        expectSplicedEqualsFull(mesher, serial, a, pool, edit);
    }
    const Domain d = unitDomain(7, 3);
    const double cell = d.finestCellSize(), tile = 8 * cell;
    util::ThreadPool pool;
    AdfPtr a;
    SurfaceMesher mesher, serial;
};

TEST(SurfaceNets, RepeatedDabsAtTileCornersAndNewTileScalesEqualAFullMesh) {
    // The sub-tile update must not reuse anything stale: a rebuilt tile whose quantisation scale
    // changed decodes different floats in cells the edit never touched, and dabs repeated around
    // one tile corner re-mesh the same cells over and over (released slots get reused).
    DabbedBlock b(3);
    const double cell = b.cell, tile = b.tile;
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::size_t rescaled = 0;
    for (int i = 0; i < 24; ++i) {
        glm::dvec3 c;
        double r;
        CsgOp op = i % 5 == 4 ? CsgOp::Union : CsgOp::Difference;
        if (i % 3 == 2) {
            // Deep cuts into the block's core: tiles there lose their largest values, so their
            // scale changes while most of their cells are copied.
            c = glm::dvec3(0.5 + 0.1 * u(rng), 0.5 + 0.1 * u(rng), 0.5 + 0.05 * u(rng));
            r = 0.06 + 0.02 * u(rng);
            op = CsgOp::Difference;
        } else {
            // Small dabs on the top face around two tile corners.
            const double corner = i % 2 ? 8 * tile : 9 * tile;
            c = glm::dvec3(corner + 1.5 * cell * u(rng), corner + 1.5 * cell * u(rng), 0.7 + cell * u(rng));
            r = 2.5 * cell + cell * u(rng);
        }
        const AdfPtr before = b.a;
        ASSERT_NO_FATAL_FAILURE(b.dab(op, c, r, i));
        rescaled += tilesWithNewScale(*before, *b.a);
    }
    EXPECT_GT(rescaled, 0u) << "no edit changed a tile's quantisation scale: the case is untested";
}

TEST(SurfaceNets, UpdatesReuseTheCrossingRecordsEarlierUpdatesReleased) {
    // A dab carved and filled again and again at one spot replaces the same crossings each
    // time: their records must be reused (a session would otherwise hold every record it ever
    // made), and reusing them must leave the mesh what a full build gives.
    DabbedBlock b(2);
    EXPECT_EQ(b.mesher.stats().crossingSlots, b.mesher.stats().crossings);  // a build holds no spare record
    const glm::dvec3 spot(0.47, 0.52, 0.7);
    std::size_t slotsAfterWarmUp = 0, mostComputed = 0;
    for (int i = 0; i < 24; ++i) {
        ASSERT_NO_FATAL_FAILURE(b.dab(i % 2 ? CsgOp::Union : CsgOp::Difference, spot, (3.0 + 0.25 * (i % 3)) * b.cell, i));
        const SurfaceNetsStats& st = b.mesher.stats();
        EXPECT_GE(st.crossingSlots, st.crossings) << "edit " << i;
        mostComputed = std::max(mostComputed, st.crossingsComputed);
        if (i == 3) slotsAfterWarmUp = st.crossingSlots;
    }
    ASSERT_GT(mostComputed, 50u) << "the dabs changed too little to test reuse";
    // Without reuse every update adds the records it replaced (here 20 updates took 7,175 records
    // to 9,350; with reuse, to 7,132).
    EXPECT_LE(b.mesher.stats().crossingSlots, slotsAfterWarmUp + mostComputed);
}

TEST(SurfaceNets, ASmallDabInsideATileRecomputesFewOfItsVertices) {
    // Counters, not time: the update's work follows the changed cells, not the tile. A dab that
    // changes its tile's quantisation scale changes every cell of it (re-meshed, rightly, by the
    // test above), so this one takes the first of a few dabs that keeps every scale.
    const Domain d = testPartDomain(10);  // 64-cell tiles, as in the app
    const SourcePtr part = makeTestPart(d);
    const AdfPtr base = generate(*part, d, testPartSettings());
    const MeshBuffers surface = mesh::meshAdf(base);
    const double cell = d.finestCellSize(), tileWorld = 64 * cell;
    // Dabs on the tile holding the most vertices, well inside it.
    auto slotOf = [&](const glm::vec3& p) {
        const glm::uvec3 s((glm::dvec3(p) - d.originWorld) / tileWorld);
        return uint64_t(s.x) | (uint64_t(s.y) << 20) | (uint64_t(s.z) << 40);
    };
    std::map<uint64_t, std::size_t> perTile;
    for (const glm::vec3& p : surface.positions) ++perTile[slotOf(p)];
    const uint64_t densest =
        std::max_element(perTile.begin(), perTile.end(), [](auto& l, auto& r) { return l.second < r.second; })->first;
    bool tested = false;
    for (std::size_t k = 0; k < surface.positions.size() && !tested; k += 13) {
        const glm::dvec3 c(surface.positions[k]);
        const glm::dvec3 inTileAt = (c - d.originWorld) / tileWorld - glm::floor((c - d.originWorld) / tileWorld);
        if (slotOf(surface.positions[k]) != densest || glm::any(glm::lessThan(inTileAt, glm::dvec3(0.3))) ||
            glm::any(glm::greaterThan(inTileAt, glm::dvec3(0.7))))
            continue;
        const AdfPtr a = dabbed(base, CsgOp::Difference, c, 2 * cell);
        if (tilesWithNewScale(*base, *a) > 0) continue;
        SurfaceMesher mesher;
        mesher.build(base);
        mesher.update(a);
        const SurfaceNetsStats inc = mesher.stats();
        const MeshBuffers full = mesh::meshAdf(a);
        ASSERT_TRUE(test::canonical(mesher.mesh()) == test::canonical(full));
        std::size_t inTile = 0;
        for (const glm::vec3& p : full.positions) inTile += slotOf(p) == densest;
        std::printf("dab: %zu changed cells; %zu vertices recomputed, %zu relaxed, %zu crossings computed; %zu vertices in its tile\n",
                    inc.changedCells, inc.verticesComputed, inc.verticesRelaxed, inc.crossingsComputed, inTile);
        EXPECT_GT(inc.verticesComputed, 0u);
        EXPECT_LT(inc.verticesComputed * 5, inTile);  // a whole-tile re-mesh recomputes all of them
        EXPECT_LT(inc.verticesRelaxed * 4, inTile);
        tested = true;
    }
    EXPECT_TRUE(tested) << "every dab changed a tile's scale";
}

TEST(SurfaceNets, DabsOnTheTestPartInTheAppsTilesEqualAFullMesh) {
    // The app's tiles (64 cells, where the update's changed-cell queries take their row-word
    // paths) and the bench's dab (radius 10 finest cells, carved and added at surface points):
    // every spliced mesh is the full mesh of its snapshot.
    const Domain d = testPartDomain(10);
    util::ThreadPool pool(2);
    AdfPtr a = generate(*makeTestPart(d), d, testPartSettings(), &pool);
    SurfaceMesher mesher(&pool);
    mesher.build(a);
    const MeshBuffers surface = mesher.mesh();
    for (int i = 0; i < 8; ++i) {
        const glm::dvec3 c(surface.positions[(std::size_t(i) * 7919) % surface.vertexCount()]);
        a = dabbed(a, i % 4 == 3 ? CsgOp::Union : CsgOp::Difference, c, 10 * d.finestCellSize(), &pool);
        mesher.update(a);
        ASSERT_TRUE(test::canonical(mesher.mesh()) == test::canonical(mesh::meshAdf(a, &pool))) << "dab " << i;
        EXPECT_GT(mesher.stats().cellsMeshed, 100u) << "dab " << i;
    }
}

}  // namespace
}  // namespace kizamu
