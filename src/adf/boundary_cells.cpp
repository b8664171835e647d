// SPDX-License-Identifier: Apache-2.0
/// @file boundary_cells.cpp
/// @brief appendBoundaryCells.
#include "adf/boundary_cells.h"

#include "adf/tile_diff.h"

#include <algorithm>
#include <array>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace kizamu::adf {

namespace {

constexpr uint32_t kAll27 = (1u << 27) - 1;

/// Bit g: q[g] < 0, for g < 27 (q holds 32 values). SSE2 packs the values to bytes with
/// saturation (signs kept) and takes their sign bits: four instructions for 27 compares.
inline uint32_t negatives27(const int16_t* q) {
#if defined(__SSE2__)
    const __m128i* v = reinterpret_cast<const __m128i*>(q);
    const uint32_t lo = uint32_t(_mm_movemask_epi8(_mm_packs_epi16(_mm_loadu_si128(v), _mm_loadu_si128(v + 1))));
    const uint32_t hi = uint32_t(_mm_movemask_epi8(_mm_packs_epi16(_mm_loadu_si128(v + 2), _mm_loadu_si128(v + 3))));
    return (lo | (hi << 16)) & kAll27;
#else
    uint32_t inside = 0;
    for (int g = 0; g < 27; ++g) inside |= uint32_t(q[g] < 0) << g;
    return inside;
#endif
}

/// brickPoint(child, c) for every child and corner (the loops below run over both).
constexpr auto kBrickPoints = [] {
    std::array<std::array<uint8_t, 8>, 8> t{};
    for (int child = 0; child < 8; ++child)
        for (int c = 0; c < 8; ++c) t[child][c] = uint8_t(adf::brickPoint(child, c));
    return t;
}();

/// The half-grid points of each child, as a 27-bit mask.
constexpr auto kChildPointMasks = [] {
    std::array<uint32_t, 8> t{};
    for (int child = 0; child < 8; ++child)
        for (int c = 0; c < 8; ++c) t[child] |= 1u << kBrickPoints[child][c];
    return t;
}();

/// The walk, descending only into cells for which `keep(origin, size)` holds, and recording
/// only the sign-changing leaves for which `keepLeaf(origin, size)` holds as well.
template <class Keep, class KeepLeaf>
void appendIf(const adf::Tile& t, int maxLevel, std::vector<BoundaryCell>& out, Keep keep, KeepLeaf keepLeaf) {
    namespace node = adf::node;
    struct Item {
        uint32_t node;
        glm::uvec3 origin;
        uint32_t size;
    };
    Item stack[8 * (adf::kMaxSupportedLevel + 1)];
    int top = 0;
    stack[top++] = {0, t.latticeOrigin(), 1u << uint32_t(maxLevel - t.level())};
    const float scale = t.scale();
    while (top > 0) {
        const Item it = stack[--top];
        if (!keep(it.origin, it.size)) continue;
        const uint32_t w = t.node(it.node);
        const uint32_t half = it.size >> 1;
        if (node::isInternal(w)) {
            for (int c = 7; c >= 0; --c)
                stack[top++] = {w + uint32_t(c), it.origin + glm::uvec3(c & 1, (c >> 1) & 1, c >> 2) * half, half};
        } else if (node::isLeaf(w)) {
            // A leaf's word holds its type (set from, and on load checked against, its corner
            // signs): most leaves are decided without decoding their corners.
            if (node::leafType(w) != adf::CellType::Boundary || !keepLeaf(it.origin, it.size)) continue;
            int16_t q[8];
            t.leafValues(node::leafIndex(w), q);
            BoundaryCell b{it.origin, it.size, {}, false};
            for (int c = 0; c < 8; ++c) b.corners[c] = float(q[c]) * scale;
            out.push_back(b);
        } else {
            // Padded to 32 (four whole vectors; the padding's bits are masked off).
            if (!t.brickMayChangeSign(node::brickIndex(w))) continue;
            int16_t q[32];
            t.brickValues(node::brickIndex(w), q);
            std::fill(q + 27, q + 32, q[0]);
            const uint32_t inside = negatives27(q);  // a child's test is then two masks
            if (inside == 0 || inside == kAll27) continue;
            for (int child = 0; child < 8; ++child) {
                const uint32_t childInside = inside & kChildPointMasks[child];
                if (childInside == 0 || childInside == kChildPointMasks[child]) continue;
                int16_t raw[8];
                for (int c = 0; c < 8; ++c) raw[c] = q[kBrickPoints[child][c]];
                const glm::uvec3 o = it.origin + glm::uvec3(child & 1, (child >> 1) & 1, child >> 2) * half;
                if (!keep(o, half) || !keepLeaf(o, half)) continue;
                BoundaryCell b{o, half, {}, true};
                for (int c = 0; c < 8; ++c) b.corners[c] = float(raw[c]) * scale;
                out.push_back(b);
            }
        }
    }
}

}  // namespace

void appendBoundaryCells(const adf::Tile& t, int maxLevel, std::vector<BoundaryCell>& out) {
    auto all = [](glm::uvec3, uint32_t) { return true; };
    appendIf(t, maxLevel, out, all, all);
}

void appendBoundaryCellsTouching(const adf::Tile& t, int maxLevel, const std::vector<LatticeBox>& boxes,
                                 std::vector<BoundaryCell>& out, LeafFilter filter) {
    auto touching = [&](glm::uvec3 o, uint32_t size) {
        for (const LatticeBox& b : boxes)
            if (touches(b, o, size)) return true;
        return false;
    };
    appendIf(t, maxLevel, out, touching,
             [&](glm::uvec3 o, uint32_t size) { return !filter.keep || filter.keep(filter.context, o, size); });
}

}  // namespace kizamu::adf
