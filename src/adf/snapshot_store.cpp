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
/// pointer store and cannot see S.
#include "adf/snapshot_store.h"

#include <cassert>
#include <utility>

namespace kizamu::adf {

SnapshotStore::SnapshotStore(AdfPtr initial, std::size_t maxReaders)
    : mEpochs(maxReaders), mCurrent(initial.get()), mCurrentOwner(std::move(initial)) {
    if (!mCurrentOwner) throw std::invalid_argument("SnapshotStore needs an initial snapshot");
}

SnapshotStore::~SnapshotStore() {
    assert(mEpochs.registeredReaders() == 0 && "SnapshotStore destroyed while readers are registered");
}

void SnapshotStore::publish(AdfPtr next) {
    if (!next) throw std::invalid_argument("cannot publish a null snapshot");
    // Take the retire-list slot first: if that allocation throws, nothing was unpublished.
    mRetired.push_back({mCurrentOwner, 0});
    mCurrentOwner = std::move(next);
    mCurrent.store(mCurrentOwner.get(), std::memory_order_seq_cst);
    mRetired.back().epoch = mEpochs.advance();
    reclaim();
}

std::size_t SnapshotStore::reclaim() {
    // Retired entries are in epoch order: stop at the first one still visible.
    while (!mRetired.empty() && mEpochs.canReclaim(mRetired.front().epoch)) mRetired.pop_front();
    return mRetired.size();
}

SnapshotStore::Reader::Reader(SnapshotStore& store) : mStore(store), mSlot(store.mEpochs.registerReader()) {
    if (mSlot < 0) throw std::runtime_error("SnapshotStore: no free reader slot");
}

SnapshotStore::Reader::~Reader() { mStore.mEpochs.unregisterReader(mSlot); }

}  // namespace kizamu::adf
