// SPDX-License-Identifier: Apache-2.0
/// @file domain.h
/// @brief The cubic region an ADF covers, its octree levels and its tile grid.
///
/// Everything in kizamu::adf is in SI units (metres) unless a name says otherwise. Three frames:
/// world (`...World`, metres), lattice (`...Lattice`, integer corner coordinates of the finest
/// level, 0..2^maxLevel per axis) and tile slots (`...Slot`, one per tile at the tile level).
/// Read by every thread; plain value type.
#pragma once

#include <glm/common.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace kizamu::adf {

/// Largest supported maximum level: lattice coordinates must stay exact in a float query.
inline constexpr int kMaxSupportedLevel = 16;
/// Largest supported tile level (tiles per axis = 2^tileLevel).
inline constexpr int kMaxTileLevel = 10;
/// Largest supported tile span: a generation scratch volume is (2^span + 1)^3 samples (136 MB
/// at span 8), and border samples pack local coordinates into 10 bits per axis.
inline constexpr int kMaxTileSpan = 8;

/// The cube [originWorld, originWorld + sizeWorld]^3 subdivided as an octree down to `maxLevel`.
/// A stored tile is the subtree below `tileLevel()`, spanning 2^tileSpanLevels finest cells.
struct Domain {
    glm::dvec3 originWorld{0.0};  ///< minimum corner, m
    double sizeWorld = 1.0;       ///< edge length, m
    int maxLevel = 10;            ///< finest octree level (root is level 0)
    int tileSpanLevels = 6;       ///< levels inside one tile (docs/decisions/0001-tile-span-6.md)

    /// Level of the stored tiles (the tile roots).
    int tileLevel() const { return std::max(0, maxLevel - tileSpanLevels); }
    /// Levels actually inside a tile (smaller than tileSpanLevels for tiny maxLevel).
    int tileSpan() const { return maxLevel - tileLevel(); }
    /// Tiles per axis.
    uint32_t slotsPerAxis() const { return 1u << tileLevel(); }
    /// Finest cells per axis; lattice corner coordinates run 0..latticeSize().
    uint32_t latticeSize() const { return 1u << maxLevel; }
    /// Edge of a finest cell, m.
    double finestCellSize() const { return sizeWorld / double(latticeSize()); }
    /// Edge of a cell at `level`, in lattice units.
    uint32_t cellLattice(int level) const { return 1u << (maxLevel - level); }

    /// World position of a lattice corner. Computed the same way everywhere so that a lattice
    /// point evaluated from two tiles gets bit-identical coordinates.
    glm::dvec3 latticeToWorld(uint32_t x, uint32_t y, uint32_t z) const {
        return latticeToWorld(originWorld, finestCellSize(), {x, y, z});
    }
    /// The same with the origin and cell size read once by the caller (a loop over many points:
    /// the division in finestCellSize() costs more than the rest).
    static glm::dvec3 latticeToWorld(const glm::dvec3& origin, double cell, glm::uvec3 p) {
        return {origin.x + double(p.x) * cell, origin.y + double(p.y) * cell, origin.z + double(p.z) * cell};
    }

    /// True when the parameters describe a usable domain. The tile level is capped so that
    /// the tile table stays small (at most 1024 tiles per axis).
    bool valid() const {
        return sizeWorld > 0.0 && std::isfinite(sizeWorld) && std::isfinite(originWorld.x) &&
               std::isfinite(originWorld.y) && std::isfinite(originWorld.z) && maxLevel >= 1 &&
               maxLevel <= kMaxSupportedLevel && tileSpanLevels >= 1 && tileSpanLevels <= kMaxTileSpan &&
               tileLevel() <= kMaxTileLevel;
    }

    bool operator==(const Domain&) const = default;
};

/// World positions back to lattice points, for sources the generator asks at lattice points
/// (Domain::latticeToWorld): the nearest one, where `p` lies in the domain within `tolerance`
/// lattice units of it on every axis. Keeps the inverse cell size: a query divides nothing.
class LatticeRounding {
public:
    explicit LatticeRounding(const Domain& d)
        : mOrigin(d.originWorld), mInvCell(1.0 / d.finestCellSize()), mTop(double(d.latticeSize()) + 1.0) {}

    bool nearest(const glm::dvec3& p, double tolerance, glm::uvec3& lattice) const {
        for (int k = 0; k < 3; ++k) {  // one axis at a time, scalar: it runs for every sample
            // The nearest integer r = floor(u + 0.5) (ties only fail the tolerance), by
            // truncation once u + 0.5 is known to lie in [0, top + 1), that is 0 <= r <= top.
            const double u = (p[k] - mOrigin[k]) * mInvCell, t = u + 0.5;
            if (!(t >= 0.0 && t < mTop)) return false;
            lattice[k] = uint32_t(t);
            if (!(std::abs(u - double(lattice[k])) < tolerance)) return false;
        }
        return true;
    }

private:
    glm::dvec3 mOrigin;
    double mInvCell;
    double mTop;  ///< bound of u + 0.5
};

/// Axis-aligned box in world space, m.
struct BoxWorld {
    glm::dvec3 min{0.0}, max{0.0};
    /// Closed-box test.
    bool contains(const glm::dvec3& p) const {
        return p.x >= min.x && p.y >= min.y && p.z >= min.z && p.x <= max.x && p.y <= max.y && p.z <= max.z;
    }
};

/// `box` grown by `pad` (m) on every side and clipped to the domain.
inline BoxWorld grownWithin(const Domain& d, const BoxWorld& box, double pad) {
    const glm::dvec3 lo = d.originWorld, hi = d.originWorld + glm::dvec3(d.sizeWorld);
    return {glm::clamp(box.min - pad, lo, hi), glm::clamp(box.max + pad, lo, hi)};
}

/// Calls fn(slot) for every tile slot that `box` (m, clipped to the domain) overlaps, x fastest.
template <class Fn>
void forEachSlotIn(const Domain& d, const BoxWorld& box, Fn&& fn) {
    const double slot = d.finestCellSize() * double(1u << d.tileSpan());
    const double last = double(d.slotsPerAxis() - 1);
    auto toSlot = [&](double w, double o) { return uint32_t(std::clamp((w - o) / slot, 0.0, last)); };
    const glm::uvec3 lo(toSlot(box.min.x, d.originWorld.x), toSlot(box.min.y, d.originWorld.y), toSlot(box.min.z, d.originWorld.z));
    const glm::uvec3 hi(toSlot(box.max.x, d.originWorld.x), toSlot(box.max.y, d.originWorld.y), toSlot(box.max.z, d.originWorld.z));
    for (uint32_t z = lo.z; z <= hi.z; ++z)
        for (uint32_t y = lo.y; y <= hi.y; ++y)
            for (uint32_t x = lo.x; x <= hi.x; ++x) fn(glm::uvec3(x, y, z));
}

}  // namespace kizamu::adf
