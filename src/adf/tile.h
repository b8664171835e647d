// SPDX-License-Identifier: Apache-2.0
/// @file tile.h
/// @brief One stored tile: an immutable block holding an octree subtree and its corner distances.
///
/// The tile is the unit of storage, editing, concurrency and undo (design brief). Cells are a
/// flat array of node words (children of a node are 8 consecutive words, depth first), 32-bit to
/// readers (Tile::node) and stored in 16 bits when every word of the tile fits (node::narrow).
/// A lone leaf owns its 8 corner distances; a cell whose 8 children are all leaves is stored as
/// a *brick*: one node word and the 27 distances of its 3x3x3 half grid, which the 8 children
/// share (27 values instead of 8 words and 64 values). Distances are quantised to 16 bits with
/// one scale per tile (docs/decisions/0003-bricks-and-packed-forms.md,
/// docs/decisions/0002-16-bit-distances-per-tile-scale.md).
/// A brick's values are stored *packed* where they fit: its centre as 16 bits and the other 26
/// as signed steps from it, counting *leaf steps* (below: 127 of them span four finest cells).
/// A brick whose values all lie within 63 leaf steps of its centre (every brick of finest
/// cells, at most sqrt(3) cells from their centre in a 1-Lipschitz field) is stored *narrow*:
/// 7 bits a step, 25 bytes instead of 54. One within 127 leaf steps (bricks of two-cell
/// children) is stored *coarse-narrow*: a byte a step, 28 bytes. One within 127 *far steps*
/// (two leaf steps) where every value rounds to within one leaf step, as a packed value always
/// does (bricks of four-cell children, away from the surface), is stored *far*: a byte a step.
/// Other bricks stay *wide* (27 x 16 bits). The steps are fixed per tile from its scale and the
/// finest cell size, never chosen from the values, so the encoding is idempotent (decode,
/// re-encode: same bits). The numbering is narrow bricks first, then coarse-narrow, far, wide;
/// readers tell the forms apart by index range. Encoding tries them in that order: a
/// coarse-narrow brick has a value at 64 leaf steps or more and a far one at 128 or more
/// (exactly, once decoded), so neither re-encodes in an earlier form.
/// Lone leaves are packed in leaf steps too: a leaf whose corners all lie within 127 leaf
/// steps of its corner 0 (every leaf of two finest cells in a 1-Lipschitz field) is stored
/// *narrow*: corner 0 as 16 bits, the other 7 as signed bytes counting leaf steps from it (9
/// bytes instead of 16). Other leaves stay wide (8 x 16 bits); narrow leaves come first in the
/// leaf numbering. Every packing keeps the sign of every value (inside stays inside, outside
/// outside) and is idempotent.
/// A cell with at least kMinGroupLeaves lone-leaf children whose shared corners agree (the
/// same samples: what generation gives) stores them as one *leaf group*: its 27-value half
/// grid, packed like a brick (narrow, coarse-narrow, far) or wide, which all its lone-leaf children
/// read (25 or 28 bytes for up to 8 leaves instead of 9 or 16 each). Grouped leaves take
/// indices 8g + child; a group's unused slots are never referenced. Where a cell's lone leaves
/// disagree at a shared corner they stay on their own, and wide where their packed corners
/// would agree (so that decoding and building again never groups them): grouping is
/// idempotent like the packing. Files keep 8 corners per leaf (the writer decodes them).
/// The header keeps byte offsets of the arrays, not pointers, and so stays at 128 bytes.
/// A tile never changes after `create`; any number of threads may read it. Edits build new
/// tiles; old ones are freed through epochs once no reader can see them (snapshot_store.h).
#pragma once

#include "adf/domain.h"

#include <glm/vec3.hpp>

#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>
#include <span>
#include <vector>

