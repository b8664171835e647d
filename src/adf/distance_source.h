// SPDX-License-Identifier: Apache-2.0
/// @file distance_source.h
/// @brief Signed distance functions the ADF samples: primitives, rigid transforms and CSG trees.
///
/// A DistanceSource is what generation and local regeneration evaluate at lattice points. Sign
/// convention (everywhere in Kizamu): negative inside the material, positive outside. Primitive
/// distances are exact; CSG with min/max is exact near the surface except across seams, and a
/// bound (|f| <= true distance, 1-Lipschitz) elsewhere, which is what trivial cell exclusion needs.
/// Threading: sources are immutable after construction; any number of threads may evaluate one.
/// Follows Kizamu (Perry & Frisken 2001) section 5 and the usual closed forms for primitives.
#pragma once

#include <glm/gtc/quaternion.hpp>
#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

#include <cstddef>
#include <limits>
#include <memory>
#include <span>
#include <vector>

namespace kizamu::adf {

struct Domain;

/// A signed distance function of world position (m), negative inside.
///
/// Requirements for implementers: `distance` is pure (same input, same bits on every x86-64
/// machine), thread-safe, and 1-Lipschitz; `distances` equals `distance` element by element, and
/// `latticeDistances` equals it at each point's `Domain::latticeToWorld` (generation may ask
/// either way, and tiles agree on the signs of the points they share only if they agree).
class DistanceSource {
public:
    virtual ~DistanceSource() = default;

    /// Signed distance at `pWorld`, m.
    /// Complexity: O(tree size). Threading: any thread. Memory: allocates nothing.
    virtual double distance(const glm::dvec3& pWorld) const = 0;

    /// Batch form: `out[i] = distance(pWorld[i])`; spans have equal length.
    /// Complexity: O(n * tree size), one virtual call per node per 64 points. Memory: stack only.
    virtual void distances(std::span<const glm::dvec3> pWorld, std::span<double> out) const;

    /// Whether latticeDistances answers lattice points of `domain` more cheaply than distances()
    /// their world positions: true for a source that is itself a lattice (a snapshot's field
    /// sampled for a LOD, mesh/lod.cpp, which need not round each point back to its lattice
    /// point). Generation then asks it that way. Default: false.
    virtual bool answersLattice(const Domain& domain) const;

    /// Batch form at lattice points of `domain`: `out[i] = distance(domain.latticeToWorld(
    /// lattice[i]))`. The default goes through world space.
    /// Complexity: as distances(). Memory: stack only.
    virtual void latticeDistances(const Domain& domain, std::span<const glm::uvec3> lattice,
                                  std::span<double> out) const;

    /// Size (m) of the smallest feature whose surface may pass within `radius` of `centreWorld`
    /// (a sphere's radius, a cylinder's radius or half height, ...), or +infinity. Generation
    /// subdivides a cell larger than this even when its 19 test points look fine, so a small
    /// shape (a tool dab on a flat face) cannot fall between the test points of a big cell.
    /// Default: no features (a smooth field such as a sampled ADF).
    virtual double featureSize(const glm::dvec3& centreWorld, double radius) const;

    /// Values (m) of a base field within which this source, an edit built on that field, is
    /// known to equal it: inside the ball (`centreWorld`, `radius`), wherever the base field
    /// lies in [lo, hi], this source answers the base field's value bit for bit. Local
    /// regeneration keeps the base's cells of a ball whose base values all lie in the range
    /// (a carve leaves everything outside the tool and above its depth untouched).
    /// Default: the empty range (not known).
    struct Range {
        double lo = std::numeric_limits<double>::infinity();
        double hi = -std::numeric_limits<double>::infinity();
        bool contains(double lo2, double hi2) const { return lo <= lo2 && hi2 <= hi; }
    };
    virtual Range unchangedRange(const glm::dvec3& centreWorld, double radius) const;

    /// The smallest feature anywhere (m): a lower bound of every featureSize() answer, fixed at
    /// construction (nodes cache it, so sources built on sources stay O(1) here).
    double smallestFeature() const { return mSmallestFeature; }

protected:
    double mSmallestFeature = std::numeric_limits<double>::infinity();
};

using SourcePtr = std::shared_ptr<const DistanceSource>;

/// Points per inner batch of the CSG nodes (stack buffers).
inline constexpr std::size_t kSourceBatch = 64;

// ---- primitives, centred on the origin of their local frame ----

/// Sphere of radius `radius` (m).
SourcePtr makeSphere(double radius);
/// Axis-aligned box with half extents `halfSize` (m).
SourcePtr makeBox(const glm::dvec3& halfSize);
/// Box with half extents `halfSize` whose edges and corners are rounded with `cornerRadius` (m).
SourcePtr makeRoundedBox(const glm::dvec3& halfSize, double cornerRadius);
/// Capsule: all points within `radius` of the segment `a`–`b` (m).
SourcePtr makeCapsule(const glm::dvec3& a, const glm::dvec3& b, double radius);
/// Capped cylinder around the z axis, `radius` and `halfHeight` in m.
SourcePtr makeCylinder(double radius, double halfHeight);
/// Torus around the z axis: ring radius `majorRadius`, tube radius `minorRadius` (m).
SourcePtr makeTorus(double majorRadius, double minorRadius);
/// Half-space {p : dot(p, normal) < offset}; `normal` need not be unit length.
SourcePtr makeHalfSpace(const glm::dvec3& normal, double offset);

// ---- transforms ----

/// `child` rotated by `rotation`, uniformly scaled by `scale` (> 0) and then moved by `translation`.
SourcePtr makeTransformed(SourcePtr child, const glm::dvec3& translation,
                          const glm::dquat& rotation = glm::dquat(1, 0, 0, 0), double scale = 1.0);
/// Shorthand for a pure translation.
SourcePtr makeTranslated(SourcePtr child, const glm::dvec3& translation);

// ---- CSG ----

enum class CsgOp { Union, Intersection, Difference };

/// min(a, b), max(a, b) or max(a, -b). With `blendRadius` > 0 (m) the seam is rounded by the
/// polynomial smooth minimum, which stays 1-Lipschitz.
SourcePtr makeCsg(CsgOp op, SourcePtr a, SourcePtr b, double blendRadius = 0.0);
/// Left fold of makeCsg over `parts` (at least one).
SourcePtr makeCsg(CsgOp op, const std::vector<SourcePtr>& parts, double blendRadius = 0.0);

}  // namespace kizamu::adf
