// SPDX-License-Identifier: Apache-2.0
// SnapshotStore's sequence numbers and reclamation without publishing, and GuardedAccessor's
// binding to guards (single thread; the threaded checks are in tests/concurrency).
#include "adf/snapshot_store.h"
#include "adf/generate.h"
#include "adf/guarded_accessor.h"
#include "adf/test_part.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>

using namespace kizamu;
using namespace kizamu::adf;

namespace {

/// A sphere of `radius` m at the unit domain's centre, level 5: a tiny snapshot whose distance
/// at kProbe tells it apart from spheres of other radii.
AdfPtr sphere(double radius) {
    const Domain d = testPartDomain(5);
    return generate(*makeTranslated(makeSphere(radius), glm::dvec3(0.5)), d, testPartSettings());
}
const glm::vec3 kProbe(0.75f, 0.5f, 0.5f);  // 0.25 m from the centre

/// A guard on the heap, for guards released in another order than acquired.
struct HeldGuard {
    explicit HeldGuard(const SnapshotStore::Reader& r) : guard(r.acquire()) {}
    SnapshotStore::Reader::Guard guard;
};

TEST(SnapshotStoreSequence, StartsAtOneAndGrowsByOneOnEveryPublish) {
    const AdfPtr a = sphere(0.2), b = sphere(0.3);
    SnapshotStore store(a, 2);
    EXPECT_EQ(store.currentSequence(), SnapshotStore::kInitialSequence);
    EXPECT_EQ(SnapshotStore::kInitialSequence, 1u);
    SnapshotStore::Reader reader(store);
    {
        const auto g = reader.acquire();
        EXPECT_EQ(g.sequence(), 1u);
        EXPECT_EQ(&g.adf(), a.get());
    }
    // Republishing a snapshot (undo, redo) gives it a new number.
    const AdfPtr order[] = {b, a, a, b};
    uint64_t expected = 1;
    for (const AdfPtr& next : order) {
        EXPECT_EQ(store.publish(next), ++expected);
        EXPECT_EQ(store.currentSequence(), expected);
        EXPECT_EQ(store.current(), next);
        const auto g = reader.acquire();
        EXPECT_EQ(g.sequence(), expected);
        EXPECT_EQ(&g.adf(), next.get());
    }
    EXPECT_THROW(store.publish(nullptr), std::invalid_argument);
    EXPECT_EQ(store.currentSequence(), expected) << "a failed publish takes no number";
}

TEST(SnapshotStoreSequence, AHeldGuardKeepsItsSnapshotAndNumber) {
    const AdfPtr a = sphere(0.2), b = sphere(0.3);
    SnapshotStore store(a, 2);
    SnapshotStore::Reader reader(store);
    const auto g = reader.acquire();
    store.publish(b);
    store.publish(sphere(0.25));
    EXPECT_EQ(g.sequence(), 1u);
    EXPECT_EQ(&g.adf(), a.get());
    EXPECT_EQ(store.currentSequence(), 3u);
}

TEST(SnapshotStoreReclaim, FreesRetiredSnapshotsWithoutAPublishOnceTheirGuardsAreReleased) {
    SnapshotStore store(sphere(0.2), 4);
    SnapshotStore::Reader r1(store), r2(store);
    std::weak_ptr<const Adf> first = store.current();
    auto g1 = std::make_unique<HeldGuard>(r1);
    store.publish(sphere(0.25));
    std::weak_ptr<const Adf> second = store.current();
    auto g2 = std::make_unique<HeldGuard>(r2);  // sees the second
    store.publish(sphere(0.3));
    EXPECT_EQ(store.retiredCount(), 2u);
    EXPECT_EQ(store.reclaim(), 2u) << "both retired snapshots are still visible";

    g1.reset();  // the only guard that could see the first
    EXPECT_EQ(store.reclaim(), 1u);
    EXPECT_TRUE(first.expired());
    EXPECT_FALSE(second.expired());

    // A guard acquired after the retirement does not delay it.
    g1 = std::make_unique<HeldGuard>(r1);
    g2.reset();
    EXPECT_EQ(store.reclaim(), 0u);
    EXPECT_EQ(store.retiredCount(), 0u);
    EXPECT_TRUE(second.expired());
    EXPECT_EQ(store.reclaim(), 0u) << "reclaim with nothing retired is a no-op";
    g1.reset();
}

TEST(GuardedAccessor, SamplesTheGuardsSnapshot) {
    const AdfPtr a = sphere(0.2);
    SnapshotStore store(a, 2);
    SnapshotStore::Reader reader(store);
    const auto g = reader.acquire();
    GuardedAccessor acc(g);
    EXPECT_EQ(acc.sequence(), 1u);
    for (float dx : {0.0f, 0.01f, -0.02f, 0.1f}) {
        const glm::vec3 p = kProbe + glm::vec3(dx, 0.003f, -0.002f);
        const Sample s = acc.sample(g, p), ref = a->sample(p);
        EXPECT_NEAR(s.distance, ref.distance, 1e-6);
        for (int i = 0; i < 3; ++i) EXPECT_NEAR(s.gradient[i], ref.gradient[i], 1e-5);
    }
}

// The stale-cache check: the accessor's cached leaf holds decoded corners of the old snapshot,
// and the probe stays in that leaf, so a cache kept across the change would answer for the old.
TEST(GuardedAccessor, ANewSnapshotDropsTheCacheAndAnswersForTheNewOne) {
    const AdfPtr a = sphere(0.2), b = sphere(0.3);
    const float da = a->sample(kProbe).distance, db = b->sample(kProbe).distance;
    ASSERT_GT(std::abs(da - db), 0.05f);
    SnapshotStore store(a, 2);
    SnapshotStore::Reader reader(store);
    std::unique_ptr<GuardedAccessor> acc;
    {
        const auto g = reader.acquire();
        acc = std::make_unique<GuardedAccessor>(g);
        EXPECT_NEAR(acc->sample(g, kProbe).distance, da, 1e-6);
    }
    EXPECT_EQ(store.publish(b), 2u);
    EXPECT_EQ(store.reclaim(), 0u);
    {
        const auto g = reader.acquire();
        EXPECT_NEAR(acc->sample(g, kProbe).distance, db, 1e-6);
        EXPECT_EQ(acc->sequence(), 2u);
    }
    // Back to the first snapshot (undo): a new number, the cache is dropped again.
    EXPECT_EQ(store.publish(a), 3u);
    {
        const auto g = reader.acquire();
        EXPECT_NEAR(acc->sample(g, kProbe).distance, da, 1e-6);
        EXPECT_EQ(acc->sequence(), 3u);
        // Same snapshot on the next guard: the cache is kept, and still right.
    }
    {
        const auto g = reader.acquire();
        acc->bind(g);
        EXPECT_EQ(acc->sequence(), 3u);
        EXPECT_NEAR(acc->sample(g, kProbe).distance, da, 1e-6);
    }
}

#ifndef NDEBUG
TEST(GuardedAccessorDeathTest, RefusesAGuardOfAnotherReader) {
    GTEST_FLAG_SET(death_test_style, "threadsafe");
    SnapshotStore store(sphere(0.2), 2);
    SnapshotStore::Reader r1(store), r2(store);
    EXPECT_DEATH(
        {
            std::unique_ptr<GuardedAccessor> acc;
            {
                const auto g1 = r1.acquire();
                acc = std::make_unique<GuardedAccessor>(g1);
            }
            const auto g2 = r2.acquire();
            acc->sample(g2, kProbe);
        },
        "another Reader");
}
#endif

}  // namespace