namespace kizamu::adf {

/// What a leaf cell holds: all corners outside, all inside, or a sign change (the surface).
enum class CellType : uint8_t { Exterior = 0, Interior = 1, Boundary = 2 };

/// Node word encoding.
/// - internal node: bits 30-31 clear, the index of its first child (never 0);
/// - leaf: bit 31 set, bits 29-30 the CellType, bits 0-28 the leaf index (8 corners each);
/// - brick (a cell whose 8 children are leaves): bit 30 set, bits 0-29 the brick index (27 values).
namespace node {
inline constexpr uint32_t kLeafBit = 1u << 31;
inline constexpr uint32_t kBrickBit = 1u << 30;
inline constexpr uint32_t kIndexMask = (1u << 29) - 1;
inline constexpr uint32_t kBrickMask = (1u << 30) - 1;
inline constexpr bool isLeaf(uint32_t w) { return (w & kLeafBit) != 0; }
inline constexpr bool isBrick(uint32_t w) { return (w & (kLeafBit | kBrickBit)) == kBrickBit; }
inline constexpr bool isInternal(uint32_t w) { return (w & (kLeafBit | kBrickBit)) == 0; }
inline constexpr uint32_t leafIndex(uint32_t w) { return w & kIndexMask; }
inline constexpr uint32_t brickIndex(uint32_t w) { return w & kBrickMask; }
inline constexpr CellType leafType(uint32_t w) { return CellType((w >> 29) & 3u); }
inline constexpr uint32_t makeLeaf(uint32_t index, CellType t) {
    return kLeafBit | (uint32_t(t) << 29) | index;
}
inline constexpr uint32_t makeBrick(uint32_t index) { return kBrickBit | index; }

/// The 16-bit form a tile uses when all its words fit (most do: a tile holds a few thousand
/// nodes): leaf bit 15, CellType in bits 13-14 and index in 0-12; brick bit 14 and index in
/// 0-13; an internal node's first child below 2^14. Readers see the 32-bit words only.
inline constexpr bool fitsNarrow(uint32_t w) {
    if (isLeaf(w)) return leafIndex(w) < (1u << 13);
    return (w & kBrickMask) < (1u << 14);  // a brick's index or an internal node's first child
}
inline constexpr uint16_t narrow(uint32_t w) {
    if (isLeaf(w)) return uint16_t(0x8000u | ((w >> 16) & 0x6000u) | leafIndex(w));
    return uint16_t((isBrick(w) ? 0x4000u : 0u) | (w & kBrickMask));
}
inline constexpr uint32_t widen(uint16_t w) {
    if (w & 0x8000u) return kLeafBit | (uint32_t(w & 0x6000u) << 16) | (w & 0x1fffu);
    if (w & 0x4000u) return kBrickBit | (w & 0x3fffu);
    return w;
}
}  // namespace node

/// Half-grid point g = i + 3j + 9k (i, j, k in 0..2) of a brick holding corner `c` of child `child`.
inline constexpr int brickPoint(int child, int c) {
    return ((child & 1) + (c & 1)) + 3 * (((child >> 1) & 1) + ((c >> 1) & 1)) +
           9 * ((child >> 2) + (c >> 2));
}

/// Corner order everywhere: corner c sits at (c & 1, (c >> 1) & 1, (c >> 2) & 1).
CellType cellTypeOf(std::span<const float, 8> corners);

class Tile;

/// Items of a tile being built that copy another tile's unchanged (regeneration keeps the old
/// tile's cells outside its edit): for each lone leaf and each brick of the new tile, the index
/// of the item of `from` it copies, or kNotCopied. Their values must be the ones `from` decodes
/// for them.
struct TileCopies {
    static constexpr uint32_t kNotCopied = ~0u;
    const Tile* from = nullptr;
    std::span<const uint32_t> leaves, bricks;
};

/// Immutable subtree block. Owned through std::shared_ptr by snapshots (writer side only).
class Tile {
public:
    /// Builds a tile from float distances (m), quantising them.
    /// @param level           octree level of the tile root (<= domain tile level)
    /// @param latticeOrigin   minimum corner of the tile root, lattice units
    /// @param nodes           node words, root first (see node::)
    /// @param leafCorners     8 values per leaf in corner order
    /// @param brickValues     27 values per brick in half-grid order
    /// @param version         snapshot version that created it (readers check it)
    /// @param finestCell      the domain's finest cell size, m (sets the leaf step)
    /// @param keepScale       a scale to keep when every value fits it and it is at most twice
    ///                        what the values need (0: none). Regeneration
    ///                        passes the old tile's, so cells it copies keep their bits and
    ///                        the mesher sees them unchanged.
    /// @param copies          items that copy another tile's (none by default): where the new
    ///                        tile keeps that tile's scale (and so its steps), their packed
    ///                        bytes are taken as they are instead of being quantised and packed
    ///                        again, which gives the same bits (the encodings are idempotent).
    /// Brick and leaf indices in `nodes` are renumbered (by form, in the order above); the field
    /// is unchanged but for packed values' rounding to the leaf step: a packed brick or group
    /// value (far ones too) and a narrow leaf's corner but corner 0 within one leaf step
    /// (4/127 finest cell, rounded up to whole quantisation steps); half a step but where
    /// keeping the sign takes the step on the value's own side. A brick's centre is exact.
    /// Complexity: O(nodes + values). Threading: any thread. Memory: one allocation.
    static std::shared_ptr<const Tile> create(int level, glm::uvec3 latticeOrigin,
                                              std::span<const uint32_t> nodes,
                                              std::span<const float> leafCorners,
                                              std::span<const float> brickValues, uint64_t version,
                                              double finestCell, float keepScale = 0.0f, const TileCopies& copies = {});
    /// Builds a tile from already quantised data (file loading). Checksum is recomputed. Brick
    /// and leaf words with an index out of range are left as they are (the file loader rejects
    /// such leaf indices before building, the tree validation such bricks after).
    static std::shared_ptr<const Tile> createQuantised(int level, glm::uvec3 latticeOrigin,
                                                       std::span<const uint32_t> nodes,
                                                       std::span<const int16_t> leafCorners,
                                                       std::span<const int16_t> brickValues,
                                                       float scale, uint64_t version, double finestCell);

