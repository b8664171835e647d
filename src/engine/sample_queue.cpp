// SPDX-License-Identifier: Apache-2.0
/// @file sample_queue.cpp
/// @brief SampleQueue's pending path (the ring is full) and the consumer's drain.
///
/// Why the error bounds add up (sample_queue.h states the guarantee). Each pending entry e
/// carries bounds for the segment from the entry before it, p: every merged sample between p
/// and e lies within dev of the segment [p, e] (position), of slerp(p, e) (orientation) and of
/// lerp(p, e) (strength) at its time. Merging b out of a, b, c:
///  - position: a point within d of [a, b] is within d + max(dist(a, [a, c]),
///    dist(b, [a, c])) = d + dist(b, [a, c]) of [a, c], distance to a convex set being convex
///    along [a, b]; likewise for [b, c]. So dev' = max(dev_ab, dev_bc) + dist(b, [a, c]).
///  - strength: lerp(a, b) and lerp(a, c) are linear in time on [t_a, t_b], agree at t_a and
///    differ by |b - lerp(a, c, τ_b)| at t_b, so by at most that in between; likewise on
///    [t_b, t_c]. dev' = max(dev_ab, dev_bc) + |b - lerp(a, c, τ_b)|.
///  - orientation: the same with slerp. Two geodesics from a common point of the unit
///    quaternion sphere stay no further apart than at their ends while both are at most pi/4
///    long (rotations of at most pi/2; checked numerically, it fails near pi/2 long), so a
///    merge whose three rotations a-b, b-c, a-c exceed pi/2 is refused.
#include "engine/sample_queue.h"

#include <glm/gtc/quaternion.hpp>
#include <glm/vec4.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace kizamu::engine {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

double distanceToSegment(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& c) {
    const glm::dvec3 ac = c - a;
    const double len2 = glm::dot(ac, ac);
    const double t = len2 > 0.0 ? std::clamp(glm::dot(p - a, ac) / len2, 0.0, 1.0) : 0.0;
    return glm::length(p - (a + t * ac));
}

glm::dquat unit(const glm::quat& q) {
    return glm::normalize(glm::dquat(q));
}

/// Rotation angle (rad, 0..pi) between two unit quaternions; atan2 keeps small angles exact.
double rotationAngle(const glm::dquat& p, glm::dquat q) {
    if (glm::dot(p, q) < 0.0) q = -q;
    const glm::dvec4 d(p.x - q.x, p.y - q.y, p.z - q.z, p.w - q.w);
    const glm::dvec4 s(p.x + q.x, p.y + q.y, p.z + q.z, p.w + q.w);
    return 2.0 * std::atan2(glm::length(d), glm::length(s));
}

/// τ of `b` between `a` and `c` (time stamps; 1/2 when they coincide).
double timeFraction(int64_t a, int64_t b, int64_t c) {
    return c > a ? std::clamp(double(b - a) / double(c - a), 0.0, 1.0) : 0.5;
}

}  // namespace

SampleQueue::SampleQueue(const SampleQueueSettings& settings)
    : mSettings(settings),
      mCapacity(settings.capacity),
      mMask(settings.capacity - 1),
      mPendingCapacity(settings.pendingCapacity) {
    if (settings.capacity < kMinCapacity || !std::has_single_bit(settings.capacity))
        throw std::invalid_argument(
            "SampleQueue: capacity must be a power of two of at least 4096");
    if (settings.pendingCapacity < 4)
        throw std::invalid_argument("SampleQueue: pendingCapacity must be at least 4");
    for (const double t :
         {settings.positionTolerance, settings.angleTolerance, settings.strengthTolerance})
        if (!(t >= 0.0) || !std::isfinite(t))
            throw std::invalid_argument("SampleQueue: tolerances must be finite and non-negative");
    // new T[n] runs the default member initialisers: every page is written here, not on the
    // producer's first push.
    mSlots.reset(new ToolSample[settings.capacity]);
    mPending.reset(new Pending[settings.pendingCapacity]);
}

