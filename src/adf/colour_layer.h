// SPDX-License-Identifier: Apache-2.0
/// @file colour_layer.h
/// @brief Paint: an immutable, copy-on-write set of colours at finest-lattice points near the
/// surface, carried by a snapshot next to its distance tiles.
///
/// Colour belongs to the material, so it lives at lattice points (the same frame as the field)
/// and not on the mesh: a carve exposes whatever colour lies there, and every mesh of the
/// snapshot (full, incremental, LOD, points) reads the same colours. Only painted points are
/// stored, grouped by the tile slot that holds them: one small immutable ColourTile per painted
/// slot (its points sorted by local index), and the layer maps slot keys to shared tiles, so a
/// paint stroke copies the slot list and the tiles it touches and shares every other tile with
/// the snapshot before it (which is what undo keeps). A point that is not stored has the base
/// colour (unpainted clay); no stored point has it, so the representation is canonical.
///
/// Colours are sRGB bytes, what the exporters write. A colour between lattice points is the
/// trilinear blend of the 8 around it, computed on the sRGB values in float and rounded to
/// the nearest byte (not in linear light): exact where the 8 agree, cheap, deterministic, and
/// the way a renderer interpolates sRGB vertex colours across a triangle anyway; a half-way
/// blend of two very different hues comes out slightly darker than linear-light mixing would.
///
/// Lattice points on the domain's upper faces (coordinate latticeSize()) belong to no slot; a
/// lookup there reads the point just inside. Immutable once built: any thread may read a layer
/// concurrently; ColourAccessor is one per thread. SI units (metres) for world positions.
#pragma once

#include "adf/domain.h"

#include <glm/gtc/type_precision.hpp>
#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <utility>
#include <vector>

namespace kizamu::adf {

/// sRGB colour, 8 bits per channel.
using Rgb8 = glm::u8vec3;

/// Unpainted clay: a light, slightly warm grey (sRGB 200, 192, 180), the colour of fresh
/// modelling clay; light enough that any paint shows on it.
inline const Rgb8 kClayColour{200, 192, 180};

/// The painted points of one tile slot: local point indices (x + 2^span (y + 2^span z), with
/// local coordinates 0..2^span-1) strictly increasing, and their colours. Immutable; shared by
/// every layer that has not repainted the slot.
class ColourTile {
public:
    /// @param points   strictly increasing local indices, at least one
    /// @param colours  one per point
    /// Asserts the preconditions (a bug otherwise; the file loader checks them itself first).
    ColourTile(std::vector<uint32_t> points, std::vector<Rgb8> colours);

    std::size_t size() const { return mPoints.size(); }
    std::span<const uint32_t> points() const { return mPoints; }
    std::span<const Rgb8> colours() const { return mColours; }
    /// Colour of local point `point`, or null when it is not painted.
    /// Complexity: O(log size) binary search. Threading: any thread. Memory: none.
    const Rgb8* find(uint32_t point) const noexcept;
    /// Bytes of the two arrays (what an undo record of this tile costs).
    std::size_t bytes() const { return mPoints.size() * (sizeof(uint32_t) + sizeof(Rgb8)); }

private:
    std::vector<uint32_t> mPoints;
    std::vector<Rgb8> mColours;
};
using ColourTilePtr = std::shared_ptr<const ColourTile>;

class ColourLayer;
using ColourLayerPtr = std::shared_ptr<const ColourLayer>;

/// The painted points of a whole snapshot. Owned by std::shared_ptr (snapshots share it);
/// immutable, so thread-safe to read.
class ColourLayer {
public:
    /// An empty layer (everything `base`) for `domain`.
    explicit ColourLayer(const Domain& domain, Rgb8 base = kClayColour);

    const Domain& domain() const { return mDomain; }
    Rgb8 baseColour() const { return mBase; }
    /// Painted slots, and their keys in increasing order.
    std::size_t slotCount() const { return mSlots.size(); }
    std::span<const uint32_t> slotKeys() const { return mSlots; }
    std::span<const ColourTilePtr> tiles() const { return mTiles; }
    /// Painted points and bytes over all tiles (plus the slot list).
    std::size_t pointCount() const;
    std::size_t bytes() const;

    /// Key of tile slot `slot`: x + n (y + n z), n = slots per axis.
    uint32_t slotKey(glm::uvec3 slot) const {
        const uint32_t n = mDomain.slotsPerAxis();
        return (slot.z * n + slot.y) * n + slot.x;
    }
    /// The painted points of slot `key`, or null. Complexity: O(log slots). Any thread.
    const ColourTile* tileAt(uint32_t key) const noexcept;

    /// Colour of lattice point `pLattice` (coordinates up to latticeSize(); the upper faces read
    /// the point just inside). Complexity: O(log slots + log points of the slot). Any thread.
    Rgb8 colourAtLattice(glm::uvec3 pLattice) const noexcept;
    /// Trilinear blend (on sRGB values, rounded) of the 8 lattice points around `pWorld` (m),
    /// clamped into the domain. Complexity: 8 lattice lookups. Any thread. Memory: none.
    /// For many coherent queries use ColourAccessor.
    Rgb8 colourAt(const glm::vec3& pWorld) const noexcept;

    /// A copy with the tiles of some slots replaced: each change is (slot key, new tile, or
    /// null for unpainted); every other tile is shared with this layer. Keys must be distinct.
    /// Complexity: O(slots + changes log changes). Memory: the new slot list.
    ColourLayerPtr withTiles(std::vector<std::pair<uint32_t, ColourTilePtr>> changes) const;
    /// A layer from scratch: keys strictly increasing and below slotsPerAxis()^3, tiles non-null
    /// (the file loader checks these before calling). @throw std::invalid_argument otherwise.
    static ColourLayerPtr create(const Domain& domain, Rgb8 base, std::vector<uint32_t> keys,
                                 std::vector<ColourTilePtr> tiles);

private:
    Domain mDomain;
    Rgb8 mBase;
    std::vector<uint32_t> mSlots;       ///< painted slot keys, increasing
    std::vector<ColourTilePtr> mTiles;  ///< one per key
};

/// Per-thread colour lookups that remember the last slot they looked up (a surface vertex's 8
/// lattice neighbours nearly always share a slot with the previous vertex's). Same results as
/// ColourLayer::colourAt. Not thread-safe: one per thread; must not outlive the layer.
class ColourAccessor {
public:
    explicit ColourAccessor(const ColourLayer& layer);
    /// Complexity: O(1) while the slot stays the same, else O(log slots + log points).
    Rgb8 colourAt(const glm::vec3& pWorld) noexcept;

private:
    const ColourTile* tileOf(uint32_t key) noexcept;
    const ColourLayer* mLayer;
    glm::vec3 mOriginWorld{0.0f};
    float mLatticePerMetre = 1.0f, mTop = 0.0f;
    uint32_t mLast = ~0u;  ///< key of the cached slot
    const ColourTile* mLastTile = nullptr;
};

/// The 8-point blend: `c` the colours at the corners of a lattice cell (corner order x + 2y + 4z),
/// `f` local coordinates in [0,1]^3. Rounds to the nearest byte.
Rgb8 blendColours(const Rgb8 (&c)[8], const glm::vec3& f) noexcept;

}  // namespace kizamu::adf
