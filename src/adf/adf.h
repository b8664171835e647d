// SPDX-License-Identifier: Apache-2.0
/// @file adf.h
/// @brief An immutable ADF snapshot: the tile table and distance/gradient reconstruction.
///
/// A snapshot maps every tile slot of the domain to a tile (a coarse tile above the tile level
/// covers many slots). The table has two levels, a root array and chunks of up to 8^3 slots,
/// so that an edit copies only the chunks it touches. Snapshots and the tiles they point to
/// are immutable: every thread may query one concurrently, and the haptic thread does so with
/// an AdfAccessor. Reconstruction is trilinear in the leaf cell (Kizamu 2.1, Frisken et al.),
/// and the gradient is the analytic derivative of that trilinear function. A snapshot may also
/// carry paint (colour_layer.h): an immutable colour layer, shared like the tiles.
#pragma once

#include "adf/domain.h"
#include "adf/error_bound.h"
#include "adf/tile.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>
#if defined(__SSE__)
#include <xmmintrin.h>
#endif

#include <array>
#include <bit>
#include <cassert>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

namespace kizamu::adf {

/// Distance (m, negative inside) and its gradient (unit-less, about unit length near the surface).
struct Sample {
    float distance = 0.0f;
    glm::vec3 gradient{0.0f};
};

/// A leaf cell found by a lookup: its tile, extent, identity and decoded corner distances.
/// A leaf found by descending a tile, its corners not decoded: most lookups only ask whether a
/// point is one of them, or for one of them.
struct LeafCell {
    const Tile* tile = nullptr;
    uint32_t word = 0;     ///< the lone leaf's or the brick's node word
    int brickChild = -1;   ///< which child of the brick, or -1 for a lone leaf
    int level = 0;
    glm::uvec3 origin{0};  ///< lattice
    uint32_t size = 0;     ///< lattice units (a power of two)
    bool contains(glm::uvec3 p) const {
        const glm::uvec3 rel = p - origin;  // wraps around below the origin
        return (rel.x | rel.y | rel.z) < size;
    }
    /// Corner index of lattice point `p`, or -1 when it is not a corner.
    int cornerIndex(glm::uvec3 p) const {
        const glm::uvec3 rel = p - origin;
        // Each coordinate must be 0 or size: no bit of any below size, none above it.
        if (((rel.x | rel.y | rel.z) & ~size) != 0) return -1;
        return int((rel.x != 0) | ((rel.y != 0) << 1) | ((rel.z != 0) << 2));
    }
    /// Decoded corner `c`, m.
    float corner(int c) const {
        return brickChild < 0 ? tile->corner(node::leafIndex(word), c) : tile->brickCorner(node::brickIndex(word), brickChild, c);
    }
    /// The 8 decoded corners, m.
    void corners(float out[8]) const {
        if (brickChild < 0) tile->leafCorners(node::leafIndex(word), out);
        else tile->brickCorners(node::brickIndex(word), brickChild, out);
    }
};

struct LeafRef {
    const Tile* tile = nullptr;
    glm::uvec3 latticeOrigin{0};
    uint32_t latticeSize = 0;
    int level = 0;
    int brickChild = -1;  ///< which child of its brick, or -1 for a lone leaf
    float corners[8] = {};  ///< m, corner order of tile.h
    CellType type() const { return cellTypeOf(std::span<const float, 8>(corners, 8)); }
};

/// A block of up to 8^3 tile slots. Immutable once published.
struct Chunk {
    std::array<const Tile*, 512> tiles{};  ///< what readers use
    /// Keeps them alive (writer side only): each distinct tile once, in pointer order (a chunk
    /// holds far fewer distinct tiles than slots; docs/decisions/0008-two-level-tile-table.md).
    std::vector<TilePtr> owners;
};
using ChunkPtr = std::shared_ptr<const Chunk>;

class AdfBuilder;
class ColourLayer;

/// One immutable version of the field. Owned by std::shared_ptr on the writer side; readers
/// reach it through SnapshotStore guards or plain references and never touch reference counts.
class Adf {
public:
    const Domain& domain() const { return mDomain; }
    const GenerationSettings& settings() const { return mSettings; }
    uint64_t version() const { return mVersion; }

