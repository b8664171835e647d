// SPDX-License-Identifier: Apache-2.0
/// @file triple_buffer.h
/// @brief A wait-free single-value mailbox between one writer thread and one reader thread: the
/// writer publishes whole values, the reader takes the newest whole value, neither ever waits
/// for or sees a half-written one.
///
/// Three slots: the writer owns one (it fills it), the reader owns one (it reads it), and the
/// third is exchanged between them through one atomic byte (its index and a "fresh" bit). A
/// publish is one exchange; a take is one load and, when something fresh is there, one
/// exchange; the acquire-release exchange orders the slot's contents with its hand-over. Used
/// where a real-time thread must read what a slower thread last wrote (the mouse's hand target
/// for the servo thread) without a lock and without a retry loop that a preempted writer could
/// stretch. T must be trivially copyable (copied with plain assignment). Not copyable.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <type_traits>

namespace kizamu::util {

template <class T>
class TripleBuffer {
    static_assert(std::is_trivially_copyable_v<T>, "TripleBuffer holds plain values");

public:
    /// Every slot starts as `initial`; read() returns it until the first take of a write.
    explicit TripleBuffer(const T& initial = T{}) : mSlots{initial, initial, initial} {}
    TripleBuffer(const TripleBuffer&) = delete;
    TripleBuffer& operator=(const TripleBuffer&) = delete;

    /// Writer thread. Publishes `value`. Wait-free: one copy and one exchange.
    void write(const T& value) noexcept {
        mSlots[mBack] = value;
        mBack = uint8_t(mMiddle.exchange(uint8_t(mBack | kFresh), std::memory_order_acq_rel) & kIndex);
    }
    /// Reader thread. Takes the newest published value if there is one not yet taken; returns
    /// whether it did. Wait-free.
    bool take() noexcept {
        if (!(mMiddle.load(std::memory_order_relaxed) & kFresh)) return false;
        mFront = uint8_t(mMiddle.exchange(mFront, std::memory_order_acq_rel) & kIndex);
        return true;
    }
    /// Reader thread. The value taken last.
    const T& read() const noexcept { return mSlots[mFront]; }

private:
    static constexpr uint8_t kIndex = 0x3, kFresh = 0x4;
    std::array<T, 3> mSlots;
    std::atomic<uint8_t> mMiddle{1};
    uint8_t mBack = 0;   ///< the writer's slot
    uint8_t mFront = 2;  ///< the reader's slot
};

}  // namespace kizamu::util
