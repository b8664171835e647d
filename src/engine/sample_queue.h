// SPDX-License-Identifier: Apache-2.0
/// @file sample_queue.h
/// @brief Tool samples from one producer to the edit thread: a bounded, wait-free
/// single-producer single-consumer ring that never drops the path when it is full.
///
/// Where it sits: the live engine's input (design brief, "The live pipeline"; issue 31). Each
/// producer (the stylus's servo thread, a headset controller, the mouse) owns one queue and is
/// its only pusher; the edit thread is its only consumer. The producer is hard real time, so
/// push() never blocks, never allocates, never frees and finishes in a bounded number of steps
/// whatever the consumer does (wait-free). The ring holds at least one second at 4 kHz
/// (kMinCapacity). If the edit thread falls that far behind, the producer keeps what it cannot
/// hand over in a fixed pending buffer and simplifies it there, within stated tolerances (the
/// guarantee below), instead of dropping samples: the whole path is carved.
///
/// The ring is the usual SPSC ring (Lamport; indices as in Rigtorp's SPSCQueue): two
/// monotonic 64-bit counters on separate cache lines, each side keeping a private copy of the
/// other's counter so that it touches the other's line only when its copy says full or empty.
/// Release on the counter a side publishes, acquire on the one it reads: a slot is written
/// before the consumer can see it and read before the producer can reuse it.
/// The simplification is a streaming Douglas-Peucker-like merge with a carried error bound per
/// kept segment (the bound is conservative: each merge adds the merged sample's distance to
/// the new chord to the larger of the two segments' bounds).
/// Units: SI (m, rad); time stamps in ns (tool_sample.h).
#pragma once

#include "engine/tool_sample.h"

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>

namespace kizamu::engine {

/// One queue's sizes and tolerances. Fixed at construction.
struct SampleQueueSettings {
    /// Ring slots: a power of two, at least SampleQueue::kMinCapacity (one second at 4 kHz).
    std::size_t capacity = 4096;
    /// Producer-side slots for samples waiting while the ring is full (at least 4). 512 hold
    /// about 20 s of a smooth hand path at the default tolerances; when they are full, the
    /// push that finds them so makes two passes over them (coarsening: O(pendingCapacity)).
    std::size_t pendingCapacity = 512;
    /// m: how far a merged sample's position may lie from the chord that replaces it.
    double positionTolerance = 1e-4;
    /// rad: how far a merged sample's orientation may lie from the slerp that replaces it
    /// (1e-3 rad at a 0.1 m tool reach is the position tolerance).
    double angleTolerance = 1e-3;
    /// How far a merged sample's strength may lie from the interpolated one (strength is 0..1).
    double strengthTolerance = 1e-2;
};

/// What the producer side has done so far. Written and read by the producer thread only.
struct SampleQueueStats {
    uint64_t merged = 0;          ///< samples the simplification removed (never handed over)
    uint64_t refused = 0;         ///< samples push() refused (see the guarantee)
    uint64_t coarsenings = 0;     ///< times the pending buffer was full and the tolerances doubled
    int maxCoarsening = 0;        ///< the largest k reached (tolerances × 2^k)
    std::size_t pendingPeak = 0;  ///< the most samples pending at once
};

/// A bounded wait-free single-producer single-consumer queue of ToolSample.
///
/// Owned by the live engine, one per producer; not copyable or movable. Thread-safe for
/// exactly one producer thread (push, flush, pendingCount, coarsening, stats) and one
/// consumer thread (drain, popAll) at a time; capacity() and sizeApprox() from any thread.
/// All memory (the ring and the pending buffer, written once so their pages are mapped) is
/// allocated by the constructor; nothing after it allocates.
///
/// **The guarantee.** The consumer receives a subsequence of the samples push() accepted, in
/// push order, each bit for bit as pushed. While the ring has room that is every sample. When
/// it is full, new samples wait in the pending buffer (in order, behind nothing: a sample goes
/// to the ring only once nothing is pending), which every push() and flush() hands over as far
/// as the ring has room. There the producer simplifies them: a *merged* sample is removed and
/// never handed over, and
///  - always kept (never merged): a *button edge*, a sample whose buttons differ from the
///    previous accepted sample's (the first sample pushed is one), and the sample just before
///    it, so the first and the last sample of every stroke; the latest accepted sample; the
///    oldest pending sample.
///  - every merged sample m, with a and c the kept samples delivered just before and after it
///    and τ = (m.timeNs - a.timeNs) / (c.timeNs - a.timeNs) (1/2 when c.timeNs = a.timeNs):
///      position:    its distance to the segment [a.posWorld, c.posWorld] is at most
///                   positionTolerance × 2^k. Distance to a segment is convex, so the whole
///                   pushed polyline from a to c lies within that of the delivered segment,
///                   and the segment within that of the pushed polyline (Hausdorff distance):
///                   the carved path is the pushed one within the tolerance;
///      orientation: the rotation angle from m.orientation to slerp(a.orientation,
///                   c.orientation, τ) (shortest path) is at most angleTolerance × 2^k;
///      strength:    |m.strength - lerp(a.strength, c.strength, τ)| is at most
///                   strengthTolerance × 2^k.
///    k, the *coarsening*, is 0 while the pending buffer has room. When it is full and a sample
///    must be added, all three tolerances double (k grows by at least 1, to the smallest value
///    that lets one more pending sample merge) and the pending samples are merged again at the
///    coarser tolerance. k only grows while samples are pending and returns to 0 once all of
///    them are handed over; the bound for m holds with the k in force when c is handed over,
///    at most stats().maxCoarsening.
///  - push() refuses a sample (returns false, stats().refused counts it; nothing accepted is lost)
///    only when the pending buffer is full and nothing pending can merge at any coarsening up
///    to kMaxCoarsening: every pending sample but the oldest and the latest is a button edge
///    or the sample before one (about pendingCapacity / 2 button changes waiting), or the
///    rest are not finite. Accepted button edges are never dropped; a refused sample's button
///    state reaches the consumer with the next accepted sample whose buttons differ from the
///    last accepted one (that sample is the edge).
class SampleQueue {
public:
    /// Smallest ring capacity: one second of samples at 4 kHz, rounded up to a power of two.
    static constexpr std::size_t kMinCapacity = 4096;
    /// Largest coarsening: tolerances × 2^40 (1e-4 m becomes 1e8 m, no longer a bound).
    static constexpr int kMaxCoarsening = 40;