SampleQueue::~SampleQueue() = default;

std::size_t SampleQueue::sizeApprox() const noexcept {
    const uint64_t head = mConsumer.head.load(std::memory_order_acquire);
    const uint64_t tail = mProducer.tail.load(std::memory_order_acquire);
    return tail > head ? std::size_t(tail - head) : 0;
}

std::size_t SampleQueue::drain(ToolSample* out, std::size_t max) noexcept {
    const uint64_t head = mConsumer.head.load(std::memory_order_relaxed);
    if (mConsumer.cachedTail - head < max)
        mConsumer.cachedTail = mProducer.tail.load(std::memory_order_acquire);
    const uint64_t n = std::min<uint64_t>(mConsumer.cachedTail - head, max);
    if (n == 0) return 0;
    // At most two contiguous runs: up to the ring's end, then from its start.
    const uint64_t first = std::min(n, mCapacity - (head & mMask));
    std::memcpy(out, &mSlots[head & mMask], std::size_t(first) * sizeof(ToolSample));
    std::memcpy(out + first, &mSlots[0], std::size_t(n - first) * sizeof(ToolSample));
    mConsumer.head.store(head + n, std::memory_order_release);
    return std::size_t(n);
}

void SampleQueue::handOverPending() noexcept {
    const uint64_t tail = mProducer.tail.load(std::memory_order_relaxed);
    if (mCapacity - (tail - mProducer.cachedHead) < mPendingCount)
        mProducer.cachedHead = mConsumer.head.load(std::memory_order_acquire);
    const std::size_t n = std::min<std::size_t>(
        mPendingCount, std::size_t(mCapacity - (tail - mProducer.cachedHead)));
    for (std::size_t i = 0; i < n; ++i) mSlots[(tail + i) & mMask] = pending(i).sample;
    mProducer.tail.store(tail + n, std::memory_order_release);
    mPendingHead = (mPendingHead + n) % mPendingCapacity;
    mPendingCount -= n;
    if (mPendingCount == 0) {
        mPendingHead = 0;
        mCoarsening = 0;  // the bounds of everything handed over are final
    }
}

bool SampleQueue::pushSlow(const ToolSample& sample) noexcept {
    if (mPendingCount > 0) {
        handOverPending();
        if (mPendingCount == 0 && tryHandOver(sample)) {
            mLastButtons = sample.buttons;
            mHasLast = true;
            return true;
        }
    }
    // The ring is full: the sample waits, and the pending path is simplified.
    const bool edge = !mHasLast || sample.buttons != mLastButtons;
    const double scale = std::ldexp(1.0, mCoarsening);
    const auto within = [&](const Deviation& d) {
        return d.position <= mSettings.positionTolerance * scale &&
               d.angle <= mSettings.angleTolerance * scale &&
               d.strength <= mSettings.strengthTolerance * scale;
    };
    if (mPendingCount > 0 && edge) pending(mPendingCount - 1).pinned = true;  // the last of its run
    if (!edge && mPendingCount >= 2 && !pending(mPendingCount - 1).pinned) {
        // Greedy step: the newest pending sample becomes interior; merge it if the chord from
        // the one before it to `sample` is within the tolerances.
        Pending& last = pending(mPendingCount - 1);
        const Deviation d =
            mergeDeviation(pending(mPendingCount - 2).sample, last.sample, sample, last.dev, {});
        if (within(d)) {
            last = Pending{sample, d, false};
            ++mStats.merged;
            return true;
        }
    }
    if (mPendingCount == mPendingCapacity && !coarsen()) {
        ++mStats.refused;
        return false;
    }
    pending(mPendingCount) = Pending{sample, {}, edge};
    ++mPendingCount;
    mStats.pendingPeak = std::max(mStats.pendingPeak, mPendingCount);
    mLastButtons = sample.buttons;
    mHasLast = true;
    return true;
}

