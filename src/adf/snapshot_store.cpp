// SPDX-License-Identifier: Apache-2.0
/// @file snapshot_store.cpp
/// @brief Publishing and reclamation.
///
/// Why a retired snapshot S (tagged with epoch e, the value advance() returned after S was
/// unpublished) is safe to free once every reader slot is idle or holds an epoch > e: all
/// operations are seq_cst, so they fall in one total order. A reader that loaded S did so after
/// its slot store and before the writer's pointer store, which precedes advance(); so its slot
/// holds a value it read before advance() incremented past e, i.e. <= e, and stays so until
/// exit(). A reader whose slot store comes after the writer's check loads the pointer after the
/// pointer store and cannot see S. reclaim() reads each slot once and frees every entry retired
/// under an epoch below the smallest announced one: the same test for all of them, one scan.
/// The pointer names an immutable record {snapshot, sequence}, retired and freed with the
/// snapshot, so a reader gets both from one load.
#include "adf/snapshot_store.h"

#include <cassert>
#include <memory>
#include <utility>

namespace kizamu::adf {

namespace {

AdfPtr notNull(AdfPtr p) {
    if (!p) throw std::invalid_argument("SnapshotStore needs an initial snapshot");
    return p;
}

}  // namespace

SnapshotStore::SnapshotStore(AdfPtr initial, std::size_t maxReaders)
    : mEpochs(maxReaders),
      mCurrentRecord(new Published{notNull(std::move(initial)), kInitialSequence}),
      mCurrent(mCurrentRecord.get()) {}

SnapshotStore::~SnapshotStore() {
    assert(mEpochs.registeredReaders() == 0 &&
           "SnapshotStore destroyed while readers are registered");
}

uint64_t SnapshotStore::publish(AdfPtr next) {
    if (!next) throw std::invalid_argument("cannot publish a null snapshot");
    // Allocate first: if either allocation throws, nothing was unpublished.
    auto record =
        std::make_unique<const Published>(Published{std::move(next), mCurrentRecord->sequence + 1});
    mRetired.push_back({nullptr, 0});
    mRetired.back().record = std::move(mCurrentRecord);
    mCurrentRecord = std::move(record);
    mCurrent.store(mCurrentRecord.get(), std::memory_order_seq_cst);
    mRetired.back().epoch = mEpochs.advance();
    reclaim();
    return mCurrentRecord->sequence;
}

std::size_t SnapshotStore::reclaim() {
    if (mRetired.empty()) return 0;
    // Retired entries are in epoch order; one scan of the slots decides for all of them.
    const uint64_t oldest = mEpochs.oldestAnnounced();
    while (!mRetired.empty() && mRetired.front().epoch < oldest) mRetired.pop_front();
    return mRetired.size();
}

SnapshotStore::Reader::Reader(SnapshotStore& store)
    : mStore(store), mSlot(store.mEpochs.registerReader()) {
    if (mSlot < 0) throw std::runtime_error("SnapshotStore: no free reader slot");
}

SnapshotStore::Reader::~Reader() {
    mStore.mEpochs.unregisterReader(mSlot);
}

}  // namespace kizamu::adf
