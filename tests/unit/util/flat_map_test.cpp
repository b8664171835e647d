// SPDX-License-Identifier: Apache-2.0
/// @file flat_map_test.cpp
/// @brief FlatMap64 against std::unordered_map under random inserts, overwrites, find-or-inserts
/// and erases; FlatMap<float>'s tryInsert (a cache filled on a miss) the same way.
#include "util/flat_map.h"

#include <gtest/gtest.h>

#include <random>
#include <unordered_map>

namespace kizamu::util {
namespace {

TEST(FlatMap64, RandomOperationsMatchAStandardMap) {
    for (const uint64_t seed : {1u, 2u, 3u}) {
        std::mt19937_64 rng(seed);
        // Few distinct keys, so probe runs collide, wrap around the table and get erased from.
        std::uniform_int_distribution<uint64_t> key(0, 3000);
        FlatMap64 map;
        std::unordered_map<uint64_t, uint32_t> ref;
        for (int i = 0; i < 200000; ++i) {
            const uint64_t k = key(rng) * 0x100000001ull;  // packed-lattice-like spread
            const int op = int(rng() % 3);
            if (op == 0) {
                const uint32_t v = uint32_t(rng());
                map.assign(k, v);
                ref[k] = v;
            } else if (op == 1) {  // the value kept, or this one inserted
                const uint32_t v = uint32_t(rng());
                ASSERT_EQ(map.findOrAssign(k, v), ref.emplace(k, v).first->second) << "seed " << seed << " step " << i;
            } else {
                map.erase(k);
                ref.erase(k);
            }
            if (i % 997 == 0) {
                ASSERT_EQ(map.size(), ref.size()) << "seed " << seed << " step " << i;
                for (uint64_t probe = 0; probe <= 3000; ++probe) {
                    const uint64_t pk = probe * 0x100000001ull;
                    const uint32_t* got = map.find(pk);
                    auto it = ref.find(pk);
                    ASSERT_EQ(got != nullptr, it != ref.end()) << "seed " << seed << " key " << probe;
                    if (got) {
                        ASSERT_EQ(*got, it->second);
                    }
                }
            }
        }
        map.clear();
        EXPECT_TRUE(map.empty());
        EXPECT_EQ(map.find(0), nullptr);
    }
}

TEST(FlatMap64, ReserveKeepsEntriesAndZeroIsAKey) {
    FlatMap64 map;
    map.assign(0, 7);  // the lattice origin's cell packs to 0
    map.reserve(1000);
    ASSERT_NE(map.find(0), nullptr);
    EXPECT_EQ(*map.find(0), 7u);
    map.erase(0);
    EXPECT_EQ(map.find(0), nullptr);
    EXPECT_EQ(map.size(), 0u);
}

TEST(FlatMap, TryInsertFillsAMissOnceAndFindsItAfterGrowing) {
    std::mt19937_64 rng(4);
    std::uniform_int_distribution<uint64_t> key(0, 5000);
    FlatMap<float> map;
    std::unordered_map<uint64_t, float> ref;
    for (int i = 0; i < 100000; ++i) {
        const uint64_t k = key(rng) * 0x100000001ull;
        const auto [value, inserted] = map.tryInsert(k, 0.0f);
        ASSERT_EQ(inserted, ref.find(k) == ref.end()) << "step " << i;
        if (inserted) {
            *value = float(i);  // filled in after the miss, as a sample cache does
            ref[k] = float(i);
        }
        ASSERT_EQ(*value, ref[k]) << "step " << i;
    }
    ASSERT_EQ(map.size(), ref.size());
    for (const auto& [k, v] : ref) {
        ASSERT_NE(map.find(k), nullptr);
        EXPECT_EQ(*map.find(k), v);
    }
}

}  // namespace
}  // namespace kizamu::util
