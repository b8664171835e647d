// SPDX-License-Identifier: Apache-2.0
// Readers query published snapshots while a writer regenerates regions continuously. Readers
// check every tile they touch (alive, version stamp, checksum) and must neither allocate nor
// free. Runs under ThreadSanitizer in scripts/test (label "concurrency").
#include "adf/adf_source.h"
#include "adf/generate.h"
#include "adf/snapshot_store.h"
#include "adf/test_part.h"
#include "tests/util/adf_compare.h"
#include "tests/util/counting_allocator.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <random>
#include <thread>
#include <vector>

using namespace kizamu;
using namespace kizamu::adf;

namespace {

struct ReaderReport {
    uint64_t reads = 0, tilesChecked = 0, badTiles = 0, versionRegressions = 0, nonFinite = 0;
    test::AllocationCounts during{};
};

/// A reader loop: nothing in here may allocate (no gtest macros, no containers).
void readerLoop(SnapshotStore& store, const std::atomic<bool>& stop, uint64_t seed, ReaderReport& out) {
    SnapshotStore::Reader reader(store);
    const test::AllocationCounts before = test::threadAllocationCounts();
    std::minstd_rand rng{uint32_t(seed)};
    uint64_t lastVersion = 0;
    ReaderReport r;
    while (!stop.load(std::memory_order_relaxed)) {
        const auto guard = reader.acquire();
        const Adf& adf = guard.adf();
        if (adf.version() < lastVersion) ++r.versionRegressions;
        lastVersion = adf.version();
        // Every tile this reader touches is checked: 4 by slot, and the 4 that queries land in.
        const uint32_t slots = adf.domain().slotsPerAxis();
        auto check = [&](const Tile* t) {
            ++r.tilesChecked;
            if (!t->alive() || t->version() > adf.version() || t->computeChecksum() != t->checksum()) ++r.badTiles;
        };
        for (int i = 0; i < 4; ++i) check(adf.tileAtSlot({rng() % slots, rng() % slots, rng() % slots}));
        const uint32_t n = adf.domain().latticeSize();
        for (int i = 0; i < 4; ++i) {
            const glm::uvec3 lattice(rng() % n, rng() % n, rng() % n);
            check(adf.findLeaf(lattice).tile);
            const glm::vec3 p = (glm::vec3(lattice) + 0.5f) * adf.metresPerLattice() + adf.originWorldF();
            const Sample s = adf.sample(p);
            if (!std::isfinite(s.distance)) ++r.nonFinite;
        }
        ++r.reads;
    }
    const test::AllocationCounts after = test::threadAllocationCounts();
    r.during = {after.allocations - before.allocations, after.frees - before.frees};
    out = r;
}

TEST(SnapshotStore, ReadersSeeWholeSnapshotsWhileTheWriterRegenerates) {
    const Domain d = testPartDomain(7);
    const SourcePtr part = makeTestPart(d);
    SnapshotStore store(generate(*part, d, testPartSettings()), 8);

    std::atomic<bool> stop{false};
    ReaderReport reports[2];
    std::thread readers[2];
    for (int i = 0; i < 2; ++i)
        readers[i] = std::thread(readerLoop, std::ref(store), std::cref(stop), 100 + i, std::ref(reports[i]));

    // Writer: carve and re-fill spheres at random places, each edit limited to its region.
    std::mt19937_64 rng(1);
    std::uniform_real_distribution<double> u(0.25, 0.75);
    SourcePtr current = part;
    const int edits = 30;
    for (int e = 0; e < edits; ++e) {
        const glm::dvec3 c(u(rng), u(rng), u(rng));
        const double r = 0.05;
        const BoxWorld region{c - (r + 0.02), c + (r + 0.02)};
        const auto tool = makeTranslated(makeSphere(r), c);
        const SourcePtr edited = makeRegionLimited(
            current, makeCsg(e % 2 ? CsgOp::Union : CsgOp::Difference, current, tool), region);
        store.publish(regenerate(*store.current(), *edited, region));
        current = edited;
    }
    stop = true;
    for (auto& t : readers) t.join();
    EXPECT_EQ(store.reclaim(), 0u) << "retired snapshots must all be freed once readers leave";
    EXPECT_EQ(store.current()->version(), uint64_t(edits + 1));

    for (const auto& r : reports) {
        EXPECT_GT(r.reads, 0u);
        EXPECT_EQ(r.badTiles, 0u);
        EXPECT_EQ(r.versionRegressions, 0u);
        EXPECT_EQ(r.nonFinite, 0u);
        EXPECT_EQ(r.during.allocations, 0u) << "a reader allocated";
        EXPECT_EQ(r.during.frees, 0u) << "a reader freed memory";
    }
}

TEST(SnapshotStore, AHeldSnapshotStaysAliveUntilItsReaderLeaves) {
    const Domain d = testPartDomain(6);
    const SourcePtr part = makeTestPart(d);
    SnapshotStore store(generate(*part, d, testPartSettings()), 4);
    SnapshotStore::Reader reader(store);
    std::weak_ptr<const Adf> first = store.current();
    {
        const auto guard = reader.acquire();
        for (int i = 0; i < 5; ++i) store.publish(generate(*part, d, testPartSettings()));
        EXPECT_EQ(store.retiredCount(), 5u);
        EXPECT_FALSE(first.expired());
        EXPECT_EQ(&guard.adf(), first.lock().get());
        const Tile* t = guard.adf().tileAtSlot({0, 0, 0});
        EXPECT_TRUE(t->alive());
    }
    EXPECT_EQ(store.reclaim(), 0u);
    EXPECT_TRUE(first.expired());
}

TEST(SnapshotStore, RefusesReadersBeyondItsSlots) {
    const Domain d = testPartDomain(5);
    SnapshotStore store(generate(*makeTestPart(d), d, testPartSettings()), 1);
    SnapshotStore::Reader one(store);
    EXPECT_THROW(SnapshotStore::Reader two(store), std::runtime_error);
}

}  // namespace