    int level() const { return mLevel; }
    glm::uvec3 latticeOrigin() const { return {mOrigin[0], mOrigin[1], mOrigin[2]}; }
    uint32_t nodeCount() const { return mNodeCount; }
    /// True when the node words are stored in 16 bits (node::narrow), half the bytes.
    bool narrowNodes() const { return mNarrowNodes; }
    /// Bytes of the node words as stored.
    std::size_t nodeBytes() const { return std::size_t(mNodeCount) * (mNarrowNodes ? 2 : 4); }
    /// Leaf indices: 8 per leaf group (slot 8g + child; a slot whose child is not a lone leaf is
    /// never referenced), then narrow lone leaves, then wide ones. Every index below this decodes.
    uint32_t leafCount() const { return mLeafCount; }
    uint32_t groupCount() const { return mGroupCount; }              ///< leaf groups, packed and wide
    uint32_t narrowGroupCount() const { return mNarrowGroupCount; }  ///< groups 0 .. this - 1 are narrow (7-bit leaf steps)
    uint32_t packedGroupCount() const { return mPackedGroupCount; }  ///< groups 0 .. this - 1 are packed (narrow, coarse-narrow, far)
    uint32_t farGroupCount() const { return mPackedGroupCount - mCoarseGroupEnd; }  ///< the last of the packed groups are far
    uint32_t groupedLeafCount() const { return mGroupedLeafCount; }  ///< lone leaves stored in groups
    /// Lone leaves stored on their own (not in a group), narrow and wide.
    uint32_t ownLeafCount() const { return mLeafCount - 8 * mGroupCount; }
    /// Of them narrow: indices 8 groupCount() .. that + this - 1.
    uint32_t narrowLeafCount() const { return mNarrowLeafCount; }
    /// True when leaf `leaf`'s corners are packed (rounded to the leaf step; corner 0 or the
    /// group's centre exact): packed groups and narrow own leaves.
    bool packedLeaf(uint32_t leaf) const {
        const uint32_t grouped = 8 * mGroupCount;
        return leaf < grouped ? leaf < 8 * mPackedGroupCount : leaf - grouped < mNarrowLeafCount;
    }
    int32_t leafStep() const { return mStep; }  ///< quantisation steps per leaf step (every packed value counts them)
    uint32_t brickCount() const { return mBrickCount; }   ///< narrow, coarse-narrow, far and wide
    uint32_t narrowBrickCount() const { return mNarrowCount; }  ///< bricks 0 .. this - 1 are narrow (7-bit steps)
    /// Bricks narrowBrickCount() .. that + this - 1 are coarse-narrow (8-bit leaf steps).
    uint32_t coarseBrickCount() const { return mCoarseEnd - mNarrowCount; }
    /// The bricks after them up to packedBrickCount() - 1 are far (8-bit far steps).
    uint32_t farBrickCount() const { return mPackedCount - mCoarseEnd; }
    uint32_t packedBrickCount() const { return mPackedCount; }  ///< narrow, coarse-narrow and far
    /// Bytes of one stored item of each form (the layout in tile.cpp), for accounting. Bricks
    /// and groups are half grids: a centre and 26 steps of 7 bits (narrow) or 8 (coarse-narrow,
    /// far), or 27 values of 16 bits (wide).
    static constexpr std::size_t kNarrowLeafBytes = 2 + 7, kWideLeafBytes = 8 * 2;
    static constexpr std::size_t kNarrowGridSteps = (26 * 7 + 7) / 8, kCoarseGridSteps = 26;
    static constexpr std::size_t kNarrowGridBytes = 2 + kNarrowGridSteps, kCoarseGridBytes = 2 + kCoarseGridSteps,
                                 kWideGridBytes = 27 * 2;
    /// Lone-leaf children a cell needs for them to be stored as a group (fewer cost less alone).
    static constexpr int kMinGroupLeaves = 4;
    /// Leaf cells: lone leaves (own and grouped) plus 8 per brick.
    std::size_t cellCount() const {
        return std::size_t(ownLeafCount()) + mGroupedLeafCount + 8 * std::size_t(mBrickCount);
    }
    /// Node word `i` in the 32-bit encoding of node::, whichever width the tile stores.
    uint32_t node(uint32_t i) const {
        return mNarrowNodes ? node::widen(at<uint16_t>(mNodesAt)[i]) : at<uint32_t>(mNodesAt)[i];
    }
    /// Every node word in the 32-bit encoding (files, copies, tests).
    std::vector<uint32_t> nodeWords() const;
    /// The tile as createQuantised takes it: 32-bit node words with the lone leaves numbered
    /// densely in index order (a group's unused slots skipped), 8 quantised corners per leaf
    /// and 27 values per brick, packed ones decoded. Files store this; building it again at
    /// the tile's scale gives the same tile. Complexity: O(nodes + values).
    struct Quantised {
        std::vector<uint32_t> nodes;
        std::vector<int16_t> leafCorners, brickValues;
    };
    Quantised quantised() const;
    /// Quantised corner `c` of lone leaf `leaf`.
    int16_t leafValue(uint32_t leaf, int c) const {
        const uint32_t grouped = 8 * mGroupCount;
        if (leaf < grouped) {
            int16_t q;
            decodeGroup(leaf, brickPoint(int(leaf & 7u), c), kOnePoint, &q);
            return q;
        }
        leaf -= grouped;
        if (leaf < mNarrowLeafCount) {
            const int32_t base = at<int16_t>(mLeafBasesAt)[leaf];
            return c == 0 ? int16_t(base)
                          : int16_t(base + int32_t(at<int8_t>(mLeafDeltasAt)[7 * leaf + uint32_t(c - 1)]) * mStep);
        }
        return at<int16_t>(mWideLeavesAt)[8 * (leaf - mNarrowLeafCount) + uint32_t(c)];
    }
    /// The 8 quantised corners of lone leaf `leaf` (one branch on its form for all of them: the
    /// haptic path).
    void leafValues(uint32_t leaf, int16_t out[8]) const {
        const uint32_t grouped = 8 * mGroupCount;
        if (leaf < grouped) {
            decodeGroup(leaf, brickPoint(int(leaf & 7u), 0), kChildCornerPoints, out);
            return;
        }
        leaf -= grouped;
        if (leaf < mNarrowLeafCount) {
            unpackLeaf(at<int16_t>(mLeafBasesAt)[leaf], at<int8_t>(mLeafDeltasAt) + 7 * std::size_t(leaf), leafStep(), out);
        } else {
            const int16_t* q = at<int16_t>(mWideLeavesAt) + 8 * std::size_t(leaf - mNarrowLeafCount);
            for (int c = 0; c < 8; ++c) out[c] = q[c];
        }
    }
    /// The 8 decoded corners of lone leaf `leaf`, m (float(value) * scale, as corner() gives).
    void leafCorners(uint32_t leaf, float out[8]) const {
        int16_t q[8];
        leafValues(leaf, q);
        for (int c = 0; c < 8; ++c) out[c] = float(q[c]) * mScale;
    }
    /// The 8 decoded corners of child `child` of brick `brick`, m (as brickCorner gives them).
    /// One branch for all of them, as leafCorners.
    void brickCorners(uint32_t brick, int child, float out[8]) const {
        int16_t q[8];
        decodeBrick(brick, brickPoint(child, 0), kChildCornerPoints, q);
        for (int c = 0; c < 8; ++c) out[c] = float(q[c]) * mScale;
    }
    /// Quantised value of half-grid point g (tile.h's brickPoint order) of brick `brick`.
    /// Packed bricks share one layout; the step is a select on the index (no extra branch).
    int16_t brickValue(uint32_t brick, int g) const {
        int16_t q;
        decodeBrick(brick, g, kOnePoint, &q);
        return q;
    }
    /// The 27 quantised values of brick `brick`, as brickValue gives them (one branch for all:
    /// readers comparing or scanning whole bricks).
    void brickValues(uint32_t brick, int16_t out[27]) const { decodeBrick(brick, 0, kBrickPoints, out); }
    /// False where brick `brick`'s stored form alone shows its 27 values share a sign (all
    /// negative or none): a packed brick's values lie within its steps' reach of its centre, so
    /// a centre farther from zero than that needs no decoding. True says nothing.
    bool brickMayChangeSign(uint32_t brick) const {
        if (brick >= mPackedCount) return true;  // wide
        const int32_t reach = brick < mNarrowCount ? 64 * mStep : brick < mCoarseEnd ? 128 * mStep : 256 * mStep;
        const int32_t base = at<int16_t>(mBrickBasesAt)[brick];
        return base - reach < 0 && base + reach >= 0;
    }
    /// Whether brick `brick` and brick `otherBrick` of `other` are stored alike (the same form,
    /// centre, steps and leaf step): then their values are the same, without decoding them
    /// (a rebuilt tile copies most of its bricks so). False says nothing.
    bool storesBrickAs(uint32_t brick, const Tile& other, uint32_t otherBrick) const {
        return mStep == other.mStep && storesGridAs(bricks(), brick, other, other.bricks(), otherBrick);
    }
    /// The same for lone leaf `leaf` and lone leaf `otherLeaf` of `other`: own leaves stored in
    /// the same form with the same bytes, or grouped ones the same child of groups stored alike.
    bool storesLeafAs(uint32_t leaf, const Tile& other, uint32_t otherLeaf) const {
        const uint32_t grouped = 8 * mGroupCount, otherGrouped = 8 * other.mGroupCount;
        if (mStep != other.mStep || (leaf < grouped) != (otherLeaf < otherGrouped)) return false;
        if (leaf < grouped)
            return (leaf & 7u) == (otherLeaf & 7u) && storesGridAs(groups(), leaf >> 3, other, other.groups(), otherLeaf >> 3);
        const uint32_t i = leaf - grouped, j = otherLeaf - otherGrouped;
        const bool narrow = i < mNarrowLeafCount;
        if (narrow != (j < other.mNarrowLeafCount)) return false;
        if (!narrow)
            return std::memcmp(at<int16_t>(mWideLeavesAt) + 8 * std::size_t(i - mNarrowLeafCount),
                               other.at<int16_t>(other.mWideLeavesAt) + 8 * std::size_t(j - other.mNarrowLeafCount),
                               kWideLeafBytes) == 0;
        return at<int16_t>(mLeafBasesAt)[i] == other.at<int16_t>(other.mLeafBasesAt)[j] &&
               std::memcmp(at<int8_t>(mLeafDeltasAt) + 7 * std::size_t(i), other.at<int8_t>(other.mLeafDeltasAt) + 7 * std::size_t(j),
                           7) == 0;
    }
    float scale() const { return mScale; }               ///< m per quantisation step
    uint64_t version() const { return mVersion; }
    uint64_t checksum() const { return mChecksum; }
    /// Bytes of the block (header and arrays).
    std::size_t bytes() const;
    /// FNV-1a of level, origin, scale, nodes, corners and bricks: equals checksum() unless memory
    /// is bad.
    uint64_t computeChecksum() const;
    /// True when the whole tile is one leaf cell.
    bool singleLeaf() const { return mNodeCount == 1 && node::isLeaf(node(0)); }
    /// Type of the root when singleLeaf().
    CellType rootType() const { return node::leafType(node(0)); }
    /// Decoded corner `c` of lone leaf `leaf`, m.
    float corner(uint32_t leaf, int c) const { return float(leafValue(leaf, c)) * mScale; }
    /// Decoded corner `c` of child `child` of brick `brick`, m.
    float brickCorner(uint32_t brick, int child, int c) const {
        return float(brickValue(brick, brickPoint(child, c))) * mScale;
    }