    /// Cold path: allocates the ring and the pending buffer.
    /// @throw std::invalid_argument when the capacity is not a power of two at least
    ///        kMinCapacity, pendingCapacity < 4, or a tolerance is negative or not finite
    explicit SampleQueue(const SampleQueueSettings& settings = {});
    ~SampleQueue();
    SampleQueue(const SampleQueue&) = delete;
    SampleQueue& operator=(const SampleQueue&) = delete;

    // ---- producer (one thread) ----

    /// Hands `sample` over, or keeps it pending (simplified) when the ring is full; first
    /// hands over what is pending, as far as the ring has room.
    /// @param sample  time stamps must not decrease from push to push
    /// @return false only when refused (see the guarantee); true when handed over or pending
    /// Complexity: O(1) while nothing is pending (one store into the ring, one release store,
    ///             and an acquire load of the consumer's counter only when the ring looks full);
    ///             with samples pending O(pending handed over) plus, when the pending buffer is
    ///             full, two passes over it: O(pendingCapacity), bounded (wait-free)
    /// Threading:  the producer thread only; never blocks, no lock
    /// Memory:     allocates and frees nothing
    bool push(const ToolSample& sample) noexcept {
        if (mPendingCount == 0 && tryHandOver(sample)) {
            mLastButtons = sample.buttons;
            mHasLast = true;
            return true;
        }
        return pushSlow(sample);
    }

    /// Hands pending samples over as far as the ring has room (call it when the producer has
    /// no new sample, e.g. after a stroke ends, so the tail of a path is not held back).
    /// @return true when nothing is pending any more
    /// Complexity: O(samples handed over). Threading: the producer thread only, never blocks.
    /// Memory: none.
    bool flush() noexcept {
        if (mPendingCount > 0) handOverPending();
        return mPendingCount == 0;
    }

    /// Samples accepted but not yet handed over. Producer thread only.
    std::size_t pendingCount() const noexcept { return mPendingCount; }
    /// The coarsening k in force (tolerances × 2^k). Producer thread only.
    int coarsening() const noexcept { return mCoarsening; }
    /// Producer thread only.
    const SampleQueueStats& stats() const noexcept { return mStats; }

    // ---- consumer (one thread) ----

    /// Moves up to `max` of the oldest handed-over samples into `out`, in push order.
    /// @return how many were written to out[0..n)
    /// Complexity: O(n). Threading: the consumer thread only, never blocks. Memory: none.
    std::size_t drain(ToolSample* out, std::size_t max) noexcept;

