// SPDX-License-Identifier: Apache-2.0
/// @file stroke_edit.cpp
/// @brief StrokeEdit: a stroke's CSG with the old field.
#include "sculpt/stroke_edit.h"

#include "sculpt/symmetry.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <span>
#include <utility>

namespace kizamu::sculpt {

namespace {


/// old − tool (carve) or old ∪ tool (add), as min/max CSG, asking the swept tool only as far as
/// it can change the answer. `reflect` mirrors the tool across the domain's mid planes of the
/// axes whose bit is set (symmetry): the query point is reflected instead.
class StrokeEdit final : public adf::DistanceSource {
public:
    StrokeEdit(adf::SourcePtr old, std::shared_ptr<const SweptTool> tool, uint8_t reflect, glm::dvec3 centre, double offset,
               ToolLimits limits, double finestCell)
        : mOld(std::move(old)), mTool(std::move(tool)), mOp(mTool->tool().op), mReflect(reflect), mCentre(centre),
          mOffset(offset), mFinestCell(finestCell), mCore(mTool->tool().strength * mTool->tool().radius), mLimits(std::move(limits)) {
        // Flatten: the plane through the first pose, normal to its z axis (mirrored copies
        // mirror the point, so the plane is taken in the reflected frame too).
        const ToolSample& first = mTool->firstSample();
        mPlanePoint = mirrored(first.position);
        mPlaneNormal = first.orientation * glm::dvec3(0.0, 0.0, 1.0);
        for (int k = 0; k < 3; ++k)
            if ((mReflect >> k) & 1) mPlaneNormal[k] = -mPlaneNormal[k];
        mSmallestFeature = std::min(mOld->smallestFeature(), mTool->smallestFeature());
        for (const adf::SourcePtr& m : mLimits.masks) mSmallestFeature = std::min(mSmallestFeature, m->smallestFeature());
    }
    double distance(const glm::dvec3& p) const override { return combine(p, mOld->distance(p)); }
    void distances(std::span<const glm::dvec3> p, std::span<double> out) const override {
        mOld->distances(p, out);
        if (plainCsg()) return combineRun(p, out);
        for (std::size_t i = 0; i < p.size(); ++i) out[i] = combine(p[i], out[i]);
    }
    /// At lattice points when the old field answers them (a snapshot's own lattice): the tool
    /// takes their world positions, the old field the points themselves.
    bool answersLattice(const adf::Domain& d) const override { return mOld->answersLattice(d); }
    void latticeDistances(const adf::Domain& d, std::span<const glm::uvec3> p, std::span<double> out) const override {
        mOld->latticeDistances(d, p, out);
        const glm::dvec3 origin = d.originWorld;
        const double cell = d.finestCellSize();
        if (!plainCsg()) {
            for (std::size_t i = 0; i < p.size(); ++i) out[i] = combine(adf::Domain::latticeToWorld(origin, cell, p[i]), out[i]);
            return;
        }
        glm::dvec3 world[kRun];
        for (std::size_t first = 0; first < p.size(); first += kRun) {
            const std::size_t n = std::min(kRun, p.size() - first);
            for (std::size_t k = 0; k < n; ++k) world[k] = adf::Domain::latticeToWorld(origin, cell, p[first + k]);
            combineRun({world, n}, out.subspan(first, n));
        }
    }
    double featureSize(const glm::dvec3& c, double radius) const override {
        double f = std::min(mOld->featureSize(c, radius), mTool->featureSize(mirrored(c), radius));
        for (const adf::SourcePtr& m : mLimits.masks) f = std::min(f, m->featureSize(c, radius));
        return f;
    }

