// SPDX-License-Identifier: Apache-2.0
/// @file servo_stats_test.cpp
/// @brief LatencyHistogram buckets and quantiles on known inputs; ServoStats' counts and rate.
#include "haptics/servo_stats.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <random>

namespace kizamu::haptics {
namespace {

TEST(LatencyHistogram, EveryValueLiesInItsBucket) {
    std::mt19937_64 rng(3);
    for (int i = 0; i < 200'000; ++i) {
        const uint64_t v = i < 1000 ? uint64_t(i) : rng() >> (24 + rng() % 40);
        const std::size_t b = LatencyHistogram::bucketOf(v);
        ASSERT_LT(b, LatencyHistogram::kBuckets) << v;
        ASSERT_LE(LatencyHistogram::bucketLow(b), v) << v;
        ASSERT_LT(v, LatencyHistogram::bucketLow(b) + LatencyHistogram::bucketWidth(b)) << v;
        // at most 1/64 of the value wide
        ASSERT_LE(double(LatencyHistogram::bucketWidth(b)), std::max(1.0, double(v) / 64.0)) << v;
    }
    // Buckets tile the line: each starts where the previous ends.
    for (std::size_t i = 1; i < LatencyHistogram::kBuckets; ++i)
        ASSERT_EQ(LatencyHistogram::bucketLow(i), LatencyHistogram::bucketLow(i - 1) + LatencyHistogram::bucketWidth(i - 1)) << i;
    EXPECT_EQ(LatencyHistogram::bucketOf(~uint64_t(0)), LatencyHistogram::kBuckets - 1);
}

TEST(LatencyHistogram, QuantilesOfKnownInputs) {
    LatencyHistogram h;
    EXPECT_EQ(LatencyHistogram::quantileNs(h.buckets(), 0.5), 0.0);
    for (int us = 1; us <= 1000; ++us) h.record(int64_t(us) * 1000);  // 1..1000 µs, once each
    const std::vector<uint64_t> b = h.buckets();
    EXPECT_NEAR(LatencyHistogram::quantileNs(b, 0.5, h.maxNs()), 500e3, 500e3 * 0.01);
    EXPECT_NEAR(LatencyHistogram::quantileNs(b, 0.99, h.maxNs()), 990e3, 990e3 * 0.01);
    EXPECT_NEAR(LatencyHistogram::quantileNs(b, 0.999, h.maxNs()), 999e3, 999e3 * 0.01);
    EXPECT_LE(LatencyHistogram::quantileNs(b, 1.0, h.maxNs()), 1000e3);
    EXPECT_EQ(h.maxNs(), 1'000'000u);
    // Small values are exact; negative ones count as zero.
    LatencyHistogram s;
    for (int i = 0; i < 99; ++i) s.record(7);
    s.record(-5);
    EXPECT_EQ(LatencyHistogram::quantileNs(s.buckets(), 0.5), 7.0);
    EXPECT_EQ(LatencyHistogram::quantileNs(s.buckets(), 0.001), 0.0);
    s.clear();
    EXPECT_EQ(s.maxNs(), 0u);
    EXPECT_EQ(LatencyHistogram::quantileNs(s.buckets(), 0.5), 0.0);
}

TEST(LatencyHistogram, TailQuantileSeesRareOutliers) {
    LatencyHistogram h;
    for (int i = 0; i < 9980; ++i) h.record(20'000);  // 20 µs
    for (int i = 0; i < 20; ++i) h.record(400'000);   // 0.2 % at 400 µs
    const std::vector<uint64_t> b = h.buckets();
    EXPECT_NEAR(LatencyHistogram::quantileNs(b, 0.99, h.maxNs()), 20e3, 20e3 * 0.01);
    EXPECT_NEAR(LatencyHistogram::quantileNs(b, 0.999, h.maxNs()), 400e3, 400e3 * 0.01);
    EXPECT_EQ(h.maxNs(), 400'000u);
}

TEST(ServoStats, CountsRateAndSummary) {
    ServoStats s;
    for (int i = 0; i < 1001; ++i) s.recordTick(int64_t(i) * 1'000'000 + 5'000'000, 10'000 + i, 2'000, i % 100 == 0);
    s.countClamped();
    s.countNonFinite();
    s.countNonFinite();
    s.countDisconnect();
    s.countDisconnectedTick();
    s.countWatchdogTrip();
    const ServoSummary sum = s.summary();
    EXPECT_EQ(sum.counts.ticks, 1001u);
    EXPECT_EQ(sum.counts.missed, 11u);
    EXPECT_EQ(sum.counts.clamped, 1u);
    EXPECT_EQ(sum.counts.nonFinite, 2u);
    EXPECT_EQ(sum.counts.disconnects, 1u);
    EXPECT_EQ(sum.counts.disconnectedTicks, 1u);
    EXPECT_EQ(sum.counts.watchdogTrips, 1u);
    EXPECT_EQ(sum.counts.firstTickNs, 5'000'000);
    EXPECT_NEAR(sum.rateHz, 1000.0, 1e-6);
    EXPECT_NEAR(sum.missedFraction, 11.0 / 1001.0, 1e-12);
    EXPECT_NEAR(sum.periodErrorUs.p50, 10.5, 0.2);
    EXPECT_NEAR(sum.forceUs.p999, 2.0, 0.02);
    EXPECT_NEAR(sum.periodErrorUs.max, 11.0, 1e-9);
    s.clear();
    EXPECT_EQ(s.counts().ticks, 0u);
    EXPECT_EQ(s.summary().rateHz, 0.0);
}

TEST(ServoStats, NegativeForceTimeMeansNotComputed) {
    ServoStats s;
    s.recordTick(1, 0, -1, false);
    EXPECT_EQ(s.counts().ticks, 1u);
    EXPECT_EQ(s.forceTime().maxNs(), 0u);
    uint64_t n = 0;
    for (const uint64_t c : s.forceTime().buckets()) n += c;
    EXPECT_EQ(n, 0u);
}

}  // namespace
}  // namespace kizamu::haptics
