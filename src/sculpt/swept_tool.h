// SPDX-License-Identifier: Apache-2.0
/// @file swept_tool.h
/// @brief The volume a tool sweeps along a stroke, as a distance source (Kizamu 4.2, figure 3).
///
/// A stroke is a polyline of tool samples. Between two samples the tool moves continuously:
/// position linearly, orientation by slerp. The swept volume is the union over segments of
/// { pose(t) applied to the tool : t in [0, 1] }, and its distance at p is the minimum over t
/// of the tool's distance in the moving frame. A sphere turns into itself: its swept volume is
/// a capsule per segment, turning or not, in closed form. For the other shapes, with a fixed
/// orientation that function of t is convex (the tools are convex), so a golden-section search
/// finds its minimum; where the orientation turns, the search starts from the best of samples
/// spaced by at most 5 degrees. So fast strokes never break and slow strokes cost no
/// more than their length: 2 samples or 200 along the same path give the same volume.
/// Segments sit in a bounding-volume hierarchy; a query visits only those that can matter.
/// Immutable; thread-safe. Complexity: O(log segments + segments near p) per query.
#pragma once

#include "adf/distance_source.h"
#include "adf/domain.h"
#include "sculpt/tool.h"

#include <glm/mat3x3.hpp>

#include <limits>
#include <memory>
#include <span>
#include <vector>

namespace kizamu::sculpt {

class SweptTool final : public adf::DistanceSource {
public:
    /// @throw std::invalid_argument for an invalid tool, no samples, or non-finite poses.
    SweptTool(const Tool& tool, std::vector<ToolSample> samples);

    double distance(const glm::dvec3& p) const override { return distanceBelow(p, std::numeric_limits<double>::infinity()); }
    /// The distance where it is below `limit`; otherwise some value >= `limit`. Parts of the
    /// stroke that cannot come closer than the limit are not searched (what an edit needs:
    /// far from the tool the old field wins the CSG anyway).
    double distanceBelow(const glm::dvec3& p, double limit) const;
    /// distanceBelow of every point of `p`, each with its own limit, into `limitInOut` (the
    /// same values). For a sphere's dab or one-segment stroke (what most dabs are) the loop
    /// runs the capsule distance directly: no search and no call per point.
    void distancesBelow(std::span<const glm::dvec3> p, std::span<double> limitInOut) const;
    /// A lower bound of the true distance to the swept volume where below `limit` (otherwise
    /// `limit`), without searching: exact for a sphere (a capsule per segment), a box bound per
    /// segment for the other shapes. distance() never falls below it (its search only misses
    /// minima, never invents them). What an edit needs to say where it cannot reach.
    double lowerBound(const glm::dvec3& p, double limit) const;
    double featureSize(const glm::dvec3& centre, double radius) const override;

    /// Box (m) containing every point of the swept tool.
    adf::BoxWorld bounds() const { return mBounds; }
    const Tool& tool() const { return mTool; }
    /// The stroke's first pose (orientation unit).
    const ToolSample& firstSample() const { return mSegments.front().a; }

private:
    struct Segment {
        ToolSample a, b;
        glm::dmat3 inverseA;    ///< world to tool frame at a
        glm::dvec3 moveA;       ///< b - a in the tool frame at a (other shapes, fixed orientations)
        double moveA2;          ///< its squared length
        glm::dvec3 axis;        ///< world axis of the turn from a to b (unit)
        double angle;           ///< radians turned from a to b
        bool fixedOrientation;  ///< a and b share their orientation
        int angleSteps;         ///< samples for the turning case
        glm::dvec3 move{0.0};   ///< b - a in the world (a sphere's capsule)
        double move2 = 0.0;     ///< its squared length
    };
    struct Node {
        glm::dvec3 lo, hi;  ///< segment boxes grown by the tool's bounding radius
        uint32_t first, count, left, right;
    };
    double segmentDistance(const Segment& s, const glm::dvec3& p) const;
    /// A sphere's distance along a segment, whatever its turn (a sphere turns into itself):
    /// the capsule from a to b.
    double capsuleDistance(const Segment& s, const glm::dvec3& p) const;
    /// Nearest segment by `segment(s)`, visiting only BVH nodes whose box could beat `limit`.
    template <class SegmentDistance>
    double search(const glm::dvec3& p, double limit, const SegmentDistance& segment) const;
    uint32_t build(uint32_t first, uint32_t count);

    Tool mTool;
    double mBoundingRadius;  ///< mTool's, asked by every query
    std::vector<Segment> mSegments;
    std::vector<Node> mNodes;
    adf::BoxWorld mBounds;
};

std::shared_ptr<const SweptTool> makeSweptTool(const Tool& tool, std::vector<ToolSample> samples);

/// Throws std::invalid_argument (readable) unless `tool` is valid and `samples` is non-empty
/// with finite positions and non-zero finite orientations: what SweptTool requires.
void validateStroke(const Tool& tool, const std::vector<ToolSample>& samples);

}  // namespace kizamu::sculpt
