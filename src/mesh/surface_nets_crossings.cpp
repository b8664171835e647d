// SPDX-License-Identifier: Apache-2.0
/// @file surface_nets_crossings.cpp
/// @brief Boundary leaves -> crossings: the minimal sign-changing edges a tile's leaves emit,
/// with the ring of leaves around each (the build and the update alike), and a build's border
/// list.
///
/// Takes in: a tile's boundary leaves (decoded corners, in walk order for a build, any order for
/// an update) and the snapshot, for the leaves around their edges. Produces: one Crossing per
/// minimal sign-changing edge, emitted by the smallest leaf around it (the first in quadrant
/// order among equals), with its ring of four leaves and its zero-crossing point; edges a
/// smaller leaf splits, or whose ring leaves the domain, emit nothing.
/// Complexity: O(boundary leaves x 12 edges); a ring leaf is found in O(1) where it is a leaf
/// of the same tile (PlaceTable) or a brick sibling, else by the leaf locator's cached descent.
/// Threading: one call per tile, on the tile's task; reads the snapshot, writes the tile's pool.
#include "mesh/surface_nets_internal.h"

#include "mesh/surface_nets_cell.h"

#include <algorithm>
#include <array>
#include <bit>

namespace kizamu::mesh::detail {

using adf::Adf;
using adf::Tile;

namespace {

/// A leaf around an edge, as a crossing's ring records it: packed origin, size in lattice
/// units, level.
struct RingLeaf {
    uint64_t cell;
    uint32_t size;
    uint32_t level;
};

/// The leaf containing a lattice point (like Adf::locateLeaf), for the neighbours of a leaf of
/// a given size: where that leaf is smaller, any smaller cell (all the callers ask then).
/// Two caches:
/// - the leaf found, by the block of the given size holding the point: neighbouring leaves
///   ask about the same blocks. Where the leaf is no smaller than the block it holds the whole
///   block (cells nest); where it is smaller, so is the leaf at any point of the block.
///   Direct-mapped: a collision only costs a search (callers copy what they need before the
///   next lookup).
/// - the path of the last search: a search near it climbs only to their common cell. It keeps
///   node indices only: a cell's size and origin follow from its depth and the point, and a
///   child's index from one bit per axis (sizes are powers of two: shifts, no divisions).
/// Why a second cached descent beside adf::AdfAccessor (which caches the path and the leaf's
/// decoded corners, for sampling): the mesher asks by block and needs the leaf's origin and
/// level, never its values, and most asks repeat a block a neighbouring leaf asked about, which
/// the block cache answers with no descent at all; the path alone (what the accessor offers,
/// without its decoding) costs measurably more (docs/decisions/0013-leaf-locator-cache.md).
/// One per computeCrossings call (8 KiB of cache, no allocation); not thread-safe.
class LeafLocator {
public:
    explicit LeafLocator(const Adf& adf)
        : mAdf(adf), mMaxLevel(adf.domain().maxLevel),
          mSlotShift(uint32_t(adf.domain().maxLevel - adf.domain().tileLevel())) {
        std::fill(std::begin(mKeys), std::end(mKeys), kEmpty);
    }

    /// The reference stays valid until the next call. By reference: a returned copy is moved
    /// through the stack in overlapping pieces, and the load that reads it back stalls.
    /// `block`: the packed origin of a block of `size` (aligned to it).
    const RingLeaf& locate(uint64_t block, uint32_t size) {
        // Lattice coordinates stay below 2^17: bits 57 up of a packed point are free.
        const uint64_t key = block | (uint64_t(std::countr_zero(size)) << 58);
        const uint32_t i = uint32_t((key * 0x9e3779b97f4a7c15ull) >> (64 - kCacheBits));
        if (mKeys[i] != key) {
            mKeys[i] = key;
            mFound[i] = search(unpackLattice(block));
        }
        return mFound[i];
    }

private:
    RingLeaf search(glm::uvec3 p) {
        if (mDepth > 0) {
            // Keep the cells that hold p: every cell of the path holds the last point, and
            // cells are aligned to their size, so those larger than every bit where p differs
            // from it (entry i has size 2^(rootShift - i)).
            const glm::uvec3 d = p ^ mLast;
            mDepth = std::clamp(mRootShift - int(std::bit_width(d.x | d.y | d.z)) + 1, 0, mDepth);
        }
        if (mDepth == 0) {
            mTile = mAdf.tileAtSlot(p >> mSlotShift);
            mRootShift = mMaxLevel - mTile->level();
            mNode[0] = 0;
            mDepth = 1;
        }
        mLast = p;
        uint32_t w = mTile->node(mNode[mDepth - 1]);
        while (adf::node::isInternal(w)) {
            const int shift = mRootShift - mDepth;  // of the child's size
            const uint32_t child = ((p.x >> shift) & 1u) | (((p.y >> shift) & 1u) << 1) | (((p.z >> shift) & 1u) << 2);
            mNode[mDepth++] = w + child;
            w = mTile->node(w + child);
        }
        const int depth = mDepth - 1 + int(adf::node::isBrick(w));  // a brick: its child holding p
        const uint32_t shift = uint32_t(mRootShift - depth);
        return {packLattice((p >> shift) << shift), 1u << shift, uint32_t(mTile->level() + depth)};
    }