    /// How many items of each stored form the tile holds (own leaves, bricks and leaf groups,
    /// narrow and wide), which fix its layout and bytes (tile.cpp).
    struct Counts {
        uint32_t nodes = 0;
        bool narrowNodes = false;
        uint32_t narrowLeaves = 0, wideLeaves = 0;
        uint32_t narrowBricks = 0, coarseBricks = 0, farBricks = 0, wideBricks = 0;
        uint32_t narrowGroups = 0, coarseGroups = 0, farGroups = 0, wideGroups = 0, groupedLeaves = 0;  ///< as bricks
    };
    Counts counts() const;
    /// Bytes of the stored values (leaf corners, brick and group half grids) of items counted
    /// by `n`: the tile's bytes less its header, node words and padding.
    static std::size_t valueBytes(const Counts& n);
    /// Bytes of half grids (bricks or leaf groups): `narrow` of 25, `packed - narrow` of 28
    /// (coarse-narrow and far) and `all - packed` of 54.
    static constexpr std::size_t gridBytes(std::size_t narrow, std::size_t packed, std::size_t all) {
        return narrow * kNarrowGridBytes + (packed - narrow) * kCoarseGridBytes + (all - packed) * kWideGridBytes;
    }
    /// Where packed half grid `index` keeps its steps, from the start of its steps array: the
    /// `narrowEnd` narrow ones first (7-bit fields), then the others (a byte each). (With
    /// index = packed count, the bytes of them all.)
    static constexpr std::size_t gridStepsOffset(std::size_t narrowEnd, std::size_t index) {
        return index < narrowEnd ? kNarrowGridSteps * index : kNarrowGridSteps * narrowEnd + kCoarseGridSteps * (index - narrowEnd);
    }

