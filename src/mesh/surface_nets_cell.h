// SPDX-License-Identifier: Apache-2.0
/// @file surface_nets_cell.h
/// @brief One cell as the mesher sees it: the signs of its 8 corners, its 12 edges, its
/// trilinear field and the projection onto it (internal to src/mesh/surface_nets*).
///
/// Shared by the crossing phase (which edges change sign), the cycle phase (which sign patterns
/// make one sheet) and the vertex phase (projection). Everything here is inline or a constant
/// table: it runs per cell or per vertex, in the phases' inner loops.
/// Threading: pure functions and constant tables.
#pragma once

#include "adf/adf.h"
#include "adf/lattice.h"
#include "mesh/surface_nets_records.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#if defined(__SSE__)
#include <immintrin.h>
#endif

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>

namespace kizamu::mesh::detail {

/// Bit c: corner c negative (as the crossings' signs). Eight compares in two instructions
/// where SSE has them.
inline uint32_t insideCorners(const float* c) {
#if defined(__SSE__)
    const __m128 zero = _mm_setzero_ps();
    return uint32_t(_mm_movemask_ps(_mm_cmplt_ps(_mm_loadu_ps(c), zero))) |
           uint32_t(_mm_movemask_ps(_mm_cmplt_ps(_mm_loadu_ps(c + 4), zero))) << 4;
#else
    uint32_t inside = 0;
    for (int i = 0; i < 8; ++i) inside |= uint32_t(c[i] < 0.0f) << i;
    return inside;
#endif
}

inline bool isBoundary(const float* c) {
    const uint32_t inside = insideCorners(c);
    return inside != 0 && inside != 0xffu;
}

/// The 12 edges of a cell in the order crossings are emitted: start and end corner, axis, the
/// quadrant the cell fills around the edge, and per quadrant the step back from the edge's
/// start to the unit cube next to it there (1 along a and/or b), packed (packLattice).
struct CellEdge {
    uint8_t c0, c1, axis, a, b;
    uint8_t quadrant;  ///< the cell's own quadrant around the edge
    uint64_t packedStep[4];
};
/// Quadrant q lies on the -a (-b) side of an edge.
inline constexpr bool kMinusA[4] = {false, true, true, false}, kMinusB[4] = {false, false, true, true};
inline constexpr std::array<CellEdge, 12> kCellEdges = [] {
    std::array<CellEdge, 12> e{};
    int i = 0;
    for (int k = 0; k < 3; ++k)
        for (int c0 = 0; c0 < 8; ++c0) {
            if ((c0 >> k) & 1) continue;
            const int a = (k + 1) % 3, b = (k + 2) % 3;
            const bool plusA = !((c0 >> a) & 1), plusB = !((c0 >> b) & 1);
            const int quadrant = plusA ? (plusB ? 0 : 3) : (plusB ? 1 : 2);
            CellEdge& x = e[i++];
            x = {uint8_t(c0), uint8_t(c0 | (1 << k)), uint8_t(k), uint8_t(a), uint8_t(b), uint8_t(quadrant), {}};
            for (int q = 0; q < 4; ++q) {
                uint32_t d[3] = {0, 0, 0};
                d[a] = kMinusA[q];
                d[b] = kMinusB[q];
                x.packedStep[q] = packLattice({d[0], d[1], d[2]});
            }
        }
    return e;
}();
/// Bit i: edge i of kCellEdges changes sign, by the cell's inside corners (bit c: corner c).
inline constexpr std::array<uint16_t, 256> kSignChangingEdges = [] {
    std::array<uint16_t, 256> t{};
    for (uint32_t inside = 0; inside < 256; ++inside)
        for (int i = 0; i < 12; ++i)
            t[inside] |= uint16_t((((inside >> kCellEdges[i].c0) ^ (inside >> kCellEdges[i].c1)) & 1u) << i);
    return t;
}();

inline glm::vec3 clampToCell(glm::vec3 p, const Vertex& v) {
    const glm::vec3 lo(v.origin), hi = lo + float(v.size);
    return glm::clamp(p, lo, hi);
}

/// The cell's trilinear field at lattice point `p`: distance (m) and gradient (m per lattice unit).
/// kPacked: adf::trilinearPacked (the same value; where samples are not chained).
template <bool kPacked = false>
inline adf::Sample cellSample(const Vertex& v, glm::vec3 p) {
    const float inv = 1.0f / float(v.size);
    const glm::vec3 f = (p - glm::vec3(v.origin)) * inv;
    adf::Sample s = kPacked ? adf::trilinearPacked(v.corners, f) : adf::trilinear(v.corners, f);
    s.gradient *= inv;
    return s;
}

/// One Newton step onto the cell's zero set along its gradient, in lattice units, kept in the
/// cell. Reads only the cell's corners: inside its box that is the field itself.
template <bool kPacked = false>
inline glm::vec3 projectOnce(const Vertex& v, glm::vec3 p, glm::vec3* gradient = nullptr) {
    const adf::Sample s = cellSample<kPacked>(v, p);
    if (gradient) *gradient = s.gradient;
    const float g2 = glm::dot(s.gradient, s.gradient);
    if (!(g2 > 1e-20f) || !std::isfinite(s.distance)) return p;
    return clampToCell(p - (s.distance / g2) * s.gradient, v);
}

}  // namespace kizamu::mesh::detail