    /// Calls fn(const ToolSample&) for every handed-over sample, in push order, then frees
    /// their slots at once. fn must not throw (noexcept context) and must not call this queue's
    /// consumer functions. @return how many samples fn saw.
    /// Complexity: O(n) calls. Threading: the consumer thread only. Memory: none.
    template <class Fn>
    std::size_t popAll(Fn&& fn) noexcept {
        const uint64_t head = mConsumer.head.load(std::memory_order_relaxed);
        mConsumer.cachedTail = mProducer.tail.load(std::memory_order_acquire);
        const uint64_t n = mConsumer.cachedTail - head;
        for (uint64_t i = 0; i < n; ++i)
            fn(static_cast<const ToolSample&>(mSlots[(head + i) & mMask]));
        mConsumer.head.store(head + n, std::memory_order_release);
        return std::size_t(n);
    }

    // ---- any thread ----

    std::size_t capacity() const noexcept { return std::size_t(mCapacity); }
    /// Samples handed over and not yet taken; exact only on a quiet queue.
    std::size_t sizeApprox() const noexcept;
    const SampleQueueSettings& settings() const noexcept { return mSettings; }

private:
    /// Carried error bounds of a pending segment (from the entry before to this one).
    struct Deviation {
        double position = 0.0;  ///< m
        double angle = 0.0;     ///< rad
        double strength = 0.0;
    };
    struct Pending {
        ToolSample sample;
        Deviation dev;        ///< of the segment ending here (merged samples inside it)
        bool pinned = false;  ///< a button edge or the sample before one
        Deviation mergeCost;  ///< coarsen()'s scratch: the bounds if this entry merged
    };
    static constexpr std::size_t kCacheLine = 64;
    struct alignas(kCacheLine) ProducerLine {
        std::atomic<uint64_t> tail{0};  ///< samples handed over so far (published, release)
        uint64_t cachedHead = 0;        ///< the producer's copy of the consumer's head
    };
    struct alignas(kCacheLine) ConsumerLine {
        std::atomic<uint64_t> head{0};  ///< samples taken so far (published, release)
        uint64_t cachedTail = 0;        ///< the consumer's copy of the producer's tail
    };

    /// Writes `sample` into the ring if it has room (producer).
    bool tryHandOver(const ToolSample& sample) noexcept {
        const uint64_t tail = mProducer.tail.load(std::memory_order_relaxed);
        if (tail - mProducer.cachedHead == mCapacity) {
            mProducer.cachedHead = mConsumer.head.load(std::memory_order_acquire);
            if (tail - mProducer.cachedHead == mCapacity) return false;
        }
        mSlots[tail & mMask] = sample;
        mProducer.tail.store(tail + 1, std::memory_order_release);
        return true;
    }
    /// The bounds of the segment [a, c] once b (between them) is merged: `ab` and `bc` are the
    /// bounds carried by [a, b] and [b, c]. Infinite when a rotation is too large to bound.
    static Deviation mergeDeviation(const ToolSample& a, const ToolSample& b, const ToolSample& c,
                                    const Deviation& ab, const Deviation& bc) noexcept;
    bool pushSlow(const ToolSample& sample) noexcept;
    void handOverPending() noexcept;
    /// Doubles the tolerances until one more pending sample can merge and merges again;
    /// false when no pending sample can merge at any coarsening up to kMaxCoarsening.
    bool coarsen() noexcept;
    /// The pending entry i places after the oldest.
    Pending& pending(std::size_t i) noexcept {
        const std::size_t j = mPendingHead + i;
        return mPending[j < mPendingCapacity ? j : j - mPendingCapacity];
    }

    // Read-only after construction (read by both sides).
    SampleQueueSettings mSettings;
    std::unique_ptr<ToolSample[]> mSlots;
    uint64_t mCapacity;
    uint64_t mMask;

    // Producer side.
    ProducerLine mProducer;
    std::unique_ptr<Pending[]> mPending;  ///< circular, mPendingCapacity entries
    std::size_t mPendingCapacity;
    std::size_t mPendingHead = 0;
    std::size_t mPendingCount = 0;
    int mCoarsening = 0;
    uint32_t mLastButtons = 0;  ///< buttons of the last accepted sample
    bool mHasLast = false;
    SampleQueueStats mStats;

    // Consumer side.
    ConsumerLine mConsumer;
};

}  // namespace kizamu::engine
