// SPDX-License-Identifier: Apache-2.0
// The progress line's arithmetic and throttle on a fake clock: the time left from the rate so
// far, the text, and at most one line per interval. (That nothing is drawn off a terminal or
// with --quiet is checked end to end in tests/cli/cli_test.sh.)
#include "app/progress.h"

#include <gtest/gtest.h>

#include <atomic>

using namespace kizamu::app;

TEST(Progress, TimeLeftFollowsTheRateSoFar) {
    EXPECT_FALSE(secondsLeft(0, 100, 10.0).has_value()) << "nothing done: no rate";
    EXPECT_FALSE(secondsLeft(5, 0, 10.0).has_value()) << "no total";
    EXPECT_FALSE(secondsLeft(5, 100, 0.4).has_value())
        << "under half a second: too little to go by";
    EXPECT_DOUBLE_EQ(*secondsLeft(25, 100, 10.0), 30.0);
    EXPECT_DOUBLE_EQ(*secondsLeft(1500, 2000, 90.0), 30.0);
    EXPECT_DOUBLE_EQ(*secondsLeft(100, 100, 10.0), 0.0);
    EXPECT_DOUBLE_EQ(*secondsLeft(120, 100, 10.0), 0.0) << "overshoot counts as done";
}

TEST(Progress, DurationsReadAsClockTimes) {
    EXPECT_EQ(formatDuration(0.0), "0:00");
    EXPECT_EQ(formatDuration(-3.0), "0:00");
    EXPECT_EQ(formatDuration(59.4), "0:59");
    EXPECT_EQ(formatDuration(59.6), "1:00");
    EXPECT_EQ(formatDuration(83.0), "1:23");
    EXPECT_EQ(formatDuration(3599.0), "59:59");
    EXPECT_EQ(formatDuration(3723.0), "1:02:03");
    EXPECT_EQ(formatDuration(36000.0), "10:00:00");
}

TEST(Progress, OneLineSaysWhatIsDoneAndWhatIsLeft) {
    EXPECT_EQ(progressText("replay", "strokes", 1500, 2000, 90.0),
              "replay: 1500/2000 strokes (75%), 1:30 elapsed, 0:30 left");
    EXPECT_EQ(progressText("generate", "tiles", 0, 0, 2.0), "generate: 0:02 elapsed")
        << "no total yet";
    EXPECT_EQ(progressText("generate", "tiles", 0, 4096, 0.3),
              "generate: 0/4096 tiles (0%), 0:00 elapsed, estimating");
    EXPECT_EQ(progressText("replay", "strokes", 2000, 2000, 600.0),
              "replay: 2000/2000 strokes (100%), 10:00 elapsed, 0:00 left");
}

TEST(Progress, MeterDrawsAtMostOneLinePerIntervalOnAFakeClock) {
    const double t0 = 1000.0;  // any clock origin: only differences count
    ProgressMeter meter("replay", "strokes", t0, 0.25);
    EXPECT_FALSE(meter.poll(0, 2000, t0 + 0.10)) << "nothing before the first interval";
    EXPECT_FALSE(meter.poll(1, 2000, t0 + 0.20));
    const auto first = meter.poll(2, 2000, t0 + 0.30);
    ASSERT_TRUE(first);
    EXPECT_EQ(*first, "replay: 2/2000 strokes (0%), 0:00 elapsed, estimating");
    EXPECT_FALSE(meter.poll(3, 2000, t0 + 0.40)) << "0.1 s after the last line";
    EXPECT_FALSE(meter.poll(4, 2000, t0 + 0.54));
    EXPECT_TRUE(meter.poll(5, 2000, t0 + 0.56));
    // 100 strokes in 10 s: 1900 left take 190 s.
    const auto later = meter.poll(100, 2000, t0 + 10.0);
    ASSERT_TRUE(later);
    EXPECT_EQ(*later, "replay: 100/2000 strokes (5%), 0:10 elapsed, 3:10 left");
    // Polled every 50 ms (the reporter thread's period) for 10 s: 4 lines a second.
    ProgressMeter steady("generate", "tiles", t0, 0.25);
    int lines = 0;
    for (int k = 1; k <= 200; ++k)
        lines += steady.poll(uint64_t(k), 200, t0 + 0.05 * k).has_value();
    EXPECT_GE(lines, 39);
    EXPECT_LE(lines, 40);
}

TEST(Progress, AReporterThatIsNotWantedStartsNothing) {
    const std::atomic<uint64_t> done{3}, total{10};
    const ProgressReporter reporter("replay", "strokes", done, total, /*enabled=*/false);
    // Destroyed at once: no thread to join, no line to erase. Under a test runner stderr is
    // seldom a terminal, and --quiet always wins:
    EXPECT_FALSE(progressWanted(/*quiet=*/true));
}