    /// Where the tool cannot reach, the old field stands: carving changes only points deeper
    /// in the material than the tool's distance, adding only points farther out, the gradual
    /// tools only points inside the tool. The true swept distance is 1-Lipschitz and the tool's
    /// answer never below it, so a lower bound of it at the centre, less the radius, bounds the
    /// tool over the ball (SweptTool::lowerBound: exact for spheres, a box bound otherwise, no
    /// search per cell). Masks and limits only ever take away from what the tool does. The
    /// slack covers neighbouring tiles storing a shared corner at different scales (the
    /// generator also allows for the old tile's own rounding).
    Range unchangedRange(const glm::dvec3& c, double radius) const override {
        constexpr double kInf = std::numeric_limits<double>::infinity();
        const double slack = 0.05 * mFinestCell;
        const double reach = radius + slack;
        const glm::dvec3 q = mirrored(c);
        // Searched only up to well past the band: beyond, the limit itself is a lower bound.
        const double far = reach + 32.0 * mFinestCell;
        switch (mOp) {
        case ToolOp::Carve: return {reach - mTool->lowerBound(q, far), kInf};  // unchanged where old >= -tool
        case ToolOp::Add: return {-kInf, mTool->lowerBound(q, far) - reach};   // unchanged where old <= tool
        default:
            if (mTool->lowerBound(q, reach) >= reach) return {-kInf, kInf};  // the weight is 0
            return {};
        }
    }

private:
    /// A carve or an addition with neither symmetry nor limits: min/max with the tool alone.
    bool plainCsg() const { return (mOp == ToolOp::Carve || mOp == ToolOp::Add) && mReflect == 0 && mLimits.empty(); }
    static constexpr std::size_t kRun = 64;
    /// combine() of world points `p` with the old values in `out` when plainCsg(), the tool asked
    /// for a run of at most kRun points at once (SweptTool::distancesBelow): the same values.
    void combineRun(std::span<const glm::dvec3> p, std::span<double> out) const {
        double tool[kRun];
        const bool carve = mOp == ToolOp::Carve;
        for (std::size_t first = 0; first < p.size(); first += kRun) {
            const std::size_t n = std::min(kRun, p.size() - first);
            for (std::size_t k = 0; k < n; ++k) tool[k] = carve ? -out[first + k] : out[first + k];  // where the tool decides
            mTool->distancesBelow(p.subspan(first, n), {tool, n});
            for (std::size_t k = 0; k < n; ++k) {
                double& v = out[first + k];
                v = carve ? std::max(v, -tool[k]) : std::min(v, tool[k]);
            }
        }
    }
    glm::dvec3 mirrored(const glm::dvec3& p) const { return mirroredPoint(p, mReflect, mCentre); }
    /// The swept tool's distance at p (q: p mirrored) where below `limit`, cut by the limits:
    /// intersected with the outside of every mask and with the allowed side of the offset of
    /// the reference surface.
    double toolBelow(const glm::dvec3& p, const glm::dvec3& q, double limit) const {
        double d = mTool->distanceBelow(q, limit);
        if (d >= limit || mLimits.empty()) return d;
        for (const adf::SourcePtr& m : mLimits.masks) d = std::max(d, -m->distance(p));
        if (mLimits.reference) {
            const double ref = mLimits.reference->distance(p);
            if (mLimits.depth >= 0.0) d = std::max(d, -(ref + mLimits.depth));  // carve only above ref = -depth
            if (mLimits.height >= 0.0) d = std::max(d, ref - mLimits.height);   // add only below ref = height
        }
        return d;
    }
    double combine(const glm::dvec3& p, double old) const {
        const glm::dvec3 q = mirrored(p);
        switch (mOp) {
        case ToolOp::Carve: return std::max(old, -toolBelow(p, q, -old));  // decided by tool < -old
        case ToolOp::Add: return std::min(old, toolBelow(p, q, old));      // decided by tool < old
        default: break;
        }
        // The gradual tools: a smooth weight, 0 at the tool's boundary and 1 at depth `mCore`
        // inside it, so the surface moves continuously as the tool arrives.
        const double inside = -toolBelow(p, q, 0.0);
        if (!(inside > 0.0)) return old;
        const double w = toolWeight(inside, mCore);
        switch (mOp) {
        case ToolOp::Build: return old - mOffset * w;
        case ToolOp::HeatGun: return old + mOffset * w;
        case ToolOp::Smooth: {
            // One Laplacian step: the mean of the field at six points a quarter of the tool's
            // radius away. A plane's field is its own mean; a ridge's is higher (wears), a
            // valley's lower (fills).
            const double r = 0.25 * mTool->tool().radius;
            double mean = 0.0;
            for (int k = 0; k < 3; ++k)
                for (double sign : {-1.0, 1.0}) {
                    glm::dvec3 o(0.0);
                    o[k] = sign * r;
                    mean += mOld->distance(p + o);
                }
            return old + w * mTool->tool().strength * (mean / 6.0 - old);
        }
        case ToolOp::Flatten: return old + w * (glm::dot(p - mPlanePoint, mPlaneNormal) - old);
        default: return old;
        }
    }
    adf::SourcePtr mOld;
    std::shared_ptr<const SweptTool> mTool;
    ToolOp mOp;
    uint8_t mReflect;
    glm::dvec3 mCentre;
    double mOffset;  ///< m, build and heat gun
    double mFinestCell;  ///< m
    double mCore;    ///< m, depth inside the tool where the weight reaches 1
    glm::dvec3 mPlanePoint{0.0}, mPlaneNormal{0.0, 0.0, 1.0};  ///< flatten
    ToolLimits mLimits;
};

/// The tool's distance at p (q: p mirrored) where below `limit`, cut by masks and limits
/// (StrokeEdit::toolBelow, for any swept tool).
double limitedToolBelow(const SweptTool& tool, const ToolLimits& limits, const glm::dvec3& p, const glm::dvec3& q, double limit) {
    double d = tool.distanceBelow(q, limit);
    if (d >= limit || limits.empty()) return d;
    for (const adf::SourcePtr& m : limits.masks) d = std::max(d, -m->distance(p));
    if (limits.reference) {
        const double ref = limits.reference->distance(p);
        if (limits.depth >= 0.0) d = std::max(d, -(ref + limits.depth));
        if (limits.height >= 0.0) d = std::max(d, ref - limits.height);
    }
    return d;
}

/// old + the growth a live segment of a gradual tool adds (LiveSegment).
class LiveSegmentEdit final : public adf::DistanceSource {
public:
    LiveSegmentEdit(adf::SourcePtr old, LiveSegment seg, uint8_t reflect, glm::dvec3 centre, ToolLimits limits, double finestCell)
        : mOld(std::move(old)), mSeg(std::move(seg)), mOp(mSeg.segment->tool().op), mReflect(reflect), mCentre(centre),
          mFinestCell(finestCell), mCore(mSeg.segment->tool().strength * mSeg.segment->tool().radius),
          mLimits(std::move(limits)) {
        if (mOp == ToolOp::Carve || mOp == ToolOp::Add || mOp == ToolOp::Paint)
            throw std::invalid_argument("a live segment edit is for the gradual tools (build, heat gun, smooth, flatten)");
        // Flatten's plane: through the stroke's first pose, as StrokeEdit takes it.
        mPlanePoint = mirroredPoint(mSeg.first.position, mReflect, mCentre);
        mPlaneNormal = glm::normalize(mSeg.first.orientation) * glm::dvec3(0.0, 0.0, 1.0);
        for (int k = 0; k < 3; ++k)
            if ((mReflect >> k) & 1) mPlaneNormal[k] = -mPlaneNormal[k];
        // The heat gun's dwell grew: the whole path swept so far melts further.
        mWholePath = mOp == ToolOp::HeatGun && mSeg.before && mSeg.offsetNow != mSeg.offsetBefore;
        mSmallestFeature = std::min({mOld->smallestFeature(), mSeg.start->smallestFeature(), mSeg.segment->smallestFeature()});
        for (const adf::SourcePtr& m : mLimits.masks) mSmallestFeature = std::min(mSmallestFeature, m->smallestFeature());
    }
    double distance(const glm::dvec3& p) const override { return combine(p, mOld->distance(p)); }
    void distances(std::span<const glm::dvec3> p, std::span<double> out) const override {
        mOld->distances(p, out);
        for (std::size_t i = 0; i < p.size(); ++i) out[i] = combine(p[i], out[i]);
    }
    bool answersLattice(const adf::Domain& d) const override { return mOld->answersLattice(d); }
    void latticeDistances(const adf::Domain& d, std::span<const glm::uvec3> p, std::span<double> out) const override {
        mOld->latticeDistances(d, p, out);
        for (std::size_t i = 0; i < p.size(); ++i)
            out[i] = combine(adf::Domain::latticeToWorld(d.originWorld, d.finestCellSize(), p[i]), out[i]);
    }
    double featureSize(const glm::dvec3& c, double radius) const override {
        double f = std::min({mOld->featureSize(c, radius), mSeg.start->featureSize(c, radius),
                             mSeg.segment->featureSize(mirrored(c), radius)});
        if (mWholePath) f = std::min(f, mSeg.before->featureSize(mirrored(c), radius));
        for (const adf::SourcePtr& m : mLimits.masks) f = std::min(f, m->featureSize(c, radius));
        return f;
    }
    /// The growth is 0 outside the segment's tool (and, when the heat gun's dwell grew, outside
    /// the path swept so far): the old field stands there.
    Range unchangedRange(const glm::dvec3& c, double radius) const override {
        constexpr double kInf = std::numeric_limits<double>::infinity();
        const double reach = radius + 0.05 * mFinestCell;
        const glm::dvec3 q = mirrored(c);
        if (mSeg.segment->lowerBound(q, reach) < reach) return {};
        if (mWholePath && mSeg.before->lowerBound(q, reach) < reach) return {};
        return {-kInf, kInf};
    }

private:
    glm::dvec3 mirrored(const glm::dvec3& p) const { return mirroredPoint(p, mReflect, mCentre); }
    double weight(const SweptTool& tool, const glm::dvec3& p, const glm::dvec3& q) const {
        const double inside = -limitedToolBelow(tool, mLimits, p, q, 0.0);
        return inside > 0.0 ? toolWeight(inside, mCore) : 0.0;
    }
    /// Where the running maximum weight grows (or the heat gun's dwell did), the start field
    /// moved by the new maximum: the previous segments' result there plus the growth, read
    /// from the start snapshot rather than from the regenerated field, so no error accumulates
    /// over segments. Elsewhere the old field stands.
    double combine(const glm::dvec3& p, double old) const {
        const glm::dvec3 q = mirrored(p);
        const double wSeg = weight(*mSeg.segment, p, q);
        if (!(wSeg > 0.0) && !mWholePath) return old;
        const double wBefore = mSeg.before ? weight(*mSeg.before, p, q) : 0.0;
        const double w = std::max(wBefore, wSeg);
        if (mOp == ToolOp::HeatGun) {
            if (!(w > 0.0) || (!(wSeg > wBefore) && !mWholePath)) return old;
            return mSeg.start->distance(p) + mSeg.offsetNow * w;
        }
        if (!(wSeg > wBefore)) return old;
        const double start = mSeg.start->distance(p);
        switch (mOp) {
        case ToolOp::Build: return start - mSeg.offsetNow * w;
        case ToolOp::Smooth: {
            // StrokeEdit's Laplacian step, of the start field.
            const double r = 0.25 * mSeg.segment->tool().radius;
            double mean = 0.0;
            for (int k = 0; k < 3; ++k)
                for (double sign : {-1.0, 1.0}) {
                    glm::dvec3 o(0.0);
                    o[k] = sign * r;
                    mean += mSeg.start->distance(p + o);
                }
            return start + w * mSeg.segment->tool().strength * (mean / 6.0 - start);
        }
        case ToolOp::Flatten: return start + w * (glm::dot(p - mPlanePoint, mPlaneNormal) - start);
        default: return old;
        }
    }
    adf::SourcePtr mOld;
    LiveSegment mSeg;
    ToolOp mOp;
    uint8_t mReflect;
    glm::dvec3 mCentre;
    double mFinestCell;  ///< m
    double mCore;        ///< m
    glm::dvec3 mPlanePoint{0.0}, mPlaneNormal{0.0, 0.0, 1.0};
    bool mWholePath = false;
    ToolLimits mLimits;
};

}  // namespace

adf::SourcePtr makeLiveSegmentEdit(adf::SourcePtr old, LiveSegment segment, uint8_t reflect, glm::dvec3 centre,
                                   ToolLimits limits, double finestCell) {
    return std::make_shared<LiveSegmentEdit>(std::move(old), std::move(segment), reflect, centre, std::move(limits),
                                             finestCell);
}

adf::SourcePtr makeStrokeEdit(adf::SourcePtr old, std::shared_ptr<const SweptTool> tool, uint8_t reflect,
                              glm::dvec3 centre, double offset, ToolLimits limits, double finestCell) {
    return std::make_shared<StrokeEdit>(std::move(old), std::move(tool), reflect, centre, offset, std::move(limits),
                                        finestCell);
}

}  // namespace kizamu::sculpt
