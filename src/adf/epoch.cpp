// SPDX-License-Identifier: Apache-2.0
/// @file epoch.cpp
/// @brief EpochDomain slots and the reclamation test.
#include "adf/epoch.h"

#include <algorithm>
#include <cassert>

namespace kizamu::adf {

EpochDomain::EpochDomain(std::size_t maxReaders)
    : mSlotCount(maxReaders), mSlots(new Slot[maxReaders]) {}

int EpochDomain::registerReader() {
    for (std::size_t i = 0; i < mSlotCount; ++i) {
        bool expected = false;
        if (mSlots[i].used.compare_exchange_strong(expected, true)) return int(i);
    }
    return -1;
}

void EpochDomain::unregisterReader(int slot) {
    assert(slot >= 0 && std::size_t(slot) < mSlotCount);
    assert(mSlots[slot].epoch.load() == kIdle && "unregistering a reader that is still inside");
    mSlots[slot].used.store(false);
}

bool EpochDomain::canReclaim(uint64_t retiredEpoch) const noexcept {
    for (std::size_t i = 0; i < mSlotCount; ++i) {
        const uint64_t e = mSlots[i].epoch.load(std::memory_order_seq_cst);
        if (e != kIdle && e <= retiredEpoch) return false;
    }
    return true;
}

uint64_t EpochDomain::oldestAnnounced() const noexcept {
    uint64_t oldest = kIdle;
    for (std::size_t i = 0; i < mSlotCount; ++i)
        oldest = std::min(oldest, mSlots[i].epoch.load(std::memory_order_seq_cst));
    return oldest;
}

std::size_t EpochDomain::registeredReaders() const noexcept {
    std::size_t n = 0;
    for (std::size_t i = 0; i < mSlotCount; ++i) n += mSlots[i].used.load();
    return n;
}

std::size_t EpochDomain::activeReaders() const noexcept {
    std::size_t n = 0;
    for (std::size_t i = 0; i < mSlotCount; ++i) n += mSlots[i].epoch.load() != kIdle;
    return n;
}

}  // namespace kizamu::adf