    ~Tile();
    Tile(const Tile&) = delete;
    Tile& operator=(const Tile&) = delete;

private:
    Tile() = default;
    static constexpr std::array<int, 27> kBrickPoints{0,  1,  2,  3,  4,  5,  6,  7,  8,  9,  10, 11, 12, 13,
                                                      14, 15, 16, 17, 18, 19, 20, 21, 22, 23, 24, 25, 26};
    static constexpr std::array<int, 1> kOnePoint{0};
    static constexpr std::array<int, 8> kChildCornerPoints{brickPoint(0, 0), brickPoint(0, 1), brickPoint(0, 2),
                                                           brickPoint(0, 3), brickPoint(0, 4), brickPoint(0, 5),
                                                           brickPoint(0, 6), brickPoint(0, 7)};
    /// The quantised values of half-grid points first + points[k] of half grid `index` stored
    /// at `basesAt`/`stepsAt` (packed: a centre and 26 steps: leaf steps of 7 bits below
    /// `narrowEnd`, then leaf steps of a byte below `coarseEnd`, far steps of a byte below
    /// `packedEnd`) or `wideAt` (27 x 16 bits), with one branch on the form for all of them:
    /// bricks and leaf groups share it.
    template <std::size_t N>
    void decodeGrid(uint32_t basesAt, uint32_t stepsAt, uint32_t wideAt, uint32_t narrowEnd, uint32_t coarseEnd,
                    uint32_t packedEnd, uint32_t index, int first, const std::array<int, N>& points,
                    int16_t* out) const {
        if (index < packedEnd) {
            const int32_t base = at<int16_t>(basesAt)[index];
            const unsigned char* p = at<unsigned char>(stepsAt) + gridStepsOffset(narrowEnd, index);
            if (index < narrowEnd) {
                if constexpr (N == 27) {
                    unpackNarrowGrid(p, base, mStep, out);  // every point (first is 0): a block at a time
                } else {
                    for (std::size_t k = 0; k < N; ++k) out[k] = int16_t(base + narrowGridStep(p, first + points[k]) * mStep);
                }
            } else {
                const int32_t step = index < coarseEnd ? mStep : 2 * mStep;
                for (std::size_t k = 0; k < N; ++k) out[k] = int16_t(base + coarseGridStep(p, first + points[k]) * step);
            }
        } else {
            const int16_t* q = at<int16_t>(wideAt) + 27 * std::size_t(index - packedEnd) + first;
            for (std::size_t k = 0; k < N; ++k) out[k] = q[points[k]];
        }
    }
    /// One family of half grids (bricks, or leaf groups): where its arrays start, and where the
    /// numbers of each form end (narrow, coarse-narrow, far, then wide).
    struct Grids {
        uint32_t basesAt, stepsAt, wideAt, narrowEnd, coarseEnd, packedEnd;
        int form(uint32_t i) const { return i < narrowEnd ? 0 : i < coarseEnd ? 1 : i < packedEnd ? 2 : 3; }
    };
    Grids bricks() const { return {mBrickBasesAt, mBrickDeltasAt, mWideBricksAt, mNarrowCount, mCoarseEnd, mPackedCount}; }
    Grids groups() const {
        return {mGroupBasesAt, mGroupDeltasAt, mWideGroupsAt, mNarrowGroupCount, mCoarseGroupEnd, mPackedGroupCount};
    }
    /// Whether half grid `index` of `mine` is stored as `otherIndex` of `other`'s `theirs`: the
    /// same form, and the same centre and steps, or the same 27 values when wide.
    bool storesGridAs(const Grids& mine, uint32_t index, const Tile& other, const Grids& theirs, uint32_t otherIndex) const {
        const int f = mine.form(index);
        if (f != theirs.form(otherIndex)) return false;
        if (f == 3)
            return std::memcmp(at<int16_t>(mine.wideAt) + 27 * std::size_t(index - mine.packedEnd),
                               other.at<int16_t>(theirs.wideAt) + 27 * std::size_t(otherIndex - theirs.packedEnd),
                               kWideGridBytes) == 0;
        return at<int16_t>(mine.basesAt)[index] == other.at<int16_t>(theirs.basesAt)[otherIndex] &&
               std::memcmp(at<unsigned char>(mine.stepsAt) + gridStepsOffset(mine.narrowEnd, index),
                           other.at<unsigned char>(theirs.stepsAt) + gridStepsOffset(theirs.narrowEnd, otherIndex),
                           f == 0 ? kNarrowGridSteps : kCoarseGridSteps) == 0;
    }
    /// A packed half grid stores the steps of its 26 points other than the centre (point 13,
    /// whose step is 0), in point order: field j holds point gridPointOf(j).
    static constexpr int fieldOf(int g) { return g - (g > 13); }
    static constexpr int gridPointOf(int j) { return j + (j >= 13); }
    /// Leaf steps of half-grid point g from the centre (0 at the centre): 7-bit fields packed
    /// little-endian from bit 0.
    static int32_t narrowGridStep(const unsigned char* p, int g) {
        const unsigned bit = 7u * unsigned(fieldOf(g));
        const unsigned pair = unsigned(p[bit >> 3]) | unsigned(p[(bit >> 3) + 1]) << 8;
        const int32_t k = int32_t((pair >> (bit & 7u)) << 25) >> 25;  // sign-extend 7 bits
        return g == 13 ? 0 : k;
    }
    /// All 27 values of a narrow half grid from its centre `base` and its fields (`step` quantisation
    /// steps each): 8 fields fill 7 bytes exactly, so they are read a 56-bit block at a time (one
    /// load of 8 bytes each for the first three, which stays inside the item's 23).
    static void unpackNarrowGrid(const unsigned char* p, int32_t base, int32_t step, int16_t* out) {
        static_assert(std::endian::native == std::endian::little, "fields are read as little-endian words");
        out[13] = int16_t(base);
#pragma GCC unroll 4
        for (int block = 0; block < 4; ++block) {
            const int fields = block < 3 ? 8 : 2;
            uint64_t w = 0;
            std::memcpy(&w, p + 7 * block, block < 3 ? 8 : 2);
#pragma GCC unroll 8
            for (int f = 0; f < fields; ++f) {
                const int32_t k = int32_t(uint32_t(w >> (7 * f)) << 25) >> 25;  // sign-extend 7 bits
                out[gridPointOf(8 * block + f)] = int16_t(base + k * step);
            }
        }
    }
    /// The same with a signed byte per point.
    static int32_t coarseGridStep(const unsigned char* p, int g) {
        const int32_t k = int8_t(p[fieldOf(g)]);
        return g == 13 ? 0 : k;
    }
    /// Brick `brick`'s values (brickValues, brickCorners; brickValue is the one-point case).
    template <std::size_t N>
    void decodeBrick(uint32_t brick, int first, const std::array<int, N>& points, int16_t* out) const {
        decodeGrid(mBrickBasesAt, mBrickDeltasAt, mWideBricksAt, mNarrowCount, mCoarseEnd, mPackedCount, brick, first,
                   points, out);
    }
    /// Grouped leaf `leaf`'s values: its group's half grid (all leaf steps when packed).
    template <std::size_t N>
    void decodeGroup(uint32_t leaf, int first, const std::array<int, N>& points, int16_t* out) const {
        decodeGrid(mGroupBasesAt, mGroupDeltasAt, mWideGroupsAt, mNarrowGroupCount, mCoarseGroupEnd, mPackedGroupCount,
                   leaf >> 3, first, points, out);
    }
    /// A narrow own leaf's 8 corners from its corner 0 and 7 steps of `step` (Tile::leafValues,
    /// and Tile::build, which asks what a packed leaf would decode to).
    static void unpackLeaf(int32_t base, const int8_t* steps, int32_t step, int16_t out[8]) {
        out[0] = int16_t(base);
        for (int c = 1; c < 8; ++c) out[c] = int16_t(base + int32_t(steps[c - 1]) * step);
    }
    /// The array at byte offset `offset` from the start of the block (arrays follow the header).
    template <class T>
    const T* at(uint32_t offset) const {
        return reinterpret_cast<const T*>(reinterpret_cast<const unsigned char*>(this) + offset);
    }
    /// How brick `brick` is stored, by its number: 0 narrow, 1 coarse-narrow, 2 far, 3 wide
    /// (tile.cpp's GridForm order).
    int brickForm(uint32_t brick) const { return bricks().form(brick); }
    static Tile* allocate(const Counts& n);
    struct Packing;  ///< build's packing steps (tile.cpp)
    /// Shared tail of both create functions: quantised leaves and bricks in, narrow ones packed
    /// (`copies`, whose source must share the scale: take its packing; of a copied packed brick
    /// only the centre, value 13, is read: its steps are its source's bytes).
    static std::shared_ptr<const Tile> build(int level, glm::uvec3 latticeOrigin, std::span<const uint32_t> nodes,
                                             std::span<const int16_t> leafCorners, std::span<const int16_t> brickValues,
                                             float scale, uint64_t version, double finestCell, const TileCopies& copies = {});
    /// Sets the header of a filled block, seals it with its checksum and hands it out.
    static std::shared_ptr<const Tile> finish(Tile* t, int level, glm::uvec3 latticeOrigin, float scale,
                                              uint64_t version);
    struct Deleter {
        void operator()(const Tile* t) const;
    };