    /// Tile covering tile slot `slot` (never null in a built snapshot).
    /// Complexity: O(1), two dependent loads. Threading: any thread. Memory: none.
    const Tile* tileAtSlot(glm::uvec3 slot) const noexcept {
        const glm::uvec3 r = slot >> uint32_t(mChunkLevels);
        const uintptr_t e = mRoot[(r.z * mRootDim + r.y) * mRootDim + r.x];
        if (e & 1u) return reinterpret_cast<const Tile*>(e & ~uintptr_t(1));
        const glm::uvec3 c = slot & (mChunkDim - 1);
        return reinterpret_cast<const Chunk*>(e)->tiles[(c.z * mChunkDim + c.y) * mChunkDim + c.x];
    }

    /// Calls fn(slot) for every tile slot where `other`, a snapshot of the same domain, holds a
    /// different tile. Chunks both share (an edit copies only those it writes) are skipped
    /// whole. Complexity: O(root entries + slots of the chunks they do not share): an edit's
    /// few chunks, not every slot (262k at level 12). Threading: any thread. Memory: none.
    template <class Fn>
    void forEachSlotDiffering(const Adf& other, Fn&& fn) const {
        assert(other.mRoot.size() == mRoot.size() && "forEachSlotDiffering compares snapshots of one domain");
        // Entry i of a cube of side 2^bits (x fastest), as coordinates.
        auto unpack = [](uint32_t i, uint32_t bits) {
            const uint32_t mask = (1u << bits) - 1;
            return glm::uvec3(i & mask, (i >> bits) & mask, i >> (2 * bits));
        };
        const auto rootBits = uint32_t(std::countr_zero(mRootDim)), chunkBits = uint32_t(mChunkLevels);
        for (uint32_t i = 0; i < uint32_t(mRoot.size()); ++i) {
            if (mRoot[i] == other.mRoot[i]) continue;
            const glm::uvec3 first = unpack(i, rootBits) << chunkBits;
            for (uint32_t k = 0; k < (1u << (3 * chunkBits)); ++k) {
                const glm::uvec3 slot = first + unpack(k, chunkBits);
                if (tileAtSlot(slot) != other.tileAtSlot(slot)) fn(slot);
            }
        }
    }

    /// Leaf cell containing lattice point `p` (each coordinate < latticeSize()), corners not
    /// decoded. Complexity: O(tile span) node loads. Threading: any thread. Memory: none.
    LeafCell locateLeaf(glm::uvec3 p) const noexcept;
    /// The same leaf with its corners decoded.
    LeafRef findLeaf(glm::uvec3 p) const noexcept;

    /// Distance and gradient at `pWorld` (m). Outside the domain the distance grows by the
    /// distance to the domain and the gradient is the one at the nearest domain point.
    /// Complexity: O(tile span). Threading: any thread. Memory: none. For coherent queries
    /// use AdfAccessor, which skips the lookup while the point stays in the same leaf.
    Sample sample(const glm::vec3& pWorld) const noexcept;
    float distance(const glm::vec3& pWorld) const noexcept { return sample(pWorld).distance; }

    /// Distance (m) at lattice point `p` (each coordinate <= latticeSize()): the stored value
    /// when `p` is a corner of its leaf, else the trilinear value there; no gradient. For
    /// readers whose points lie on the lattice (a coarser lattice re-sampling this one).
    /// Complexity: O(tile span) node loads, one decoded value at a corner. Threading: any
    /// thread. Memory: none.
    float latticeDistance(glm::uvec3 p) const noexcept;
    /// latticeDistance of every point of `p`, into `out` (the same size): the same values, but
    /// the points' descents run side by side, a level at a time, so that their memory loads
    /// overlap instead of waiting in turn (one descent is a chain of dependent loads). For
    /// readers that re-sample a coarser lattice in batches (the LOD).
    /// Complexity: O(n * tile span) node loads. Threading: any thread. Memory: none.
    void latticeDistances(std::span<const glm::uvec3> p, std::span<float> out) const noexcept;

    /// The paint, or null when this clay was never painted (meshes then carry no colours).
    /// Complexity: O(1). Threading: any thread (the layer is immutable).
    const std::shared_ptr<const ColourLayer>& colours() const { return mColours; }

