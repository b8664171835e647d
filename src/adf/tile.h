// SPDX-License-Identifier: Apache-2.0
/// @file tile.h
/// @brief One stored tile: an immutable block holding an octree subtree and its corner distances.
///
/// The tile is the unit of storage, editing, concurrency and undo (design brief). Cells are a
/// flat array of 32-bit node words (children of a node are 8 consecutive words, depth first),
/// and each leaf owns 8 corner distances quantised to 16 bits with one scale per tile
/// (docs/ARCHITECTURE.md gives the measurements behind that choice).
/// A tile never changes after `create`; any number of threads may read it. Edits build new
/// tiles; old ones are freed through epochs once no reader can see them (snapshot_store.h).
#pragma once

#include "adf/domain.h"

#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>

namespace kizamu::adf {

/// What a leaf cell holds: all corners outside, all inside, or a sign change (the surface).
enum class CellType : uint8_t { Exterior = 0, Interior = 1, Boundary = 2 };

/// Node word encoding. Internal node: index of its first child (bit 31 clear, never 0).
/// Leaf: bit 31 set, bits 29-30 the CellType, bits 0-28 the leaf index.
namespace node {
inline constexpr uint32_t kLeafBit = 1u << 31;
inline constexpr uint32_t kIndexMask = (1u << 29) - 1;
inline constexpr bool isLeaf(uint32_t w) { return (w & kLeafBit) != 0; }
inline constexpr uint32_t leafIndex(uint32_t w) { return w & kIndexMask; }
inline constexpr CellType leafType(uint32_t w) { return CellType((w >> 29) & 3u); }
inline constexpr uint32_t makeLeaf(uint32_t index, CellType t) {
    return kLeafBit | (uint32_t(t) << 29) | index;
}
}  // namespace node

/// Corner order everywhere: corner c sits at (c & 1, (c >> 1) & 1, (c >> 2) & 1).
CellType cellTypeOf(std::span<const float, 8> corners);

/// Immutable subtree block. Owned through std::shared_ptr by snapshots (writer side only).
class Tile {
public:
    /// Builds a tile from float corner distances (8 per leaf, m), quantising them.
    /// @param level           octree level of the tile root (<= domain tile level)
    /// @param latticeOrigin   minimum corner of the tile root, lattice units
    /// @param nodes           node words, root first (see node::)
    /// @param leafCorners     8 values per leaf in corner order, m
    /// @param version         snapshot version that created it (readers check it)
    /// Complexity: O(nodes + leaves). Threading: any thread. Memory: one allocation.
    static std::shared_ptr<const Tile> create(int level, glm::uvec3 latticeOrigin,
                                              std::span<const uint32_t> nodes,
                                              std::span<const float> leafCorners,
                                              uint64_t version);
    /// Builds a tile from already quantised data (file loading). Checksum is recomputed.
    static std::shared_ptr<const Tile> createQuantised(int level, glm::uvec3 latticeOrigin,
                                                       std::span<const uint32_t> nodes,
                                                       std::span<const int16_t> leafCorners,
                                                       float scale, uint64_t version);

    int level() const { return mLevel; }
    glm::uvec3 latticeOrigin() const { return mOrigin; }
    uint32_t nodeCount() const { return mNodeCount; }
    uint32_t leafCount() const { return mLeafCount; }
    const uint32_t* nodes() const { return mNodes; }
    const int16_t* corners() const { return mCorners; }  ///< 8 per leaf
    float scale() const { return mScale; }               ///< m per quantisation step
    uint64_t version() const { return mVersion; }
    uint64_t checksum() const { return mChecksum; }
    /// Bytes of the block (header and arrays).
    std::size_t bytes() const;
    /// FNV-1a of level, origin, scale, nodes and corners: equals checksum() unless memory is bad.
    uint64_t computeChecksum() const;
    /// True when the whole tile is one leaf cell.
    bool singleLeaf() const { return mNodeCount == 1; }
    /// Type of the root when singleLeaf().
    CellType rootType() const { return node::leafType(mNodes[0]); }
    /// Decoded corner distance, m.
    float corner(uint32_t leaf, int c) const { return float(mCorners[8 * leaf + c]) * mScale; }

    ~Tile();
    Tile(const Tile&) = delete;
    Tile& operator=(const Tile&) = delete;

private:
    Tile() = default;
    static Tile* allocate(uint32_t nodeCount, uint32_t leafCount);
    struct Deleter {
        void operator()(const Tile* t) const;
    };

    uint64_t mMagic = 0;  ///< kAlive while valid; poisoned by the destructor
    uint64_t mVersion = 0;
    uint64_t mChecksum = 0;
    const uint32_t* mNodes = nullptr;
    const int16_t* mCorners = nullptr;
    glm::uvec3 mOrigin{0};
    uint32_t mNodeCount = 0;
    uint32_t mLeafCount = 0;
    float mScale = 0.0f;
    int mLevel = 0;

public:
    static constexpr uint64_t kAlive = 0x4b5a54494c45a11eull;
    /// False for a freed (poisoned) tile: lets the stress test catch use after free.
    bool alive() const { return mMagic == kAlive; }
};

using TilePtr = std::shared_ptr<const Tile>;

}  // namespace kizamu::adf