    uint64_t mMagic = 0;  ///< kAlive while valid; poisoned by the destructor
    uint64_t mVersion = 0;
    uint64_t mChecksum = 0;
    // Byte offsets of the arrays from the start of the block (half a pointer's bytes each).
    uint32_t mNodesAt = 0;        ///< node words, 32 or (mNarrowNodes) 16 bits
    uint32_t mWideLeavesAt = 0;   ///< 8 x int16 per wide own leaf
    uint32_t mLeafBasesAt = 0;    ///< int16 corner 0 of each narrow own leaf
    uint32_t mLeafDeltasAt = 0;   ///< 7 x int8 per narrow own leaf, leaf steps from corner 0
    uint32_t mBrickBasesAt = 0;   ///< int16 centre of each narrow and coarse-narrow brick
    uint32_t mBrickDeltasAt = 0;  ///< 26 x 7 bits per narrow brick, then 26 x int8 per coarse-narrow and far one
    uint32_t mWideBricksAt = 0;   ///< 27 x int16 per wide brick
    uint32_t mGroupBasesAt = 0;   ///< int16 centre of each packed leaf group
    uint32_t mGroupDeltasAt = 0;  ///< leaf steps, as for bricks
    uint32_t mWideGroupsAt = 0;   ///< 27 x int16 per wide leaf group
    uint16_t mOrigin[3] = {0, 0, 0};  ///< lattice coordinates: below 2^16 (level 16 at most)
    uint32_t mNodeCount = 0;
    uint32_t mLeafCount = 0;
    uint32_t mNarrowLeafCount = 0;
    uint32_t mBrickCount = 0;
    uint32_t mNarrowCount = 0;
    uint32_t mCoarseEnd = 0;    ///< narrow and coarse-narrow bricks
    uint32_t mPackedCount = 0;  ///< narrow, coarse-narrow and far bricks
    uint32_t mGroupCount = 0;
    uint32_t mNarrowGroupCount = 0;  ///< narrow groups (7-bit leaf steps)
    uint32_t mCoarseGroupEnd = 0;    ///< narrow and coarse-narrow groups
    uint32_t mPackedGroupCount = 0;  ///< narrow, coarse-narrow and far groups
    uint32_t mGroupedLeafCount = 0;
    float mScale = 0.0f;
    int16_t mStep = 1;   ///< quantisation steps per leaf step (at most 32767)
    int8_t mLevel = 0;   // with the flag below, keeps the header at 128 bytes (tile_test)
    bool mNarrowNodes = false;

public:
    static constexpr uint64_t kAlive = 0x4b5a54494c45a11eull;
    /// False for a freed (poisoned) tile: lets the stress test catch use after free.
    bool alive() const { return mMagic == kAlive; }
};

using TilePtr = std::shared_ptr<const Tile>;

}  // namespace kizamu::adf