    /// Calls `fn` once for every distinct tile (coarse tiles once, not once per slot), in slot order.
    void forEachTile(const std::function<void(const Tile&)>& fn) const;

    /// Totals over distinct tiles.
    struct Stats {
        std::size_t tiles = 0;        ///< distinct tiles
        std::size_t coarseTiles = 0;  ///< tiles above the tile level
        std::size_t cells = 0;        ///< leaf cells (lone leaves and 8 per brick)
        std::size_t bricks = 0;       ///< bricks (each holds 8 of the leaf cells)
        std::size_t narrowBricks = 0; ///< of them stored narrow (7-bit leaf steps, tile.h)
        std::size_t coarseBricks = 0; ///< of them stored coarse-narrow (8-bit leaf steps, tile.h)
        std::size_t farBricks = 0;    ///< of them stored far (8-bit far steps, tile.h)
        std::size_t narrowLeaves = 0; ///< lone leaves stored narrow on their own (8-bit steps, tile.h)
        std::size_t groupedLeaves = 0;  ///< lone leaves stored in leaf groups (tile.h)
        std::size_t packedGroupedLeaves = 0;  ///< of them in packed groups (narrow, coarse-narrow or far)
        std::size_t nodes = 0;        ///< node words (leaves and internal)
        std::size_t tileBytes = 0;    ///< bytes of all tile blocks
        std::size_t tableBytes = 0;   ///< root array and chunks
        std::size_t boundaryCells = 0;  ///< leaves whose corners change sign
        BoxWorld surfaceBounds;         ///< box around the boundary cells (zero box if none)
        std::size_t paintedPoints = 0;  ///< lattice points of the colour layer
        std::size_t colourBytes = 0;    ///< bytes of the colour layer
        std::size_t bytes() const { return tileBytes + tableBytes + colourBytes; }
        /// Field bytes (tiles and table, not paint) per leaf cell.
        double bytesPerCell() const { return cells ? double(tileBytes + tableBytes) / double(cells) : 0.0; }
    };
    /// Complexity: O(slots). Threading: any thread. Memory: one small set.
    Stats computeStats() const;

    // ---- internals shared with AdfAccessor ----
    glm::vec3 originWorldF() const { return mOriginF; }
    float latticePerMetre() const { return mLatticePerMetre; }
    float metresPerLattice() const { return mMetresPerLattice; }
    /// Largest lattice coordinate a query is clamped to (just below latticeSize()).
    float latticeTop() const { return float(mDomain.latticeSize()) * (1.0f - 1e-7f); }

private:
    friend class AdfBuilder;
    Adf() = default;

    /// Child of the cell 2^cellShift wide holding lattice point `p`.
    static int childAt(glm::uvec3 p, int cellShift) noexcept {
        const glm::uvec3 b = (p >> uint32_t(cellShift - 1)) & 1u;
        return int(b.x | (b.y << 1) | (b.z << 2));
    }
    /// The leaf holding `p` once its descent in `tile` reached `w`, the first node word on p's
    /// path that is not internal, for a cell 2^shift wide.
    LeafCell leafOfWord(const Tile* tile, uint32_t w, int shift, glm::uvec3 p) const noexcept {
        LeafCell c;
        c.tile = tile;
        if (node::isBrick(w)) c.brickChild = childAt(p, shift--);
        c.word = w;
        c.level = mDomain.maxLevel - shift;
        c.origin = (p >> uint32_t(shift)) << uint32_t(shift);
        c.size = 1u << shift;
        return c;
    }

