// SPDX-License-Identifier: Apache-2.0
// Readers query published snapshots while a writer regenerates regions continuously. Readers
// check every tile they touch (alive, version stamp, checksum) and must neither allocate nor
// free. Runs under ThreadSanitizer in scripts/test (label "concurrency").
#include "adf/snapshot_store.h"
#include "adf/adf_source.h"
#include "adf/generate.h"
#include "adf/guarded_accessor.h"
#include "adf/test_part.h"
#include "tests/util/adf_compare.h"
#include "tests/util/counting_allocator.h"

#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <cmath>
#include <optional>
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
void readerLoop(SnapshotStore& store, const std::atomic<bool>& stop, uint64_t seed,
                ReaderReport& out) {
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
            if (!t->alive() || t->version() > adf.version() ||
                t->computeChecksum() != t->checksum())
                ++r.badTiles;
        };
        for (int i = 0; i < 4; ++i)
            check(adf.tileAtSlot({rng() % slots, rng() % slots, rng() % slots}));
        const uint32_t n = adf.domain().latticeSize();
        for (int i = 0; i < 4; ++i) {
            const glm::uvec3 lattice(rng() % n, rng() % n, rng() % n);
            check(adf.findLeaf(lattice).tile);
            const glm::vec3 p =
                (glm::vec3(lattice) + 0.5f) * adf.metresPerLattice() + adf.originWorldF();
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
        readers[i] = std::thread(readerLoop, std::ref(store), std::cref(stop), 100 + i,
                                 std::ref(reports[i]));

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

// Sequence numbers under load: snapshot number s is kRing[(s - 1) % K], K spheres of different
// radii (generating thousands of snapshots would be slow; the rotation keeps the check: a wrong
// pairing or a stale cache answers with another radius).
struct SequenceReport {
    uint64_t guards = 0, rebinds = 0, regressions = 0, wrongSnapshot = 0, wrongDistance = 0;
    test::AllocationCounts during{};
};

TEST(SnapshotStore, SequenceNumbersGrowAndNameTheirSnapshotWhileTheWriterPublishes) {
    constexpr std::size_t kRing = 4;
    constexpr int kPublishes = 4000;
    const Domain d = testPartDomain(5);
    const glm::vec3 probe(0.75f, 0.5f, 0.5f);
    std::array<AdfPtr, kRing> ring;
    std::array<float, kRing> expected{};
    for (std::size_t k = 0; k < kRing; ++k) {
        ring[k] = generate(*makeTranslated(makeSphere(0.2 + 0.03 * double(k)), glm::dvec3(0.5)), d,
                           testPartSettings());
        expected[k] = ring[k]->sample(probe).distance;
        for (std::size_t j = 0; j < k; ++j) ASSERT_GT(std::abs(expected[k] - expected[j]), 0.01f);
    }
    SnapshotStore store(ring[0], 4);
    auto slotOf = [&](uint64_t seq) {
        return std::size_t((seq - SnapshotStore::kInitialSequence) % kRing);
    };

    std::atomic<bool> stop{false};
    std::atomic<int> started{0};
    std::atomic<uint64_t> progress[3] = {};  // guards so far, per reader
    SequenceReport reports[3];
    auto readerLoop = [&](int index, SequenceReport& out) {
        SnapshotStore::Reader reader(store);
        const test::AllocationCounts before = test::threadAllocationCounts();
        SequenceReport r;
        uint64_t last = 0;
        std::optional<GuardedAccessor> acc;  // engaged before the counted loop: no allocation
        {
            const auto g = reader.acquire();
            acc.emplace(g);
        }
        started.fetch_add(1);
        while (!stop.load(std::memory_order_relaxed)) {
            const auto g = reader.acquire();
            if (g.sequence() < last) ++r.regressions;
            r.rebinds += g.sequence() != acc->sequence();
            last = g.sequence();
            const std::size_t k = slotOf(g.sequence());
            if (&g.adf() != ring[k].get()) ++r.wrongSnapshot;
            // Twice: the second query hits the cache filled under this guard.
            for (int i = 0; i < 2; ++i)
                if (std::abs(acc->sample(g, probe).distance - expected[k]) > 1e-5f)
                    ++r.wrongDistance;
            progress[index].store(++r.guards, std::memory_order_relaxed);
        }
        const test::AllocationCounts after = test::threadAllocationCounts();
        r.during = {after.allocations - before.allocations, after.frees - before.frees};
        out = r;
    };
    std::thread readers[3];
    for (int i = 0; i < 3; ++i) readers[i] = std::thread(readerLoop, i, std::ref(reports[i]));

    // Publish kPublishes, and on until every reader has taken a few hundred guards (a loaded
    // machine may start a reader late), within a cap.
    while (started.load() < 3) std::this_thread::yield();
    auto readersBehind = [&] {
        for (const auto& p : progress)
            if (p.load(std::memory_order_relaxed) < 300) return true;
        return false;
    };
    uint64_t badNumbers = 0;
    for (int i = 1; i <= kPublishes || (readersBehind() && i <= 50 * kPublishes); ++i) {
        const uint64_t seq = store.publish(ring[std::size_t(i) % kRing]);
        badNumbers +=
            seq != SnapshotStore::kInitialSequence + uint64_t(i) || seq != store.currentSequence();
        if (i % 32 == 0) std::this_thread::yield();  // let readers see a good share of numbers
    }
    stop = true;
    for (auto& t : readers) t.join();
    EXPECT_EQ(badNumbers, 0u);

    // No publish from here: reclaim alone frees every retired snapshot once readers are gone.
    EXPECT_EQ(store.reclaim(), 0u);
    EXPECT_EQ(store.retiredCount(), 0u);
    for (std::size_t k = 0; k < kRing; ++k)
        EXPECT_EQ(ring[k].use_count(), store.current() == ring[k] ? 2 : 1)
            << "snapshot " << k << " still referenced";

    for (const auto& r : reports) {
        EXPECT_GT(r.guards, 0u);
        EXPECT_EQ(r.regressions, 0u) << "a reader saw a sequence number decrease";
        EXPECT_EQ(r.wrongSnapshot, 0u) << "a guard's sequence number named another snapshot";
        EXPECT_EQ(r.wrongDistance, 0u) << "a query answered for another snapshot (stale cache)";
        EXPECT_EQ(r.during.allocations, 0u) << "a reader allocated";
        EXPECT_EQ(r.during.frees, 0u) << "a reader freed memory";
    }
    const uint64_t rebinds = reports[0].rebinds + reports[1].rebinds + reports[2].rebinds;
    EXPECT_GT(rebinds, 0u) << "readers never saw a new snapshot: the test checked nothing";
}

// Readers that keep acquiring never hold back what was retired before their guards: the writer
// publishes once, then only reclaims, and the retired snapshot goes once the old guard is gone.
TEST(SnapshotStore, ReclaimWithoutPublishingFreesWhileReadersKeepAcquiring) {
    const Domain d = testPartDomain(5);
    const SourcePtr part = makeTestPart(d);
    SnapshotStore store(generate(*part, d, testPartSettings()), 4);
    std::weak_ptr<const Adf> first = store.current();
    std::atomic<bool> stop{false};
    std::atomic<uint64_t> guards{0};
    std::thread busy([&] {
        SnapshotStore::Reader reader(store);
        while (!stop.load(std::memory_order_relaxed)) {
            const auto g = reader.acquire();
            guards.fetch_add(1, std::memory_order_relaxed);
        }
    });
    while (guards.load() == 0) std::this_thread::yield();
    store.publish(generate(*part, d, testPartSettings()));
    // The busy reader may still hold a guard on the first snapshot for a moment; its next guard
    // sees the second, so a bounded number of reclaim() calls (each after a yield) frees it.
    int calls = 0;
    while (store.reclaim() != 0 && calls < 100000) {
        ++calls;
        std::this_thread::yield();
    }
    EXPECT_EQ(store.retiredCount(), 0u) << "after " << calls << " reclaim calls";
    EXPECT_TRUE(first.expired());
    stop = true;
    busy.join();
}

TEST(SnapshotStore, RefusesReadersBeyondItsSlots) {
    const Domain d = testPartDomain(5);
    SnapshotStore store(generate(*makeTestPart(d), d, testPartSettings()), 1);
    SnapshotStore::Reader one(store);
    EXPECT_THROW(SnapshotStore::Reader two(store), std::runtime_error);
}

}  // namespace
