// SPDX-License-Identifier: Apache-2.0
/// @file error_bound.h
/// @brief Bremer's adaptive error bound and the generation settings that use it.
///
/// Bremer et al. 2002, section III: the bound is epsilon within k*epsilon of the surface and grows
/// quadratically beyond, which stops refinement chasing the medial axis far from the surface.
/// Bounded-surface generation (Kizamu 5.2) enforces it inside a band around the surface, which
/// is what the haptic thread relies on. Plain values; any thread.
#pragma once

#include "adf/domain.h"

#include <cmath>

namespace kizamu::adf {

/// ε̂(d) = ε for d < kε, else ε + (d - kε)^2 * C / (k^2 ε). Units: m in, m out.
struct ErrorBound {
    double epsilon = 0.0;  ///< bound at the surface, m
    double k = 4.0;        ///< the bound stays epsilon up to k*epsilon from the surface
    double c = 0.05;       ///< growth constant (dimensionless)

    double operator()(double distance) const {
        const double d = std::abs(distance);
        const double knee = k * epsilon;
        if (d < knee) return epsilon;
        const double t = d - knee;
        return epsilon + t * t * c / (k * k * epsilon);
    }
};

/// Knobs of generation and regeneration, in finest cells so they are resolution independent.
struct GenerationSettings {
    double epsilonCells = 0.25;  ///< ε at the surface, finest cells
    double boundK = 4.0;         ///< Bremer's k
    double boundC = 0.05;        ///< Bremer's C
    double bandCells = 8.0;      ///< accurate band half-width, finest cells; 0 = surface only

    ErrorBound errorBound(const Domain& d) const {
        return {epsilonCells * d.finestCellSize(), boundK, boundC};
    }
    double bandWorld(const Domain& d) const { return bandCells * d.finestCellSize(); }
    bool valid() const {
        return epsilonCells > 0.0 && boundK > 0.0 && boundC >= 0.0 && bandCells >= 0.0 &&
               std::isfinite(epsilonCells + boundK + boundC + bandCells);
    }
    bool operator==(const GenerationSettings&) const = default;
};

}  // namespace kizamu::adf
