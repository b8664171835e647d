// SPDX-License-Identifier: Apache-2.0
/// @file dabbed.h
/// @brief Test helper: a snapshot with one sphere dab regenerated into it, as an edit makes it.
#pragma once

#include "adf/adf_source.h"
#include "adf/distance_source.h"
#include "adf/generate.h"
#include "util/thread_pool.h"

#include <glm/vec3.hpp>

namespace kizamu::adf {

/// `a` with a sphere of radius `r` (m) at `c` carved (Difference) or added (Union), regenerated
/// over the sphere's box and a margin of two finest cells.
inline AdfPtr dabbed(const AdfPtr& a, CsgOp op, glm::dvec3 c, double r, util::ThreadPool* pool = nullptr) {
    const double cell = a->domain().finestCellSize();
    const BoxWorld region{c - glm::dvec3(r + 2 * cell), c + glm::dvec3(r + 2 * cell)};
    const SourcePtr old = makeAdfSource(a);
    return regenerate(*a, *makeRegionLimited(old, makeCsg(op, old, makeTranslated(makeSphere(r), c)), region), region,
                      pool);
}

}  // namespace kizamu::adf
