// SPDX-License-Identifier: Apache-2.0
/// @file generate_keep.cpp
/// @brief Regeneration's keep and copy checks: which cells of a rebuilt tile keep the base
/// snapshot's cells instead of being generated again.
///
/// Takes a cell of a tile being regenerated and where the base's tile holds it (an OldCell,
/// walked down from the root alongside the subdivision, never a fresh descent) and says what the
/// cell keeps: its old cells copied (it lies clear of the edited region, or the source leaves
/// every old value there unchanged), the coarser old leaf it lies in, or nothing (generate it).
/// Copying keeps the old cells' structure and packing exactly (TileCopies), which is what makes
/// a regeneration equal a full generation outside the region.
/// Complexity: O(1) per cell for the region test; O(old cells under it) for the value check and
/// the copy. Threading: reads the immutable base tile; one TileGenerator per task.
#include "adf/generate_tile.h"

#include <algorithm>

namespace kizamu::adf::detail {

bool TileGenerator::outsideRegion(glm::uvec3 o, uint32_t s) const {
    const glm::ivec3 a(mBase + o);
    const int margin = int((s + 1) / 2);
    const glm::ivec3 lo = glm::ivec3(mRegionMin) - margin, hi = glm::ivec3(mRegionMax) + margin;
    return a.x > hi.x || a.y > hi.y || a.z > hi.z || a.x + int(s) < lo.x || a.y + int(s) < lo.y || a.z + int(s) < lo.z;
}

Keep TileGenerator::keepsOldFrom(glm::uvec3 o, uint32_t s, int level, const OldCell& cell) const {
    if (outsideRegion(o, s)) return Keep::Copy;
    if (level >= mDomain.maxLevel) return Keep::No;  // its corners are sampled already
    const double size = double(s) * mDomain.finestCellSize();
    const glm::dvec3 centre = mDomain.originWorld + (glm::dvec3(mBase + o) + 0.5 * double(s)) * mDomain.finestCellSize();
    DistanceSource::Range range = mSource.unchangedRange(centre, size * kHalfDiagonal);
    // The old tile's values are rounded (16-bit steps, and within a leaf step for packed
    // leaves, groups and bricks, far ones too): stay clear of the range's ends by that much.
    const double rounding = double(mOld->scale()) * double(std::max(1, mOld->leafStep()) + 1);
    range.lo += rounding;
    range.hi -= rounding;
    if (range.lo > range.hi || mRule.hidesFeature(mSource, mBase + o, level)) return Keep::No;
    return oldValuesWithin(cell, range);
}

Keep TileGenerator::oldValuesWithin(const OldCell& cell, const DistanceSource::Range& range) const {
    const float scale = mOld->scale();
    // value(k) is a quantised value; all n must decode into the range
    auto inRange = [&](int n, const auto& value) {
        for (int k = 0; k < n; ++k) {
            const double v = double(float(value(k)) * scale);
            if (!(range.lo <= v && v <= range.hi)) return false;
        }
        return true;
    };
    // A leaf's 8 corners decoded at once (one branch on its form: own or grouped, packed or not).
    auto leafValues = [&](uint32_t leaf) {
        std::array<int16_t, 8> q;
        mOld->leafValues(leaf, q.data());
        return [q](int c) { return q[std::size_t(c)]; };
    };
    if (cell.brickChild >= 0) {
        const uint32_t brick = node::brickIndex(cell.word);
        if (!inRange(8, [&](int c) { return mOld->brickValue(brick, brickPoint(cell.brickChild, c)); })) return Keep::No;
        return cell.coarser ? Keep::Leaf : Keep::Copy;
    }
    if (cell.coarser) return inRange(8, leafValues(node::leafIndex(cell.word))) ? Keep::Leaf : Keep::No;
    uint32_t stack[8 * kMaxTileSpan + 8];  // depth-first: at most 7 pending siblings per level
    int top = 0;
    stack[top++] = cell.word;
    while (top > 0) {
        const uint32_t w = stack[--top];
        if (node::isLeaf(w)) {
            if (!inRange(8, leafValues(node::leafIndex(w)))) return Keep::No;
        } else if (node::isBrick(w)) {
            const uint32_t brick = node::brickIndex(w);
            if (!inRange(27, [&](int g) { return mOld->brickValue(brick, g); })) return Keep::No;
        } else {
            for (uint32_t c = 0; c < 8; ++c) stack[top++] = mOld->node(w + c);
        }
    }
    return Keep::Copy;
}

bool TileGenerator::copyOld(uint32_t nodeIndex, const OldCell& cell) {
    if (cell.coarser) return false;
    if (cell.brickChild >= 0) {
        float corners[8];
        for (int c = 0; c < 8; ++c) corners[c] = mOld->brickCorner(node::brickIndex(cell.word), cell.brickChild, c);
        makeLeaf(nodeIndex, corners);
        return true;
    }
    copySubtree(nodeIndex, cell.word);
    return true;
}

void TileGenerator::copySubtree(uint32_t nodeIndex, uint32_t w) {
    const float scale = mOld->scale();
    if (node::isLeaf(w)) {
        float corners[8];
        mOld->leafCorners(node::leafIndex(w), corners);
        makeLeaf(nodeIndex, corners, node::leafIndex(w));
    } else if (node::isBrick(w)) {
        int16_t q[27];
        mOld->brickValues(node::brickIndex(w), q);  // one branch on the brick's form for all
        float values[27];
        for (int g = 0; g < 27; ++g) values[g] = float(q[g]) * scale;
        makeBrick(nodeIndex, values, node::brickIndex(w));
    } else {
        const auto first = uint32_t(mNodes.size());
        mNodes.resize(first + 8);
        for (int c = 0; c < 8; ++c) copySubtree(first + uint32_t(c), mOld->node(w + uint32_t(c)));
        mNodes[nodeIndex] = first;
    }
}

}  // namespace kizamu::adf::detail
