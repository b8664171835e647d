// SPDX-License-Identifier: Apache-2.0
/// @file remote_field.h
/// @brief Remote-field correction (Kizamu 5.4): true distances again away from the surface.
///
/// Min/max CSG keeps the surface exact but leaves distances away from it that measure to
/// surfaces that no longer exist (a carve's tool surface in the air above the crater, the old
/// surface under a deep cut). The haptic thread reads those distances, so after edits the
/// field inside a *zone* (everything within the correction radius of what an edit changed) is
/// regenerated from: the old value within `keepCells` of the surface (the surface and its own
/// band stay as they are), the distance to the surface beyond `2 × keepCells` with the old
/// sign, and a smooth blend between. The surface is sampled on the zero set of every boundary
/// leaf near the zone (spacing at most half a finest cell) and searched with a k-d tree
/// (nanoflann). Past the correction radius, the value is at least that radius.
///
/// Deterministic: the result depends only on the snapshot and the zone.
/// Complexity: O(boundary leaves near the zone · log) to sample, O(log samples) per lattice
/// point of the zone's tiles. Threading: regeneration runs on the pool; call from the edit thread.
#pragma once

#include "adf/adf.h"

#include <vector>

namespace kizamu::util {
class ThreadPool;
}

namespace kizamu::sculpt {

struct CorrectionSettings {
    double radiusCells = 16.0;  ///< finest cells: the field is made true this far from the surface
    double keepCells = 2.0;     ///< finest cells: values nearer the surface are kept
};

/// Points on the zero set of the boundary leaves of the tiles overlapping `box` (m).
std::vector<glm::dvec3> surfaceSamples(const adf::Adf& adf, const adf::BoxWorld& box);

/// `adf` with the field inside `zone` corrected; everything outside the zone's tiles shared.
adf::AdfPtr correctRemoteField(const adf::AdfPtr& adf, const adf::BoxWorld& zone, util::ThreadPool* pool,
                               const CorrectionSettings& settings = {});

/// The zone of an edit over `region` (m): the region grown by the correction radius, clipped to
/// the domain.
adf::BoxWorld correctionZone(const adf::Adf& adf, const adf::BoxWorld& region, const CorrectionSettings& settings);

/// `adf` with every zone corrected, merged (mergeZones) where that is cheaper, in order.
adf::AdfPtr correctZones(adf::AdfPtr adf, std::vector<adf::BoxWorld> zones, util::ThreadPool* pool,
                         const CorrectionSettings& settings = {});

/// Zones merged where one pass over their bounding box costs less than separate passes (the
/// box's volume at most the sum of theirs, its extent at most `maxExtent` m). Deterministic.
std::vector<adf::BoxWorld> mergeZones(std::vector<adf::BoxWorld> zones, double maxExtent);

}  // namespace kizamu::sculpt
