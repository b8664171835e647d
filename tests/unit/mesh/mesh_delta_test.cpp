// SPDX-License-Identifier: Apache-2.0
/// @file mesh_delta_test.cpp
/// @brief Mesh deltas: a consumer's mirror, fed by SurfaceMesher::takeDelta / fullDelta, equals
/// the mesher's mesh() canonically after every take (single and coalesced updates, removed
/// tiles, resync after missed deltas), and a small dab's delta holds few tiles.
#include "mesh/mesh_delta.h"

#include "adf/generate.h"
#include "adf/lattice.h"
#include "adf/test_part.h"
#include "mesh/surface_nets.h"
#include "tests/util/canonical_mesh.h"
#include "tests/util/dabbed.h"
#include "tests/util/random_shape.h"
#include "util/thread_pool.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <random>
#include <vector>

namespace kizamu {
namespace {

using namespace adf;
using mesh::MeshBuffers;
using mesh::MeshDelta;
using mesh::MeshMirror;
using mesh::SurfaceMesher;

using test::canonicalOf;

/// The test part at `level`, meshed, with a mirror fed by the mesher's first (reset) delta.
struct Session {
    explicit Session(int level, unsigned threads = 2)
        : pool(threads), d(testPartDomain(level)), a(generate(*makeTestPart(d), d, testPartSettings(), &pool)),
          mesher(&pool) {
        mesher.build(a);
        MeshDelta first = mesher.takeDelta();
        EXPECT_TRUE(first.reset);
        EXPECT_TRUE(mirror.apply(std::move(first)));
    }
    /// A dab of radius `cells` finest cells on a vertex of the current mesh picked by `rng`.
    void dab(std::mt19937_64& rng, CsgOp op, double cells) {
        const MeshBuffers m = mesher.mesh();
        const glm::vec3 p = m.positions[std::uniform_int_distribution<std::size_t>(0, m.positions.size() - 1)(rng)];
        a = dabbed(a, op, glm::dvec3(p), cells * d.finestCellSize(), &pool);
        mesher.update(a);
    }
    bool mirrorMatches() const { return canonicalOf(mirror.flatten()) == canonicalOf(mesher.mesh()); }

