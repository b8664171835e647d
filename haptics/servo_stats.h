// SPDX-License-Identifier: Apache-2.0
/// @file servo_stats.h
/// @brief The servo loop's statistics: tick counts, fault counts, and preallocated histograms
/// of the period error and of the force computation time, with their quantiles.
///
/// Where it sits: ServoTicker (servo_loop.h) records one tick at a time on the servo thread;
/// benchmarks, tests and a status line read counts() and summary() from any thread while it
/// runs. Units: nanoseconds in, microseconds in the summaries (named with `Us`).
///
/// Threading: one writer (the servo thread), any number of readers, no locks. Every counter
/// and every histogram bucket is a std::atomic<uint64_t> written with relaxed load + store (a
/// single writer needs no read-modify-write, so a tick costs plain moves on x86) and read with
/// relaxed loads. Not a seqlock: a seqlock would make a reader retry while the servo thread
/// writes, and nothing needs more than this gives: each value is exact by itself, and a copy
/// taken while the loop runs may count a tick in one counter and not yet in another (at most one
/// tick apart). Once the servo thread is joined, every read is exact.
///
/// Histograms: HDR-style log-linear buckets over nanoseconds: exact below 128 ns, then 64
/// buckets per power of two (a bucket is at most 1/64 of its value wide; a quantile is reported
/// as its bucket's midpoint, so within 0.8 %), up to 2^40 ns (18 minutes; larger values land in
/// the last bucket). 2,304 buckets, 18 KiB per histogram, allocated once at construction.
#pragma once

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace kizamu::haptics {

/// Counters of a servo loop, copied out of ServoStats (plain values).
struct ServoCounts {
    uint64_t ticks = 0;              ///< ticks run (each one read, computed and wrote, or zeroed)
    uint64_t missed = 0;             ///< ticks that started more than one period after their deadline
    uint64_t clamped = 0;            ///< forces above DeviceSpec::maxForce, scaled down to it
    uint64_t nonFinite = 0;          ///< forces with a NaN or infinite component, replaced by zero
    uint64_t disconnectedTicks = 0;  ///< ticks on which the device did not answer (force zero)
    uint64_t disconnects = 0;        ///< times the device went from answering to not answering
    uint64_t watchdogTrips = 0;      ///< times the watchdog zeroed the force of a stalled loop
    uint64_t gateBusy = 0;           ///< ticks that skipped the device because the watchdog held it
    int64_t firstTickNs = 0;         ///< servo clock of the first tick (0: none yet)
    int64_t lastTickNs = 0;          ///< servo clock of the latest tick
};

/// Quantiles of one histogram, in microseconds.
struct ServoQuantiles {
    double p50 = 0.0, p99 = 0.0, p999 = 0.0, max = 0.0;
};

/// What a run achieved: counts, rate, quantiles. Computed off the servo thread.
struct ServoSummary {
    ServoCounts counts;
    double rateHz = 0.0;          ///< (ticks - 1) / (lastTickNs - firstTickNs)
    double missedFraction = 0.0;  ///< missed / ticks
    ServoQuantiles periodErrorUs;  ///< how late each tick started after its deadline
    ServoQuantiles forceUs;        ///< time in ServoClient::tick
};

/// A log-linear histogram of non-negative durations in ns; one writer, lock-free readers.
/// Owned by ServoStats; not copyable.
class LatencyHistogram {
public:
    static constexpr int kSubBits = 6;
    static constexpr uint64_t kSub = uint64_t(1) << kSubBits;  ///< buckets per power of two
    static constexpr int kMaxExponent = 40;                    ///< values up to 2^40 ns
    static constexpr std::size_t kBuckets = std::size_t(kMaxExponent - kSubBits + 2) * kSub;

    LatencyHistogram() = default;
    LatencyHistogram(const LatencyHistogram&) = delete;
    LatencyHistogram& operator=(const LatencyHistogram&) = delete;

    /// Counts one value (ns; negative counts as 0). Writer thread only.
    /// Complexity: O(1), one count leading zeros. Memory: none. Never blocks.
    void record(int64_t ns) noexcept {
        const uint64_t v = ns > 0 ? uint64_t(ns) : 0;
        std::atomic<uint64_t>& b = mBuckets[bucketOf(v)];
        b.store(b.load(std::memory_order_relaxed) + 1, std::memory_order_relaxed);
        if (v > mMax.load(std::memory_order_relaxed)) mMax.store(v, std::memory_order_relaxed);
    }
    /// Copies the bucket counts (any thread). Memory: allocates kBuckets counts.
    std::vector<uint64_t> buckets() const;
    /// The largest value recorded (ns), exact.
    uint64_t maxNs() const noexcept { return mMax.load(std::memory_order_relaxed); }
    /// Sets every bucket to zero. Only while nothing records (before the loop starts).
    void clear() noexcept;

    /// The bucket holding `v` ns. O(1).
    static std::size_t bucketOf(uint64_t v) noexcept;
    /// The smallest value of bucket `i`, and its width (ns).
    static uint64_t bucketLow(std::size_t i) noexcept;
    static uint64_t bucketWidth(std::size_t i) noexcept;
    /// The q-quantile (0..1) of `buckets` (as buckets() returns) in ns: the midpoint of the
    /// bucket holding the value of rank ceil(q * n) (nearest rank), at most `maxNs` when that
    /// is given (> 0). 0 for an empty histogram.
    /// Complexity: O(kBuckets). Memory: none.
    static double quantileNs(const std::vector<uint64_t>& buckets, double q, uint64_t maxNs = 0) noexcept;

private:
    std::array<std::atomic<uint64_t>, kBuckets> mBuckets{};
    std::atomic<uint64_t> mMax{0};
};

/// What the servo log records, one event each, time stamped (servo clock).
enum class ServoEventKind : uint8_t {
    MissedDeadline,   ///< a tick started more than a period late; value: how late (ns)
    Disconnected,     ///< the device stopped answering (force zero until it answers)
    Reconnected,      ///< it answers again (the client restarts: soft start)
    WatchdogRestart,  ///< the first tick after a watchdog trip (force was zeroed behind its back)
    NonFiniteForce,   ///< the client returned a NaN or infinite force (replaced by zero)
};

const char* servoEventName(ServoEventKind kind) noexcept;

struct ServoEvent {
    uint64_t index = 0;  ///< 0, 1, 2, ... in the order recorded
    int64_t timeNs = 0;  ///< servo clock
    ServoEventKind kind = ServoEventKind::MissedDeadline;
    int64_t valueNs = 0;
};

/// The newest kCapacity events in a preallocated ring: one writer (the servo thread) that never
/// waits, readers on any thread (the app's status line, the benchmark) that copy events out and
/// skip any the writer overwrote while they read (a per-slot sequence check; every field is an
/// atomic, so it is also race-free under ThreadSanitizer).
class ServoEventLog {
public:
    static constexpr std::size_t kCapacity = 256;
    /// Writer. O(1), no allocation.
    void record(ServoEventKind kind, int64_t timeNs, int64_t valueNs = 0) noexcept;
    /// Events recorded so far (also those the ring no longer holds). Any thread.
    uint64_t recorded() const noexcept { return mNext.load(std::memory_order_acquire); }
    /// Appends to `out` the events with index >= `since` that the ring still holds, oldest
    /// first; returns the index to pass next time. Any thread. Allocates (out).
    uint64_t read(uint64_t since, std::vector<ServoEvent>& out) const;
    /// Only while no tick runs.
    void clear() noexcept;

private:
    struct Slot {
        std::atomic<uint64_t> sequence{0};  ///< 2 i + 1 while event i is written, 2 i + 2 once written
        std::atomic<int64_t> timeNs{0}, valueNs{0};
        std::atomic<uint8_t> kind{0};
    };
    std::array<Slot, kCapacity> mSlots{};
    std::atomic<uint64_t> mNext{0};
};

/// Statistics of one servo loop. Owned by its ServoTicker (one per loop); one writer thread
/// (the servo thread, or the test driving a ticker in lock-step), readers on any thread.
class ServoStats {
public:
    ServoStats() = default;
    ServoStats(const ServoStats&) = delete;
    ServoStats& operator=(const ServoStats&) = delete;

    // ---- writer (servo thread): O(1), no allocation, never blocks ----
    /// One tick that started at `nowNs` (servo clock), `periodErrorNs` after its deadline, whose
    /// force computation took `forceNs` (negative: not computed this tick); `missed` when it
    /// started more than a period late.
    void recordTick(int64_t nowNs, int64_t periodErrorNs, int64_t forceNs, bool missed) noexcept;
    void countClamped() noexcept { bump(mClamped); }
    void countNonFinite() noexcept { bump(mNonFinite); }
    void countDisconnectedTick() noexcept { bump(mDisconnectedTicks); }
    void countDisconnect() noexcept { bump(mDisconnects); }
    void countGateBusy() noexcept { bump(mGateBusy); }
    /// The watchdog's thread counts its trips (the only counter another thread writes; it has
    /// its own writer, so the single-writer rule holds per counter).
    void countWatchdogTrip() noexcept { bump(mWatchdogTrips); }

    // ---- readers (any thread) ----
    /// Every counter (relaxed loads; see the file comment for what a copy guarantees).
    ServoCounts counts() const noexcept;
    /// Counts, achieved rate and quantiles. Complexity: O(buckets). Memory: two bucket copies.
    ServoSummary summary() const;
    const LatencyHistogram& periodError() const noexcept { return mPeriodError; }
    const LatencyHistogram& forceTime() const noexcept { return mForceTime; }
    /// The time-stamped log of missed deadlines, disconnects and restarts (servo thread writes).
    ServoEventLog& events() noexcept { return mEvents; }
    const ServoEventLog& events() const noexcept { return mEvents; }

    /// Zeroes everything. Only while no tick runs (before start, after stop).
    void clear() noexcept;

private:
    static void bump(std::atomic<uint64_t>& c) noexcept {
        c.store(c.load(std::memory_order_relaxed) + 1, std::memory_order_relaxed);
    }

    std::atomic<uint64_t> mTicks{0}, mMissed{0}, mClamped{0}, mNonFinite{0}, mDisconnectedTicks{0},
        mDisconnects{0}, mWatchdogTrips{0}, mGateBusy{0};
    std::atomic<int64_t> mFirstTickNs{0}, mLastTickNs{0};
    LatencyHistogram mPeriodError;
    LatencyHistogram mForceTime;
    ServoEventLog mEvents;
};

}  // namespace kizamu::haptics
