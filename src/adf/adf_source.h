// SPDX-License-Identifier: Apache-2.0
/// @file adf_source.h
/// @brief An ADF snapshot read as a DistanceSource, so an edit can regenerate a region from
/// "the old field combined with a tool" (Kizamu 5.3).
///
/// The reconstruction is trilinear per leaf, so it is continuous within cells and close to
/// 1-Lipschitz; regeneration needs no more. Holds the snapshot alive (shared ownership on the
/// writer side). Thread-safe: every call reads the immutable snapshot.
#pragma once

#include "adf/adf.h"
#include "adf/distance_source.h"

namespace kizamu::adf {

/// The field of `adf` (not null) as a source.
SourcePtr makeAdfSource(AdfPtr adf);

/// `inside` within the closed box `region`, `outside` beyond it: how an edit limits a tool's
/// influence to the region it regenerates (the remote field is corrected later, Kizamu 5.4).
SourcePtr makeRegionLimited(SourcePtr outside, SourcePtr inside, const BoxWorld& region);

}  // namespace kizamu::adf