    util::ThreadPool pool;
    Domain d;
    AdfPtr a;
    SurfaceMesher mesher;
    MeshMirror mirror;
};

TEST(MeshDelta, AFullDeltaMirrorsABuild) {
    Session s(8);
    EXPECT_EQ(s.mirror.generation(), s.mesher.generation());
    EXPECT_TRUE(s.mirrorMatches());
    // A second mirror resynced from fullDelta() holds the same.
    MeshMirror other;
    MeshDelta full = s.mesher.fullDelta();
    EXPECT_TRUE(full.reset);
    EXPECT_TRUE(other.apply(std::move(full)));
    EXPECT_TRUE(canonicalOf(other.flatten()) == canonicalOf(s.mesher.mesh()));
    // Nothing changed since: an empty delta that follows.
    MeshDelta none = s.mesher.takeDelta();
    EXPECT_TRUE(none.empty());
    EXPECT_TRUE(s.mirror.apply(std::move(none)));
}

TEST(MeshDelta, TheMirrorFollowsRandomDabsOneTakeEach) {
    Session s(8);
    std::mt19937_64 rng(31);
    std::size_t mostTiles = 0, smallDabMostTiles = 0;
    for (int i = 0; i < 40; ++i) {
        const bool small = i % 4 != 3;
        s.dab(rng, i % 3 == 2 ? CsgOp::Union : CsgOp::Difference, small ? 2.5 : 9.0);
        MeshDelta delta = s.mesher.takeDelta();
        EXPECT_FALSE(delta.reset);
        EXPECT_EQ(delta.generation, s.mesher.generation());
        mostTiles = std::max(mostTiles, delta.tiles.size() + delta.removed.size());
        if (small) smallDabMostTiles = std::max(smallDabMostTiles, delta.tiles.size() + delta.removed.size());
        ASSERT_TRUE(s.mirror.apply(std::move(delta))) << "dab " << i;
        ASSERT_TRUE(s.mirrorMatches()) << "dab " << i;
    }
    EXPECT_GT(smallDabMostTiles, 0u);
    EXPECT_LT(smallDabMostTiles, 30u) << "a small dab's delta must stay local (64-cell tiles at level 8)";
    std::printf("tiles per delta: small dabs at most %zu, any at most %zu, mesh %zu tiles\n", smallDabMostTiles,
                mostTiles, s.mirror.tileCount());
}

TEST(MeshDelta, SmallTilesAndSerialMeshingFollowDabsAcrossTileCorners) {
    // 3-level tiles (8 cells a side): every dab straddles tile corners, so triangles join
    // vertices of three and four tiles and relaxation reaches tiles the edit did not rebuild.
    util::ThreadPool pool(2);
    Domain d;
    d.maxLevel = 7;
    d.tileSpanLevels = 3;
    AdfPtr a = generate(*makeTranslated(makeRoundedBox({0.3, 0.25, 0.2}, 0.03), glm::dvec3(0.5)), d,
                        GenerationSettings{}, &pool);
    for (util::ThreadPool* p : {&pool, static_cast<util::ThreadPool*>(nullptr)}) {
        SurfaceMesher mesher(p);
        mesher.build(a);
        MeshMirror mirror;
        ASSERT_TRUE(mirror.apply(mesher.takeDelta()));
        std::mt19937_64 rng(5);
        std::uniform_real_distribution<double> u(-1.0, 1.0);
        AdfPtr b = a;
        std::size_t fans = 0, splits = 0, notRebuilt = 0;
        for (int i = 0; i < 48; ++i) {
            const MeshBuffers m = mesher.mesh();
            const glm::vec3 c = m.positions[std::size_t(rng() % m.positions.size())];
            const double r = (2.0 + 3.0 * (u(rng) + 1.0)) * d.finestCellSize();
            b = dabbed(b, i % 5 == 4 ? CsgOp::Union : CsgOp::Difference, glm::dvec3(c), r, &pool);
            const AdfPtr before = mesher.snapshot();
            mesher.update(b);
            MeshDelta delta = mesher.takeDelta();
            for (const mesh::MeshTileShare& t : delta.tiles) {
                fans += t.fans.size();
                splits += t.splits.size();
                // A tile the edit shares with the last snapshot: changed by relaxation or by
                // its crossings' neighbours only.
                const glm::uvec3 slot = adf::unpackLattice(t.key) >> uint32_t(d.maxLevel - d.tileLevel());
                notRebuilt += b->tileAtSlot(slot) == before->tileAtSlot(slot);
            }
            ASSERT_TRUE(mirror.apply(std::move(delta))) << "dab " << i;
            ASSERT_TRUE(canonicalOf(mirror.flatten()) == canonicalOf(mesher.mesh())) << "dab " << i;
        }
        std::printf("fans %zu, split vertices %zu, shares of tiles not rebuilt %zu\n", fans, splits, notRebuilt);
        EXPECT_GT(notRebuilt, 0u) << "no delta held a tile the edit did not rebuild: the case is untested";
    }
}

TEST(MeshDelta, RandomShapesAndCarvingsWithSplitVerticesAndFans) {
    // Split vertices and fans (rare: doubled dual edges) are derived from other tiles' vertices;
    // random shapes carved at levels 5-7 with 4- and 8-cell tiles make enough of them.
    std::size_t cases = 0, fans = 0, splits = 0;
    for (std::size_t i = 0; i < 300 && (fans < 20 || cases < 40); ++i, ++cases) {
        std::mt19937_64 rng(1000 + i);
        std::uniform_real_distribution<double> u(0.0, 1.0);
        Domain d;
        d.maxLevel = 5 + int(i % 3);
        d.tileSpanLevels = 2 + int(i % 2);
        AdfPtr a = generate(*test::randomShape(rng), d, GenerationSettings{});
        SurfaceMesher mesher;
        mesher.build(a);
        MeshMirror mirror;
        ASSERT_TRUE(mirror.apply(mesher.takeDelta()));
        for (int e = 0; e < 5; ++e) {
            const glm::dvec3 c(0.3 + 0.4 * u(rng), 0.3 + 0.4 * u(rng), 0.3 + 0.4 * u(rng));
            a = dabbed(a, u(rng) < 0.7 ? CsgOp::Difference : CsgOp::Union, c, 0.02 + 0.1 * u(rng));
            mesher.update(a);
            MeshDelta delta = mesher.takeDelta();
            for (const mesh::MeshTileShare& t : delta.tiles) {
                fans += t.fans.size();
                splits += t.splits.size();
            }
            ASSERT_TRUE(mirror.apply(std::move(delta))) << "case " << i << " edit " << e;
            ASSERT_TRUE(canonicalOf(mirror.flatten()) == canonicalOf(mesher.mesh())) << "case " << i << " edit " << e;
        }
    }
    std::printf("%zu cases: %zu fans, %zu split vertices in deltas\n", cases, fans, splits);
    EXPECT_GT(fans, 0u) << "no fan in any delta: the case is untested";
}

TEST(MeshDelta, UpdatesCoalesceIntoOneTake) {
    Session s(8);
    std::mt19937_64 rng(77);
    for (int round = 0; round < 8; ++round) {
        const int updates = 2 + round % 4;
        for (int k = 0; k < updates; ++k) s.dab(rng, k % 2 ? CsgOp::Union : CsgOp::Difference, 2.0 + k);
        ASSERT_TRUE(s.mirror.apply(s.mesher.takeDelta())) << "round " << round;
        ASSERT_TRUE(s.mirrorMatches()) << "round " << round;
    }
    // Deltas taken one by one and coalesced by a mailbox the consumer did not empty.
    MeshDelta pending = s.mesher.takeDelta();
    for (int k = 0; k < 5; ++k) {
        s.dab(rng, k % 2 ? CsgOp::Union : CsgOp::Difference, 3.0);
        mesh::coalesce(pending, s.mesher.takeDelta());
    }
    EXPECT_EQ(pending.generation, s.mesher.generation());
    ASSERT_TRUE(s.mirror.apply(std::move(pending)));
    EXPECT_TRUE(s.mirrorMatches());
}

TEST(MeshDelta, CoalescingAndTheMirrorKeepTheNewestSampleTime) {
    mesh::MeshDelta older;
    older.reset = true;
    older.generation = 1;
    older.newestSampleNs = 500;
    mesh::MeshDelta newer;
    newer.base = 1;
    newer.generation = 2;
    mesh::coalesce(older, std::move(newer));
    EXPECT_EQ(older.newestSampleNs, 500) << "a delta with no samples keeps the older one's";
    mesh::MeshDelta reset;
    reset.reset = true;
    reset.generation = 3;
    reset.newestSampleNs = 200;
    mesh::coalesce(older, std::move(reset));
    EXPECT_EQ(older.newestSampleNs, 500);
    mesh::MeshMirror mirror;
    ASSERT_TRUE(mirror.apply(std::move(older)));
    EXPECT_EQ(mirror.newestSampleNs(), 500);
    mesh::MeshDelta next;
    next.base = 3;
    next.generation = 4;
    next.newestSampleNs = 900;
    ASSERT_TRUE(mirror.apply(std::move(next)));
    EXPECT_EQ(mirror.newestSampleNs(), 900);
}

TEST(MeshDelta, TilesCarvedAwayLeaveTheMirror) {
    // Two small spheres; carving one away whole drops its tiles from the mesher and the mirror.
    util::ThreadPool pool(2);
    const Domain d = testPartDomain(8);
    const glm::dvec3 gone(0.3, 0.3, 0.3), kept(0.7, 0.7, 0.7);
    AdfPtr a = generate(*makeCsg(CsgOp::Union, makeTranslated(makeSphere(0.06), gone),
                                 makeTranslated(makeSphere(0.06), kept)),
                        d, GenerationSettings{}, &pool);
    SurfaceMesher mesher(&pool);
    mesher.build(a);
    MeshMirror mirror;
    ASSERT_TRUE(mirror.apply(mesher.takeDelta()));
    const std::size_t tilesBefore = mirror.tileCount();
    a = dabbed(a, CsgOp::Difference, gone, 0.1, &pool);
    mesher.update(a);
    MeshDelta delta = mesher.takeDelta();
    ASSERT_FALSE(delta.removed.empty());
    const std::vector<uint64_t> removed = delta.removed;
    // (A removal may also name a tile the update made and dropped again: unknown to the mirror.)
    std::size_t known = 0;
    for (uint64_t k : removed) known += mirror.hasTile(k);
    EXPECT_GT(known, 0u);
    ASSERT_TRUE(mirror.apply(std::move(delta)));
    for (uint64_t k : removed) EXPECT_FALSE(mirror.hasTile(k));
    EXPECT_LT(mirror.tileCount(), tilesBefore);
    const MeshBuffers flat = mirror.flatten();
    EXPECT_TRUE(canonicalOf(flat) == canonicalOf(mesher.mesh()));
    for (const glm::vec3& p : flat.positions) EXPECT_GT(glm::length(glm::dvec3(p) - gone), 0.09);
    // Carving the other sphere away too leaves nothing.
    a = dabbed(a, CsgOp::Difference, kept, 0.1, &pool);
    mesher.update(a);
    ASSERT_TRUE(mirror.apply(mesher.takeDelta()));
    EXPECT_EQ(mirror.tileCount(), 0u);
    EXPECT_EQ(mirror.flatten().positions.size(), 0u);
}

TEST(MeshDelta, AMirrorThatMissedDeltasRefusesTheNextAndResyncs) {
    Session s(8);
    std::mt19937_64 rng(3);
    s.dab(rng, CsgOp::Difference, 4.0);
    MeshDelta missed = s.mesher.takeDelta();  // never delivered
    s.dab(rng, CsgOp::Union, 4.0);
    MeshDelta next = s.mesher.takeDelta();
    const uint64_t before = s.mirror.generation();
    EXPECT_FALSE(s.mirror.apply(std::move(next)));
    EXPECT_EQ(s.mirror.generation(), before);
    ASSERT_TRUE(s.mirror.apply(s.mesher.fullDelta()));
    EXPECT_TRUE(s.mirrorMatches());
    // Takes follow the resync.
    s.dab(rng, CsgOp::Difference, 3.0);
    ASSERT_TRUE(s.mirror.apply(s.mesher.takeDelta()));
    EXPECT_TRUE(s.mirrorMatches());
    // A rebuild (another snapshot) gives a reset delta.
    s.mesher.build(s.a);
    MeshDelta rebuilt = s.mesher.takeDelta();
    EXPECT_TRUE(rebuilt.reset);
    ASSERT_TRUE(s.mirror.apply(std::move(rebuilt)));
    EXPECT_TRUE(s.mirrorMatches());
}

}  // namespace
}  // namespace kizamu