bool SampleQueue::coarsen() noexcept {
    // The smallest tolerance scale at which one interior, unpinned entry could merge.
    const auto ratio = [](double dev, double tolerance) {
        return dev <= 0.0 ? 0.0 : tolerance > 0.0 ? dev / tolerance : kInf;
    };
    double need = kInf;
    for (std::size_t i = 1; i + 1 < mPendingCount; ++i) {
        Pending& b = pending(i);
        if (b.pinned) continue;
        const Deviation d = mergeDeviation(pending(i - 1).sample, b.sample, pending(i + 1).sample,
                                           b.dev, pending(i + 1).dev);
        b.mergeCost = d;  // still valid in the pass below while the entry before is kept
        const double r = std::max({ratio(d.position, mSettings.positionTolerance),
                                   ratio(d.angle, mSettings.angleTolerance),
                                   ratio(d.strength, mSettings.strengthTolerance)});
        if (r < need) need = r;  // NaN (a non-finite pose) never merges
    }
    if (!(need < kInf)) return false;
    int k = mCoarsening + 1;
    while (k <= kMaxCoarsening && std::ldexp(1.0, k) < need) ++k;
    if (k > kMaxCoarsening) return false;
    mCoarsening = k;
    ++mStats.coarsenings;
    mStats.maxCoarsening = std::max(mStats.maxCoarsening, k);

    // One pass, oldest first, merging every interior entry the new tolerances allow. Entries
    // are compacted in place (write index w never passes read index i). The entry at `need`
    // merges: nothing before it changed, or something before it merged. An entry's bounds from
    // the pass above stand unless the entry before it merged (its left neighbour and its own
    // carried bounds are then new).
    const double scale = std::ldexp(1.0, k);
    const double pos = mSettings.positionTolerance * scale, ang = mSettings.angleTolerance * scale,
                 str = mSettings.strengthTolerance * scale;
    std::size_t w = 1;
    bool leftMerged = false;
    for (std::size_t i = 1; i < mPendingCount; ++i) {
        Pending& b = pending(i);
        if (i + 1 < mPendingCount && !b.pinned) {
            Pending& c = pending(i + 1);
            const Deviation d =
                leftMerged ? mergeDeviation(pending(w - 1).sample, b.sample, c.sample, b.dev, c.dev)
                           : b.mergeCost;
            if (d.position <= pos && d.angle <= ang && d.strength <= str) {
                c.dev = d;
                ++mStats.merged;
                leftMerged = true;
                continue;
            }
        }
        leftMerged = false;
        if (w != i) pending(w) = b;
        ++w;
    }
    mPendingCount = w;
    return mPendingCount < mPendingCapacity;
}

SampleQueue::Deviation SampleQueue::mergeDeviation(const ToolSample& a, const ToolSample& b,
                                                   const ToolSample& c, const Deviation& ab,
                                                   const Deviation& bc) noexcept {
    const glm::dquat qa = unit(a.orientation), qb = unit(b.orientation), qc = unit(c.orientation);
    // Rotations of at most pi/2: half-angles of at most pi/4.
    const double minDot = std::numbers::sqrt2 / 2;
    if (std::abs(glm::dot(qa, qc)) < minDot || std::abs(glm::dot(qa, qb)) < minDot ||
        std::abs(glm::dot(qb, qc)) < minDot)
        return {kInf, kInf, kInf};
    const double tau = timeFraction(a.timeNs, b.timeNs, c.timeNs);
    Deviation d;
    d.position =
        std::max(ab.position, bc.position) + distanceToSegment(b.posWorld, a.posWorld, c.posWorld);
    d.angle = std::max(ab.angle, bc.angle) + rotationAngle(qb, glm::slerp(qa, qc, tau));
    const double s = double(a.strength) + tau * (double(c.strength) - double(a.strength));
    d.strength = std::max(ab.strength, bc.strength) + std::abs(double(b.strength) - s);
    return d;
}

}  // namespace kizamu::engine
