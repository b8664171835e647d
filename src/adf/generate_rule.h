// SPDX-License-Identifier: Apache-2.0
/// @file generate_rule.h
/// @brief Generation's cell rule: when a cell of the octree is a leaf (Kizamu 5.1 with 5.2).
///
/// Takes a cell's samples on its 3x3x3 half grid (corners, face and edge centres, centre) and
/// says whether the cell stops as a leaf or splits into 8 children: the first look at the centre
/// alone, the distance grading next to the finest level, the feature test, and the 19-point
/// error test against the adaptive bound. Shared by the upper pass (generate.cpp) and the tiles
/// (generate_tile.cpp), so both subdivide alike wherever the tile level sits.
/// Complexity: O(1) per cell (hidesFeature asks the source once). Threading: const; any thread.
/// Internal to generation: namespace kizamu::adf::detail.
#pragma once

#include "adf/distance_source.h"
#include "adf/domain.h"
#include "adf/error_bound.h"

#include <glm/vec3.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

namespace kizamu::adf::detail {

// ---- the 3x3x3 half grid of a cell: point g = i + 3j + 9k, i, j, k in {0, 1, 2} ----

/// Half-grid point of corner c, by table: subdivide() looks up all 8 for every cell.
constexpr std::array<int, 8> kCornerGrid = {0, 2, 6, 8, 18, 20, 24, 26};
constexpr int cornerToGrid(int c) { return kCornerGrid[c]; }
constexpr int kCentre = 13;  // a variable, not an enum: ensure() takes its address

/// Half the diagonal of a unit cube.
constexpr double kHalfDiagonal = 0.8660254037844386;

/// Fraction of ε̂ the 19-point test allows (see CellRule::firstLook;
/// docs/decisions/0020-error-test-margin.md).
constexpr double kCriterionMargin = 0.75;

/// The 18 half-grid points that are neither corners nor the centre.
constexpr std::array<int, 18> kFaceEdgePoints = [] {
    std::array<int, 18> out{};
    int n = 0;
    for (int g = 0; g < 27; ++g) {
        const int i = g % 3, j = (g / 3) % 3, k = g / 9;
        const bool corner = i != 1 && j != 1 && k != 1;
        if (!corner && g != kCentre) out[n++] = g;
    }
    return out;
}();

/// (i, j, k) of half-grid point g, by table: the generator turns it into the points it lists.
constexpr std::array<glm::uvec3, 27> kGridOffset = [] {
    std::array<glm::uvec3, 27> t{};
    for (int g = 0; g < 27; ++g) t[g] = {uint32_t(g % 3), uint32_t((g / 3) % 3), uint32_t(g / 9)};
    return t;
}();
constexpr glm::uvec3 gridOffset(int g) { return kGridOffset[g]; }
constexpr glm::uvec3 childOffset(int c) { return {uint32_t(c & 1), uint32_t((c >> 1) & 1), uint32_t(c >> 2)}; }

/// The subdivision rule shared by the upper pass and the tiles (Kizamu 5.1 with 5.2).
struct CellRule {
    CellRule(const Domain& d, const GenerationSettings& s, const DistanceSource& src)
        : domain(d), bound(s.errorBound(d)), band(s.bandWorld(d)),
          // Cells no larger than the smallest feature anywhere never need the per-cell query.
          smallestFeature(src.smallestFeature()) {}

    const Domain& domain;
    ErrorBound bound;
    double band;
    double smallestFeature;  ///< m

    struct FirstLook {
        bool leaf;      ///< trivially interior or exterior, outside the band: stop here
        bool nearBand;  ///< some of the cell lies within the accurate band
        float threshold;
    };
    /// Decision from the centre distance alone. The threshold is the bound at the cell point
    /// nearest the surface, so every point of the cell gets at least its own ε̂, times a
    /// margin: the 19 test points see the largest error of a smooth field, but 16-bit
    /// quantisation and the curvature seams of rounded shapes add a little elsewhere.
    FirstLook firstLook(float centre, int level) const {
        const double halfDiag = double(domain.cellLattice(level)) * domain.finestCellSize() * kHalfDiagonal;
        const double dc = std::abs(double(centre));
        const bool mayContainSurface = dc <= halfDiag;
        const bool nearBand = band > 0.0 && dc - halfDiag < band;
        return {!mayContainSurface && !nearBand, nearBand,
                float(kCriterionMargin * bound(std::max(0.0, dc - halfDiag)))};
    }
    /// True when a feature of the source smaller than the cell may cross it (see
    /// DistanceSource::featureSize): the cell must be split whatever its test points say.
    bool hidesFeature(const DistanceSource& src, glm::uvec3 latticeOrigin, int level) const {
        if (level >= domain.maxLevel) return false;
        const double size = double(domain.cellLattice(level)) * domain.finestCellSize();
        if (size <= smallestFeature) return false;
        const double half = 0.5 * double(domain.cellLattice(level));
        const glm::dvec3 c = domain.originWorld + (glm::dvec3(latticeOrigin) + half) * domain.finestCellSize();
        return src.featureSize(c, size * kHalfDiagonal) < size;
    }

