// SPDX-License-Identifier: Apache-2.0
/// @file servo_stats.cpp
/// @brief LatencyHistogram's buckets and quantiles; ServoStats' tick record and summary.
#include "haptics/servo_stats.h"

#include <algorithm>
#include <bit>
#include <cmath>

namespace kizamu::haptics {

std::size_t LatencyHistogram::bucketOf(uint64_t v) noexcept {
    if (v < 2 * kSub) return std::size_t(v);  // exact below 128 ns
    const int e = std::bit_width(v) - 1;      // floor(log2 v) >= kSubBits + 1
    if (e > kMaxExponent) return kBuckets - 1;
    const uint64_t sub = (v >> (e - kSubBits)) - kSub;  // 0..63
    return std::size_t(e - kSubBits + 1) * kSub + std::size_t(sub);
}

uint64_t LatencyHistogram::bucketLow(std::size_t i) noexcept {
    if (i < 2 * kSub) return uint64_t(i);
    const std::size_t group = i / kSub, sub = i % kSub;  // group >= 2
    return (kSub + sub) << (group - 1);
}

uint64_t LatencyHistogram::bucketWidth(std::size_t i) noexcept {
    if (i < 2 * kSub) return 1;
    return uint64_t(1) << (i / kSub - 1);
}

std::vector<uint64_t> LatencyHistogram::buckets() const {
    std::vector<uint64_t> out(kBuckets);
    for (std::size_t i = 0; i < kBuckets; ++i) out[i] = mBuckets[i].load(std::memory_order_relaxed);
    return out;
}

void LatencyHistogram::clear() noexcept {
    for (auto& b : mBuckets) b.store(0, std::memory_order_relaxed);
    mMax.store(0, std::memory_order_relaxed);
}

double LatencyHistogram::quantileNs(const std::vector<uint64_t>& buckets, double q, uint64_t maxNs) noexcept {
    uint64_t n = 0;
    for (const uint64_t c : buckets) n += c;
    if (n == 0) return 0.0;
    q = std::clamp(q, 0.0, 1.0);
    const uint64_t rank = std::max<uint64_t>(1, uint64_t(std::ceil(q * double(n))));
    uint64_t seen = 0;
    for (std::size_t i = 0; i < buckets.size(); ++i) {
        seen += buckets[i];
        if (seen < rank) continue;
        const double width = double(bucketWidth(i));
        double v = double(bucketLow(i)) + (width > 1.0 ? 0.5 * (width - 1.0) : 0.0);
        if (maxNs > 0) v = std::min(v, double(maxNs));
        return v;
    }
    return maxNs > 0 ? double(maxNs) : 0.0;
}

void ServoStats::recordTick(int64_t nowNs, int64_t periodErrorNs, int64_t forceNs, bool missed) noexcept {
    if (mTicks.load(std::memory_order_relaxed) == 0) mFirstTickNs.store(nowNs, std::memory_order_relaxed);
    mLastTickNs.store(nowNs, std::memory_order_relaxed);
    mPeriodError.record(periodErrorNs);
    if (forceNs >= 0) mForceTime.record(forceNs);
    if (missed) bump(mMissed);
    bump(mTicks);
}

ServoCounts ServoStats::counts() const noexcept {
    ServoCounts c;
    c.ticks = mTicks.load(std::memory_order_relaxed);
    c.missed = mMissed.load(std::memory_order_relaxed);
    c.clamped = mClamped.load(std::memory_order_relaxed);
    c.nonFinite = mNonFinite.load(std::memory_order_relaxed);
    c.disconnectedTicks = mDisconnectedTicks.load(std::memory_order_relaxed);
    c.disconnects = mDisconnects.load(std::memory_order_relaxed);
    c.watchdogTrips = mWatchdogTrips.load(std::memory_order_relaxed);
    c.gateBusy = mGateBusy.load(std::memory_order_relaxed);
    c.firstTickNs = mFirstTickNs.load(std::memory_order_relaxed);
    c.lastTickNs = mLastTickNs.load(std::memory_order_relaxed);
    return c;
}

namespace {

ServoQuantiles quantilesUs(const LatencyHistogram& h) {
    const std::vector<uint64_t> b = h.buckets();
    const uint64_t maxNs = h.maxNs();
    ServoQuantiles q;
    q.p50 = LatencyHistogram::quantileNs(b, 0.5, maxNs) * 1e-3;
    q.p99 = LatencyHistogram::quantileNs(b, 0.99, maxNs) * 1e-3;
    q.p999 = LatencyHistogram::quantileNs(b, 0.999, maxNs) * 1e-3;
    q.max = double(maxNs) * 1e-3;
    return q;
}

}  // namespace

ServoSummary ServoStats::summary() const {
    ServoSummary s;
    s.counts = counts();
    const ServoCounts& c = s.counts;
    if (c.ticks >= 2 && c.lastTickNs > c.firstTickNs)
        s.rateHz = double(c.ticks - 1) / (double(c.lastTickNs - c.firstTickNs) * 1e-9);
    s.missedFraction = c.ticks > 0 ? double(c.missed) / double(c.ticks) : 0.0;
    s.periodErrorUs = quantilesUs(mPeriodError);
    s.forceUs = quantilesUs(mForceTime);
    return s;
}

void ServoStats::clear() noexcept {
    for (auto* c : {&mTicks, &mMissed, &mClamped, &mNonFinite, &mDisconnectedTicks, &mDisconnects, &mWatchdogTrips, &mGateBusy})
        c->store(0, std::memory_order_relaxed);
    mFirstTickNs.store(0, std::memory_order_relaxed);
    mLastTickNs.store(0, std::memory_order_relaxed);
    mPeriodError.clear();
    mForceTime.clear();
    mEvents.clear();
}

const char* servoEventName(ServoEventKind kind) noexcept {
    switch (kind) {
    case ServoEventKind::MissedDeadline: return "missed deadline";
    case ServoEventKind::Disconnected: return "device disconnected";
    case ServoEventKind::Reconnected: return "device reconnected";
    case ServoEventKind::WatchdogRestart: return "restart after a watchdog trip";
    case ServoEventKind::NonFiniteForce: return "non-finite force";
    }
    return "?";
}

void ServoEventLog::record(ServoEventKind kind, int64_t timeNs, int64_t valueNs) noexcept {
    const uint64_t i = mNext.load(std::memory_order_relaxed);
    Slot& slot = mSlots[i % kCapacity];
    // Each field is a release store after the odd mark: a reader that sees any new field value
    // (an acquire load) then sees the odd mark, or later, when it checks the sequence again.
    slot.sequence.store(2 * i + 1, std::memory_order_relaxed);
    slot.timeNs.store(timeNs, std::memory_order_release);
    slot.valueNs.store(valueNs, std::memory_order_release);
    slot.kind.store(uint8_t(kind), std::memory_order_release);
    slot.sequence.store(2 * i + 2, std::memory_order_release);
    mNext.store(i + 1, std::memory_order_release);
}

uint64_t ServoEventLog::read(uint64_t since, std::vector<ServoEvent>& out) const {
    const uint64_t next = mNext.load(std::memory_order_acquire);
    const uint64_t first = std::max(since, next > kCapacity ? next - kCapacity : uint64_t(0));
    for (uint64_t i = first; i < next; ++i) {
        const Slot& slot = mSlots[i % kCapacity];
        ServoEvent e;
        e.index = i;
        if (slot.sequence.load(std::memory_order_acquire) != 2 * i + 2) continue;  // overwritten or being written
        e.timeNs = slot.timeNs.load(std::memory_order_acquire);
        e.valueNs = slot.valueNs.load(std::memory_order_acquire);
        e.kind = ServoEventKind(slot.kind.load(std::memory_order_acquire));
        if (slot.sequence.load(std::memory_order_relaxed) != 2 * i + 2) continue;
        out.push_back(e);
    }
    return next;
}

void ServoEventLog::clear() noexcept {
    for (Slot& slot : mSlots) slot.sequence.store(0, std::memory_order_relaxed);
    mNext.store(0, std::memory_order_release);
}

}  // namespace kizamu::haptics