    const Adf& mAdf;
    int mMaxLevel;
    uint32_t mSlotShift;
    /// 1,024 entries (docs/decisions/0013-leaf-locator-cache.md).
    static constexpr int kCacheBits = 10;
    static constexpr uint64_t kEmpty = ~uint64_t(0);
    uint64_t mKeys[1u << kCacheBits];
    RingLeaf mFound[1u << kCacheBits];
    const Tile* mTile = nullptr;
    int mRootShift = 0;  ///< the tile root's size is 2^mRootShift
    glm::uvec3 mLast{0};
    int mDepth = 0;
    uint32_t mNode[adf::kMaxSupportedLevel + 2];
};

/// Corner c's offset from a cell's origin in a cell's size, packed (packLattice).
constexpr std::array<uint64_t, 8> kPackedCorner = [] {
    std::array<uint64_t, 8> t{};
    for (uint32_t c = 0; c < 8; ++c) t[c] = packLattice({c & 1, (c >> 1) & 1, c >> 2});
    return t;
}();

/// For a brick child (by its position in the brick) and each edge: the quadrants whose unit
/// cube lies in a sibling (same size, same tile: no lookup), and the edges a sibling emits
/// (one of the sibling quadrants comes before the child's own; 12-bit mask).
struct BrickEdges {
    uint8_t siblings[12];
    uint16_t siblingEmits;
};
constexpr std::array<BrickEdges, 8> kBrickEdges = [] {
    std::array<BrickEdges, 8> t{};
    for (int child = 0; child < 8; ++child)
        for (int i = 0; i < 12; ++i) {
            const CellEdge& e = kCellEdges[i];
            // In units of the child: its offset in the brick plus the edge's start corner.
            const int va = ((child >> e.a) & 1) + ((e.c0 >> e.a) & 1), vb = ((child >> e.b) & 1) + ((e.c0 >> e.b) & 1);
            for (int q = 0; q < 4; ++q) {
                if (q == e.quadrant) continue;
                const bool inA = va == 1 || (va == 0 && !kMinusA[q]) || (va == 2 && kMinusA[q]);
                const bool inB = vb == 1 || (vb == 0 && !kMinusB[q]) || (vb == 2 && kMinusB[q]);
                if (!(inA && inB)) continue;
                t[child].siblings[i] |= uint8_t(1u << q);
                if (q < e.quadrant) t[child].siblingEmits |= uint16_t(1u << i);
            }
        }
    return t;
}();

}  // namespace

template <class Out>
void computeCrossings(const Adf& adf, const Tile& tile, const std::vector<BoundaryCell>& leaves, Out& out,
                      SurfaceNetsStats& st, StartFilter filter) {
    const uint32_t top = adf.domain().latticeSize();
    const int maxLevel = adf.domain().maxLevel;
    LeafLocator locator(adf);
    // The leaves by place: a block of the tile whose origin is a leaf's is answered by that leaf
    // (it holds the block, or is smaller), with no search. The rest ask the locator.
    const uint64_t tileKey = packLattice(tile.latticeOrigin());
    const uint64_t outside = outsideOf(tile, maxLevel);
    uint32_t* const byPlace = PlaceTable::fits(tile, maxLevel) ? PlaceTable::entries() : nullptr;
    const auto leafKey = [&](std::size_t i) { return packLattice(leaves[i].origin); };
    PlaceTable::ClearOnExit<decltype(leafKey)> clear{byPlace, tileKey, 0, leafKey};
    if (byPlace) {
        for (uint32_t i = 0; i < leaves.size(); ++i) byPlace[PlaceTable::place(leafKey(i), tileKey)] = i;
        clear.cells = leaves.size();
    }
    auto locate = [&](uint64_t block, uint32_t size) -> RingLeaf {
        if (byPlace && inTile(block, tileKey, outside)) {
            const uint32_t i = byPlace[PlaceTable::place(block, tileKey)];
            if (i != PlaceTable::kNone) return {block, leaves[i].size, uint32_t(maxLevel - std::countr_zero(leaves[i].size))};
        }
        return locator.locate(block, size);
    };
    for (const BoundaryCell& leaf : leaves) {
        const uint32_t inside = insideCorners(leaf.corners);
        uint32_t todo = kSignChangingEdges[inside];
        // Away from the domain's border no quadrant can leave it; there a brick child knows its
        // siblings from its position, and skips the edges a sibling emits without a lookup.
        const glm::uvec3 hi = leaf.origin + leaf.size;
        const bool interior = glm::all(glm::greaterThan(leaf.origin, glm::uvec3(0))) && glm::all(glm::lessThan(hi, glm::uvec3(top)));
        const BrickEdges* brick = nullptr;
        if (interior && leaf.brickChild) {
            const glm::uvec3 at = glm::min(leaf.origin & leaf.size, glm::uvec3(1));
            brick = &kBrickEdges[at.x | (at.y << 1) | (at.z << 2)];
            todo &= ~uint32_t(brick->siblingEmits);
        }
        const glm::uvec3 parent = leaf.origin & ~glm::uvec3(2 * leaf.size - 1);
        const uint8_t leafLevel = uint8_t(maxLevel - std::countr_zero(leaf.size));
        // Points and blocks as packed integers (packLattice): where no field can go below zero
        // a step is one multiply-subtract, and a packed block is what the ring records.
        const uint64_t origin = packLattice(leaf.origin), size = leaf.size;
        for (; todo; todo &= todo - 1) {
            const CellEdge& edge = kCellEdges[std::countr_zero(todo)];
            const int c0 = edge.c0, c1 = edge.c1, k = edge.axis, a = edge.a, b = edge.b, own = edge.quadrant;
            const uint64_t start = origin + size * kPackedCorner[c0];
            if (filter.keep && !filter.keep(filter.context, unpackLattice(start))) continue;
            // The block of the leaf's size next to the edge's start in each quadrant (a leaf
            // holding its unit cube there is no smaller than the block, or lies inside it);
            // whether it leaves the domain; whether it is a sibling of the same brick.
            uint64_t block[4];
            uint32_t openAt = 0, siblingAt = 0;
            if (interior) {  // the start is at least one leaf size from the domain's low faces
                for (int q = 0; q < 4; ++q) block[q] = start - size * edge.packedStep[q];
                if (brick) siblingAt = brick->siblings[std::countr_zero(todo)];
            } else {
                const glm::uvec3 p = unpackLattice(start);
                for (int q = 0; q < 4; ++q) {
                    if (q == own) continue;
                    // Plain arrays: glm's operator[] on a run-time axis is a switch.
                    uint32_t s[3] = {p.x, p.y, p.z};
                    if ((kMinusA[q] && s[a] == 0) || (kMinusB[q] && s[b] == 0)) {
                        openAt |= 1u << q;
                        continue;
                    }
                    s[a] -= kMinusA[q];
                    s[b] -= kMinusB[q];
                    if (s[a] >= top || s[b] >= top) {
                        openAt |= 1u << q;
                        continue;
                    }
                    const glm::uvec3 cube(s[0], s[1], s[2]);
                    block[q] = packLattice(cube & ~glm::uvec3(leaf.size - 1));
                    if (leaf.brickChild && glm::all(glm::lessThan(cube - parent, glm::uvec3(2 * leaf.size))))
                        siblingAt |= 1u << q;
                }
            }
            // Leaf at each quadrant: the one holding that block. Not minimal: a smaller leaf
            // splits this edge. Not canonical: an equal leaf earlier in quadrant order emits it.
            // Any one of these settles it, so siblings are asked first and lookups stop at the
            // first; only where a quadrant leaves the domain does the quadrant order decide
            // (whether the crossing is counted open).
            // The ring as found (copied at once: a later lookup may reuse the cache entry).
            uint64_t ringCell[4];
            uint32_t ringLevel[4];
            const uint32_t others = 0xfu & ~(1u << own);
            const uint32_t asks = openAt ? others : (siblingAt & others) | ((~siblingAt & others) << 4);  // in order
            bool skip = false, open = false;
            for (uint32_t m = asks; m && !skip; m &= m - 1) {
                const int q = std::countr_zero(m) & 3;
                if ((openAt >> q) & 1) {
                    open = true;
                    break;
                }
                if ((siblingAt >> q) & 1) {
                    ringCell[q] = block[q];
                    ringLevel[q] = leafLevel;
                    skip = q < own;
                } else {
                    const RingLeaf found = locate(block[q], leaf.size);
                    ringCell[q] = found.cell;
                    ringLevel[q] = found.level;
                    skip = found.size < leaf.size || (found.size == leaf.size && q < own);
                }
            }
            if (open) {
                ++st.openCrossings;
                continue;
            }
            if (skip) continue;
            Crossing& x = out.emplace_back();
            const glm::uvec3 p = unpackLattice(start);
            x.length = leaf.size;
            x.axis = uint8_t(k);
            x.startInside = (inside >> c0) & 1;
            x.emitter = uint8_t(own);
            ringCell[own] = origin;
            ringLevel[own] = leafLevel;
            for (int q = 0; q < 4; ++q) {
                x.ringCell[q] = ringCell[q];
                x.ringLevel[q] = uint8_t(ringLevel[q]);
            }
            const float v0 = leaf.corners[c0], v1 = leaf.corners[c1];
            const float t = v0 / (v0 - v1);
            // Added on its axis only (adding zero elsewhere changes nothing): written through an
            // array indexed by the axis, the point would be read back before the store lands.
            const float along = t * float(leaf.size);
            x.point = glm::vec3(float(p.x) + (k == 0 ? along : 0.0f), float(p.y) + (k == 1 ? along : 0.0f),
                                float(p.z) + (k == 2 ? along : 0.0f));
            x.alive = 1;
            ++st.crossingsComputed;
        }
    }
}

template void computeCrossings(const Adf&, const Tile&, const std::vector<BoundaryCell>&, std::vector<Crossing>&,
                               SurfaceNetsStats&, StartFilter);
template void computeCrossings(const Adf&, const Tile&, const std::vector<BoundaryCell>&, PoolAppender&,
                               SurfaceNetsStats&, StartFilter);

void listBorder(const Adf& a, TileMesh& tm, std::vector<BorderCrossing>& border,
                std::vector<BorderCrossing>& scratch) {
    // A cell's slot, packed: its origin without the bits below a slot's size (masked to a
    // field's 20 bits: packLattice does not mask, and a wider value spills into the next field).
    const uint32_t slotShift = uint32_t(a.domain().maxLevel - a.domain().tileLevel());
    const uint64_t slotMask = packLattice(glm::uvec3((0xfffffu << slotShift) & 0xfffffu));
    // The tile of the last slot looked up: the cells beyond a tile's face mostly share one.
    uint64_t lastSlot = ~uint64_t(0), lastOwner = 0;
    const uint64_t tileKey = tm.key, outside = tm.outside;  // in locals: push_back may alias tm
    scratch.clear();
    uint32_t plain = 0;
    for (uint32_t j = 0; j < tm.crossings.size(); ++j) {
        const Crossing& x = tm.crossings[j];
        plain += plainTriangles(x);
        uint64_t owners[4];
        uint32_t n = 0;
        for (int q = 0; q < 4; ++q) {
            if (inTile(x.ringCell[q], tileKey, outside)) continue;
            const uint64_t slot = x.ringCell[q] & slotMask;
            if (slot != lastSlot) {
                lastSlot = slot;
                lastOwner = ownerKey(a, x.ringCell[q]);
            }
            if (std::find(owners, owners + n, lastOwner) != owners + n) continue;
            owners[n++] = lastOwner;
            scratch.push_back({lastOwner, j});
        }
    }
    tm.plainTriangles = plain;
    std::sort(scratch.begin(), scratch.end());
    border.assign(scratch.begin(), scratch.end());
}

}  // namespace kizamu::mesh::detail