    /// Distance grading at the finest level: true when a cell one level above the finest has
    /// all 27 half-grid samples at least one finest cell from the surface. Such a cell holds
    /// no surface (every point of it is within sqrt(3)/2 finest cells of a sample) and fails
    /// the error test only across a kink of the field (a medial sheet from a sharp edge) or
    /// a focal point, where finest children miss the bound as well: splitting would halve an
    /// error the accuracy contract already leaves out (within two finest cells of a crease,
    /// docs/decisions/0025-accuracy-at-creases.md), at 8 times the cells. Not applied higher up:
    /// a cell four finest cells wide across a kink is off by half a cell two cells from it
    /// (|x - 1| on [0, 4], at x = 3), beyond that allowance, as the CSG accuracy test shows
    /// (docs/decisions/0019-distance-grading-at-finest-level.md).
    bool farFromSurface(const float* v, int level) const {
        return finestParent(level) && atLeastCells(nearestOf(v, 27), 1.0);
    }
    /// The same from the 8 corners and the centre, before the other 18 samples are taken:
    /// all at least 3 finest cells from the surface puts every face and edge centre (one
    /// cell from a corner or the centre) a cell or more from it, for any field no steeper
    /// than 2. Most cells a dab's crease sheet leaves at that level are settled here. Both
    /// tests assume a 1-Lipschitz field (the DistanceSource contract); a steeper tool field
    /// (build, heat gun) is covered by hidesFeature, which callers ask first.
    bool farFromSurfaceAtFirstLook(const float* corners, float centre, int level) const {
        return finestParent(level) && atLeastCells(std::min(nearestOf(corners, 8), std::abs(centre)), 3.0);
    }
    bool finestParent(int level) const { return level + 1 == domain.maxLevel; }
    bool atLeastCells(float distance, double cells) const { return double(distance) >= cells * domain.finestCellSize(); }
    /// Smallest |v[i]|: the sample nearest the surface.
    static float nearestOf(const float* v, int n) {
        float nearest = std::abs(v[0]);
        for (int i = 1; i < n; ++i) nearest = std::min(nearest, std::abs(v[i]));
        return nearest;
    }

    /// Largest |computed - reconstructed| over the 19 centre, face and edge points. The
    /// trilinear value at a half-grid point is the mean of the corners it lies between, built
    /// up edge -> face -> centre.
    static float error(const float* v) {
        auto g = [](int i, int j, int k) { return i + 3 * j + 9 * k; };
        float err = 0.0f;
        auto test = [&](int at, float recon) { err = std::max(err, std::abs(v[at] - recon)); };
        float ex[3][3], ey[3][3];  // x-edge centres at (j, k), y-edge centres at (i, k)
        for (int a = 0; a <= 2; a += 2)
            for (int b = 0; b <= 2; b += 2) {
                ex[a][b] = 0.5f * (v[g(0, a, b)] + v[g(2, a, b)]);
                ey[a][b] = 0.5f * (v[g(a, 0, b)] + v[g(a, 2, b)]);
                test(g(1, a, b), ex[a][b]);
                test(g(a, 1, b), ey[a][b]);
                test(g(a, b, 1), 0.5f * (v[g(a, b, 0)] + v[g(a, b, 2)]));
            }
        const float fz0 = 0.5f * (ex[0][0] + ex[2][0]), fz2 = 0.5f * (ex[0][2] + ex[2][2]);
        test(g(1, 1, 0), fz0);
        test(g(1, 1, 2), fz2);
        test(g(1, 0, 1), 0.5f * (ex[0][0] + ex[0][2]));
        test(g(1, 2, 1), 0.5f * (ex[2][0] + ex[2][2]));
        test(g(0, 1, 1), 0.5f * (ey[0][0] + ey[0][2]));
        test(g(2, 1, 1), 0.5f * (ey[2][0] + ey[2][2]));
        test(kCentre, 0.5f * (fz0 + fz2));
        return err;
    }
};

/// Throws the domain_error of a non-finite distance at `p` (cold: kept out of the callers).
[[noreturn]] void throwNonFinite(const glm::dvec3& p);
/// A source's value as stored, or a domain_error naming the point if it is NaN or infinite.
inline float checkedDistance(double d, const glm::dvec3& p) {
    if (!std::isfinite(d)) throwNonFinite(p);
    return float(d);
}
/// The same at lattice point `p` of `d` (its world position is only needed for the message).
inline float checkedDistance(double v, const Domain& d, glm::uvec3 p) {
    return std::isfinite(v) ? float(v) : checkedDistance(v, d.latticeToWorld(p.x, p.y, p.z));
}

}  // namespace kizamu::adf::detail