    Domain mDomain;
    GenerationSettings mSettings;
    uint64_t mVersion = 0;
    int mChunkLevels = 0;     ///< log2 of chunk dim
    uint32_t mChunkDim = 1;   ///< slots per chunk axis
    uint32_t mRootDim = 1;    ///< chunks per root axis
    std::vector<uintptr_t> mRoot;  ///< Chunk* or (Tile* | 1) for a chunk covered by one tile
    std::vector<ChunkPtr> mChunkOwners;
    std::vector<TilePtr> mRootTileOwners;
    std::shared_ptr<const ColourLayer> mColours;  ///< null: never painted
    glm::vec3 mOriginF{0.0f};
    float mLatticePerMetre = 1.0f;
    float mMetresPerLattice = 1.0f;
};

using AdfPtr = std::shared_ptr<const Adf>;

/// Builds a snapshot, either from scratch or as a copy-on-write edit of another one.
/// Owned by one writer thread; not thread-safe.
class AdfBuilder {
public:
    /// Empty table for `domain` (every slot must be assigned before build()).
    AdfBuilder(const Domain& domain, const GenerationSettings& settings);
    /// Starts from `base`: untouched chunks are shared with it, and so is its colour layer
    /// (so local regeneration keeps the paint: colour belongs to the material).
    explicit AdfBuilder(const Adf& base);

    /// Assigns `tile` to every slot it covers (its level and origin say which).
    /// Complexity: O(slots covered / 512 + touched chunk copies). Memory: copies touched chunks once.
    void setTile(TilePtr tile);
    /// Replaces the colour layer (null: unpainted). @throw std::invalid_argument when the layer
    /// was made for another domain. Complexity: O(1).
    void setColours(std::shared_ptr<const ColourLayer> colours);
    /// Tile currently assigned at `slot` (null if none yet).
    const Tile* tileAtSlot(glm::uvec3 slot) const;
    /// Finishes with `version`. Throws std::logic_error if a slot is unassigned.
    AdfPtr build(uint64_t version);

private:
    /// A chunk this builder may still mutate. Its owners are sorted and unique up to `kept`
    /// (as the snapshot it was copied from left them); setTile appends after that, and notes the
    /// tiles it overwrites, the only ones that can stop being shown.
    struct OwnChunk {
        std::shared_ptr<Chunk> chunk;
        std::size_t kept = 0;
        std::vector<const Tile*> replaced;
    };
    std::shared_ptr<Adf> mAdf;
    std::vector<OwnChunk> mOwnChunks;
};

/// Per-thread cached reader for coherent queries (the haptic thread's path).
/// Remembers the last leaf with its decoded corners and the path of cells from its tile root
/// down to it (as OpenVDB's ValueAccessor caches nodes): a query in the same leaf costs one
/// trilinear evaluation, and a step into a neighbouring leaf climbs only as far as the
/// smallest cached cell that contains the new point before descending again.
/// Why not the old field's leaf table (adf_source.cpp's Cache): one stream of nearby points
/// (a stylus path) leaves a leaf for a neighbour and rarely returns to one left earlier, so a
/// table of recent leaves answers it about as fast as the path does, while costing 20 KB per
/// accessor next to the haptic loop's own data; and every query here needs the corners decoded
/// and a gradient, which the table decodes lazily (docs/decisions/0013-leaf-locator-cache.md).
/// Not thread-safe: one per thread. Must not outlive the snapshot it reads.
class AdfAccessor {
public:
    explicit AdfAccessor(const Adf& adf) { reset(adf); }
    /// Same result as Adf::sample.
    /// Complexity: O(1) inside the cached leaf, O(levels climbed) nearby, O(tile span) at worst.
    /// Memory: none. Never blocks.
    Sample sample(const glm::vec3& pWorld) noexcept;
    /// Switch to another snapshot (drops the cache).
    void reset(const Adf& adf) {
        mAdf = &adf;
        mOriginWorld = adf.originWorldF();
        mLatticePerMetre = adf.latticePerMetre();
        mMetresPerLattice = adf.metresPerLattice();
        mTop = adf.latticeTop();
        mSize = 0;
        mDepth = 0;
    }

private:
    void descend(glm::uvec3 p) noexcept;

