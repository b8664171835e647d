// SPDX-License-Identifier: Apache-2.0
/// @file test_part.h
/// @brief The fixed test part every ADF benchmark and demo uses (docs/TEST-PART.md).
///
/// A rounded box (half-size 0.3 of the domain, corner radius 0.05) minus three orthogonal
/// through-cylinders (radius 0.1), plus a sphere (radius 0.15) centred on its +z face, all centred
/// in the domain. Generated with ε = 0.25 finest cell at the surface and a band of 8 finest cells.
#pragma once

#include "adf/distance_source.h"
#include "adf/domain.h"
#include "adf/error_bound.h"

namespace kizamu::adf {

/// The test part scaled to `domain` (its size and origin).
SourcePtr makeTestPart(const Domain& domain);
/// The unit-cube domain (1 m, origin 0) at `maxLevel` with the default tile span.
Domain testPartDomain(int maxLevel);
/// ε = 0.25 finest cell, band = 8 finest cells (the defaults, stated here as the contract).
GenerationSettings testPartSettings();

}  // namespace kizamu::adf
