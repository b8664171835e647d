// SPDX-License-Identifier: Apache-2.0
/// @file sculptor.cpp
/// @brief Sculptor: strokes as regenerated CSG, undo and redo.
#include "sculpt/sculptor.h"

#include "adf/adf_source.h"
#include "adf/generate.h"
#include "sculpt/paint.h"
#include "sculpt/swept_tool.h"

#include <glm/common.hpp>

#include <algorithm>
#include <chrono>
#include <memory>
#include <span>
#include <unordered_set>

namespace kizamu::sculpt {

namespace {

/// old − tool (carve) or old ∪ tool (add), as min/max CSG, asking the swept tool only as far as
/// it can change the answer. `reflect` mirrors the tool across the domain's mid planes of the
/// axes whose bit is set (symmetry): the query point is reflected instead.
class StrokeEdit final : public adf::DistanceSource {
public:
    StrokeEdit(adf::SourcePtr old, std::shared_ptr<const SweptTool> tool, uint8_t reflect, glm::dvec3 centre, double offset)
        : mOld(std::move(old)), mTool(std::move(tool)), mOp(mTool->tool().op), mReflect(reflect), mCentre(centre),
          mOffset(offset), mCore(mTool->tool().strength * mTool->tool().radius) {
        // Flatten: the plane through the first pose, normal to its z axis (mirrored copies
        // mirror the point, so the plane is taken in the reflected frame too).
        const ToolSample& first = mTool->firstSample();
        mPlanePoint = mirrored(first.position);
        mPlaneNormal = first.orientation * glm::dvec3(0.0, 0.0, 1.0);
        for (int k = 0; k < 3; ++k)
            if ((mReflect >> k) & 1) mPlaneNormal[k] = -mPlaneNormal[k];
        mSmallestFeature = std::min(mOld->smallestFeature(), mTool->smallestFeature());
    }
    double distance(const glm::dvec3& p) const override { return combine(p, mOld->distance(p)); }
    void distances(std::span<const glm::dvec3> p, std::span<double> out) const override {
        mOld->distances(p, out);
        for (std::size_t i = 0; i < p.size(); ++i) out[i] = combine(p[i], out[i]);
    }
    double featureSize(const glm::dvec3& c, double radius) const override {
        return std::min(mOld->featureSize(c, radius), mTool->featureSize(mirrored(c), radius));
    }

private:
    glm::dvec3 mirrored(glm::dvec3 p) const {
        for (int k = 0; k < 3; ++k)
            if ((mReflect >> k) & 1) p[k] = 2.0 * mCentre[k] - p[k];
        return p;
    }
    double combine(const glm::dvec3& p, double old) const {
        const glm::dvec3 q = mirrored(p);
        switch (mOp) {
        case ToolOp::Carve: return std::max(old, -mTool->distanceBelow(q, -old));  // decided by tool < -old
        case ToolOp::Add: return std::min(old, mTool->distanceBelow(q, old));      // decided by tool < old
        default: break;
        }
        // The gradual tools: a smooth weight, 0 at the tool's boundary and 1 at depth `mCore`
        // inside it, so the surface moves continuously as the tool arrives.
        const double inside = -mTool->distanceBelow(q, 0.0);
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
    double mCore;    ///< m, depth inside the tool where the weight reaches 1
    glm::dvec3 mPlanePoint{0.0}, mPlaneNormal{0.0, 0.0, 1.0};  ///< flatten
};

/// Bytes of the tiles `before` has in `region` that `after` replaced.
std::size_t replacedBytes(const adf::Adf& before, const adf::Adf& after, const adf::BoxWorld& region) {
    const adf::Domain& d = before.domain();
    const double slot = d.finestCellSize() * double(1u << d.tileSpan());
    const uint32_t n = d.slotsPerAxis();
    auto toSlot = [&](double w, double o) {
        return uint32_t(std::clamp((w - o) / slot, 0.0, double(n - 1)));
    };
    std::unordered_set<const adf::Tile*> seen;
    std::size_t bytes = 0;
    for (uint32_t z = toSlot(region.min.z, d.originWorld.z); z <= toSlot(region.max.z, d.originWorld.z); ++z)
        for (uint32_t y = toSlot(region.min.y, d.originWorld.y); y <= toSlot(region.max.y, d.originWorld.y); ++y)
            for (uint32_t x = toSlot(region.min.x, d.originWorld.x); x <= toSlot(region.max.x, d.originWorld.x); ++x) {
                const adf::Tile* old = before.tileAtSlot({x, y, z});
                if (old != after.tileAtSlot({x, y, z}) && seen.insert(old).second) bytes += old->bytes();
            }
    return bytes;
}

}  // namespace

Sculptor::Sculptor(adf::AdfPtr start, util::ThreadPool* pool, std::size_t historyBytes)
    : mPool(pool), mCurrent(std::move(start)), mBudget(historyBytes) {
    if (!mCurrent) throw std::invalid_argument("sculptor needs a start snapshot");
}

adf::BoxWorld strokeRegion(const adf::Adf& adf, const adf::BoxWorld& swept) {
    const adf::Domain& d = adf.domain();
    const double pad = adf.settings().bandWorld(d) + 2.0 * d.finestCellSize();
    const glm::dvec3 lo = d.originWorld, hi = d.originWorld + glm::dvec3(d.sizeWorld);
    return {glm::clamp(swept.min - pad, lo, hi), glm::clamp(swept.max + pad, lo, hi)};
}

void Sculptor::apply(const Stroke& stroke) {
    const auto t0 = std::chrono::steady_clock::now();
    if (stroke.tool.op == ToolOp::Paint) {
        // Paint changes only the colour layer: the new snapshot shares every distance tile.
        PaintStats ps;
        adf::AdfBuilder builder(*mCurrent);
        builder.setColours(paintStroke(*mCurrent, stroke, mPool, &ps));
        mLast.tilesRebuilt = 0;
        mLast.colourTilesPainted = ps.slotsPainted;
        finish(builder.build(mCurrent->version() + 1), ps.replacedBytes, t0);
        return;
    }
    const auto swept = makeSweptTool(stroke.tool, stroke.samples);
    const adf::Domain& d = mCurrent->domain();
    const glm::dvec3 centre = d.originWorld + glm::dvec3(0.5 * d.sizeWorld);
    // One regeneration per mirrored copy, each over its own region (a union box would rebuild
    // every tile between the copies); together they are one stroke and one undo record.
    adf::AdfPtr next = mCurrent;
    std::size_t bytes = 0;
    mLast.tilesRebuilt = 0;
    for (uint8_t reflect = 0; reflect < 8; ++reflect) {
        if ((reflect & ~stroke.mirror) != 0) continue;
        adf::BoxWorld bounds = swept->bounds();
        for (int k = 0; k < 3; ++k)
            if ((reflect >> k) & 1) {
                const double lo = 2.0 * centre[k] - bounds.max[k], hi = 2.0 * centre[k] - bounds.min[k];
                bounds.min[k] = lo;
                bounds.max[k] = hi;
            }
        const adf::BoxWorld region = strokeRegion(*next, bounds);
        const adf::SourcePtr old = adf::makeAdfSource(next);
        const double offset = stroke.tool.op == ToolOp::HeatGun ? stroke.tool.rate * stroke.dwell : stroke.tool.amount;
        const adf::SourcePtr edited = std::make_shared<StrokeEdit>(old, swept, reflect, centre, offset);
        adf::GenerationStats gs;
        adf::AdfPtr after = adf::regenerate(*next, *adf::makeRegionLimited(old, edited, region), region, mPool, &gs);
        mLast.tilesRebuilt += gs.tilesGenerated + gs.coarseTiles;
        bytes += replacedBytes(*mCurrent, *after, region);
        next = std::move(after);
    }
    mLast.colourTilesPainted = 0;
    finish(std::move(next), bytes, t0);
}

void Sculptor::finish(adf::AdfPtr next, std::size_t replacedBytes, std::chrono::steady_clock::time_point t0) {
    mLast.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    mLast.replacedBytes = replacedBytes;

    mRedo.clear();
    mUndo.push_back({mCurrent, mLast.replacedBytes});
    mHistoryBytes += mLast.replacedBytes;
    while (!mUndo.empty() && (mBudget == 0 || mHistoryBytes > mBudget)) {
        mHistoryBytes -= mUndo.front().bytes;
        mUndo.pop_front();
    }
    mCurrent = std::move(next);
}

bool Sculptor::undo() {
    if (mUndo.empty()) return false;
    Record r = std::move(mUndo.back());
    mUndo.pop_back();
    mHistoryBytes -= r.bytes;
    mRedo.push_back({mCurrent, r.bytes});
    mCurrent = std::move(r.snapshot);
    return true;
}

bool Sculptor::redo() {
    if (mRedo.empty()) return false;
    Record r = std::move(mRedo.back());
    mRedo.pop_back();
    mUndo.push_back({mCurrent, r.bytes});
    mHistoryBytes += r.bytes;
    mCurrent = std::move(r.snapshot);
    return true;
}

void Sculptor::replay(const Step& step) {
    switch (step.kind) {
    case Step::Kind::Stroke: apply(step.stroke); break;
    case Step::Kind::Undo: undo(); break;
    case Step::Kind::Redo: redo(); break;
    }
}

adf::AdfPtr startAdf(const Script& script, int level, util::ThreadPool* pool) {
    adf::Domain d = script.domain;
    if (level > 0) d.maxLevel = level;
    if (!d.valid()) throw std::invalid_argument("invalid domain or level for the script");
    return adf::generate(*script.start.source(d), d, adf::GenerationSettings{}, pool);
}

}  // namespace kizamu::sculpt