    struct PathCell {
        glm::uvec3 origin;  ///< lattice
        uint32_t size;      ///< lattice units
        uint32_t word;      ///< node word of this cell
    };
    // Copied from the snapshot so the hit path touches only this object.
    const Adf* mAdf = nullptr;
    glm::vec3 mOriginWorld{0.0f};
    float mLatticePerMetre = 1.0f, mMetresPerLattice = 1.0f, mTop = 0.0f;
    const Tile* mTile = nullptr;
    glm::uvec3 mOrigin{0};
    uint32_t mSize = 0;  ///< 0: nothing cached
    float mInvSize = 0.0f;
    float mGradientScale = 0.0f;  ///< lattice-cell derivative to per-metre
    float mCorners[8] = {};
    int mDepth = 0;  ///< valid entries of mPath
    PathCell mPath[kMaxSupportedLevel + 1];
};

/// Trilinear value and analytic gradient at local coordinates `f` in [0,1]^3 of a cell with
/// corners `v` (corner order of tile.h); the gradient is per unit of `f`.
inline Sample trilinear(const float* v, const glm::vec3& f) {
    const float a00 = v[0] + f.x * (v[1] - v[0]);
    const float a10 = v[2] + f.x * (v[3] - v[2]);
    const float a01 = v[4] + f.x * (v[5] - v[4]);
    const float a11 = v[6] + f.x * (v[7] - v[6]);
    const float b0 = a00 + f.y * (a10 - a00);
    const float b1 = a01 + f.y * (a11 - a01);
    const float dx00 = v[1] - v[0], dx10 = v[3] - v[2], dx01 = v[5] - v[4], dx11 = v[7] - v[6];
    const float gx0 = dx00 + f.y * (dx10 - dx00);
    const float gx1 = dx01 + f.y * (dx11 - dx01);
    const float gy0 = a10 - a00, gy1 = a11 - a01;
    Sample s;
    s.distance = b0 + f.z * (b1 - b0);
    s.gradient = {gx0 + f.z * (gx1 - gx0), gy0 + f.z * (gy1 - gy0), b1 - b0};
    return s;
}

/// trilinear's value, bit for bit (the same operations on the same operands), as three steps
/// of one form, a + f (b - a), each on four values at once where SSE is there: a third of the
/// instructions but a longer chain of them. Relaxation, which samples between other work, gains
/// from the fewer instructions; a chain of dependent projections pays for the longer chain and
/// keeps trilinear (docs/decisions/0024-mesher-build-shortcuts.md).
inline Sample trilinearPacked(const float* v, const glm::vec3& f) {
#if defined(__SSE__)
    const __m128 lo = _mm_loadu_ps(v), hi = _mm_loadu_ps(v + 4);
    const __m128 even = _mm_shuffle_ps(lo, hi, _MM_SHUFFLE(2, 0, 2, 0));  // v0 v2 v4 v6
    const __m128 odd = _mm_shuffle_ps(lo, hi, _MM_SHUFFLE(3, 1, 3, 1));   // v1 v3 v5 v7
    const __m128 dx = _mm_sub_ps(odd, even);                                // dx00 dx10 dx01 dx11
    const __m128 a = _mm_add_ps(even, _mm_mul_ps(_mm_set1_ps(f.x), dx));   // a00 a10 a01 a11
    const __m128 p = _mm_shuffle_ps(a, dx, _MM_SHUFFLE(2, 0, 2, 0));        // a00 a01 dx00 dx01
    const __m128 q = _mm_shuffle_ps(a, dx, _MM_SHUFFLE(3, 1, 3, 1));        // a10 a11 dx10 dx11
    const __m128 dy = _mm_sub_ps(q, p);                                     // gy0 gy1 . .
    const __m128 b = _mm_add_ps(p, _mm_mul_ps(_mm_set1_ps(f.y), dy));      // b0 b1 gx0 gx1
    const __m128 s0 = _mm_shuffle_ps(b, dy, _MM_SHUFFLE(0, 0, 2, 0));       // b0 gx0 gy0 gy0
    const __m128 s1 = _mm_shuffle_ps(b, dy, _MM_SHUFFLE(1, 1, 3, 1));       // b1 gx1 gy1 gy1
    const __m128 dz = _mm_sub_ps(s1, s0);                                   // b1-b0 . . .
    const __m128 r = _mm_add_ps(s0, _mm_mul_ps(_mm_set1_ps(f.z), dz));    // distance gx gy .
    Sample s;
    s.distance = _mm_cvtss_f32(r);
    s.gradient = {_mm_cvtss_f32(_mm_shuffle_ps(r, r, 1)), _mm_cvtss_f32(_mm_shuffle_ps(r, r, 2)), _mm_cvtss_f32(dz)};
    return s;
#else
    return trilinear(v, f);
#endif
}

// Inline so that the haptic loop compiles the cache hit into straight-line code.
/// Clamps `u` into [0, top] per axis, NaN to 0 (glm::clamp would pass NaN through).
inline glm::vec3 clampToLattice(const glm::vec3& u, float top) {
    auto c = [top](float x) { return x > 0.0f ? (x < top ? x : top) : 0.0f; };
    return {c(u.x), c(u.y), c(u.z)};
}

inline Sample AdfAccessor::sample(const glm::vec3& pWorld) noexcept {
    const glm::vec3 u = (pWorld - mOriginWorld) * mLatticePerMetre;
    float outside = 0.0f;
    glm::vec3 c = u;
    if (!(u.x >= 0.0f && u.y >= 0.0f && u.z >= 0.0f && u.x <= mTop && u.y <= mTop && u.z <= mTop)) {
        c = clampToLattice(u, mTop);
        outside = glm::length(u - c);  // NaN input gives a NaN distance, never a wild read
    }
    const glm::uvec3 p(c);
    const glm::uvec3 rel = p - mOrigin;  // wraps around when below the origin
    if (rel.x >= mSize || rel.y >= mSize || rel.z >= mSize) descend(p);
    Sample s = trilinear(mCorners, (c - glm::vec3(mOrigin)) * mInvSize);
    s.gradient *= mGradientScale;
    s.distance += outside * mMetresPerLattice;
    return s;
}

/// Calls fn(leafRef) for every leaf cell of `tile` (bricks expanded), depth first.
/// Complexity: O(nodes + cells). Memory: none. Any thread.
template <class Fn>
void forEachLeaf(const Tile& tile, int maxLevel, Fn&& fn);

// ---- definitions ----

// Inline: the descent under every query (Adf::sample), the old field and the LOD's re-sampling.
[[gnu::always_inline]] inline LeafCell Adf::locateLeaf(glm::uvec3 p) const noexcept {
    assert(p.x < mDomain.latticeSize() && p.y < mDomain.latticeSize() && p.z < mDomain.latticeSize() &&
           "locateLeaf needs a point inside the domain");
    const Tile* tile = tileAtSlot(p >> uint32_t(mDomain.tileSpan()));
    int shift = mDomain.maxLevel - tile->level();
    uint32_t w = tile->node(0);
    while (node::isInternal(w)) w = tile->node(w + uint32_t(childAt(p, shift--)));
    return leafOfWord(tile, w, shift, p);
}

template <class Fn>
void forEachLeaf(const Tile& t, int maxLevel, Fn&& fn) {
    struct Item {
        uint32_t node;
        glm::uvec3 origin;
        int level;
    };
    Item stack[8 * (kMaxSupportedLevel + 1)];
    int top = 0;
    stack[top++] = {0, t.latticeOrigin(), t.level()};
    LeafRef r;
    r.tile = &t;
    while (top > 0) {
        const Item it = stack[--top];
        const uint32_t w = t.node(it.node);
        if (node::isInternal(w)) {
            const uint32_t half = 1u << (maxLevel - it.level - 1);
            for (int c = 7; c >= 0; --c)
                stack[top++] = {w + uint32_t(c), it.origin + glm::uvec3(c & 1, (c >> 1) & 1, c >> 2) * half,
                                it.level + 1};
            continue;
        }
        if (node::isLeaf(w)) {
            r.latticeOrigin = it.origin;
            r.latticeSize = 1u << (maxLevel - it.level);
            r.level = it.level;
            r.brickChild = -1;
            for (int c = 0; c < 8; ++c) r.corners[c] = t.corner(node::leafIndex(w), c);
            fn(static_cast<const LeafRef&>(r));
            continue;
        }
        const uint32_t half = 1u << (maxLevel - it.level - 1);
        r.latticeSize = half;
        r.level = it.level + 1;
        for (int child = 0; child < 8; ++child) {
            r.latticeOrigin = it.origin + glm::uvec3(child & 1, (child >> 1) & 1, child >> 2) * half;
            r.brickChild = child;
            for (int c = 0; c < 8; ++c) r.corners[c] = t.brickCorner(node::brickIndex(w), child, c);
            fn(static_cast<const LeafRef&>(r));
        }
    }
}

}  // namespace kizamu::adf
