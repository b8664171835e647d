// SPDX-License-Identifier: Apache-2.0
/// @file sculptor.cpp
/// @brief Sculptor: strokes as regenerated CSG, undo and redo.
#include "sculpt/sculptor.h"

#include "adf/adf_source.h"
#include "adf/generate.h"
#include "sculpt/paint.h"
#include "sculpt/stroke_edit.h"
#include "sculpt/stroke_path.h"
#include "sculpt/swept_tool.h"
#include "sculpt/symmetry.h"

#include <glm/common.hpp>
#include <glm/vector_relational.hpp>

#include <algorithm>
#include <chrono>
#include <memory>
#include <span>
#include <limits>
#include <unordered_set>
#include <utility>

namespace kizamu::sculpt {

namespace {

/// Bytes of the tiles `before` has in `region` that `after` replaced.
std::size_t replacedBytes(const adf::Adf& before, const adf::Adf& after, const adf::BoxWorld& region) {
    std::unordered_set<const adf::Tile*> seen;
    std::size_t bytes = 0;
    adf::forEachSlotIn(before.domain(), region, [&](glm::uvec3 slot) {
        const adf::Tile* old = before.tileAtSlot(slot);
        if (old != after.tileAtSlot(slot) && seen.insert(old).second) bytes += old->bytes();
    });
    return bytes;
}

}  // namespace

Sculptor::Sculptor(adf::AdfPtr start, util::ThreadPool* pool, std::size_t historyBytes)
    : mPool(pool), mCurrent(std::move(start)), mBudget(historyBytes) {
    if (!mCurrent) throw std::invalid_argument("sculptor needs a start snapshot");
}

Sculptor::~Sculptor() = default;

adf::BoxWorld strokeRegion(const adf::Adf& adf, const adf::BoxWorld& swept) {
    const adf::Domain& d = adf.domain();
    return adf::grownWithin(d, swept, adf.settings().bandWorld(d) + 2.0 * d.finestCellSize());
}

ToolLimits Sculptor::limitsFor(const Stroke& stroke) const {
    const StrokeConstraints& c = stroke.constraints;
    ToolLimits limits;
    for (const Shape& m : c.masks) limits.masks.push_back(m.source(mCurrent->domain()));
    if (c.depthLimit || c.heightLimit) {
        if (!mReference) throw std::invalid_argument("depth and height limits need the original surface (Sculptor::setReference)");
        limits.reference = mReference;
        limits.depth = c.depthLimit.value_or(-1.0);
        limits.height = c.heightLimit.value_or(-1.0);
    }
    return limits;
}

void Sculptor::apply(const Stroke& stroke) {
    const auto t0 = std::chrono::steady_clock::now();
    validate(stroke);  // before anything changes: a rejected stroke leaves no trace
    const ToolLimits limits = limitsFor(stroke);
    // A copy: correctNear below replaces the current snapshot, which may free the old one.
    const adf::Domain d = mCurrent->domain();
    if (stroke.constraints.followOffset && mCorrecting) {
        // Following reads the field away from the surface: make it true around the path first.
        adf::BoxWorld near{glm::dvec3(std::numeric_limits<double>::max()), glm::dvec3(std::numeric_limits<double>::lowest())};
        for (const ToolSample& t : stroke.samples) {
            near.min = glm::min(near.min, t.position);
            near.max = glm::max(near.max, t.position);
        }
        const double reach = std::abs(*stroke.constraints.followOffset) + stroke.tool.boundingRadius() +
                             mCorrection.radiusCells * d.finestCellSize();
        correctNear({near.min - reach, near.max + reach});
    }
    // Curves and constrained paths are kept within a tenth of a finest cell: below what the
    // field resolves (epsilon is a quarter cell).
    std::vector<ToolSample> path = resolvePath(stroke, *mCurrent, 0.1 * d.finestCellSize());
    if (stroke.tool.op == ToolOp::Paint) {
        // Paint changes only the colour layer: the new snapshot shares every distance tile, and
        // no correction is owed.
        Stroke resolved = stroke;
        resolved.samples = std::move(path);
        resolved.bezier = false;
        PaintStats ps;
        adf::AdfBuilder builder(*mCurrent);
        builder.setColours(paintStroke(*mCurrent, resolved, mPool, &ps));
        mLast.tilesRebuilt = 0;
        mLast.samples = 0;
        mLast.colourTilesPainted = ps.slotsPainted;
        finish(builder.build(mCurrent->version() + 1), ps.replacedBytes, mPending, t0);
        return;
    }
    const auto swept = makeSweptTool(stroke.tool, std::move(path));
    const glm::dvec3 centre = d.originWorld + glm::dvec3(0.5 * d.sizeWorld);
    // One regeneration per mirrored copy, each over its own region (a union box would rebuild
    // every tile between the copies); together they are one stroke and one undo record.
    adf::AdfPtr next = mCurrent;
    PendingList pending = mPending;
    std::size_t bytes = 0;
    mLast.tilesRebuilt = 0;
    mLast.samples = 0;
    for (uint8_t reflect = 0; reflect < 8; ++reflect) {
        if ((reflect & ~stroke.mirror) != 0) continue;
        const adf::BoxWorld region = strokeRegion(*next, mirroredBox(swept->bounds(), reflect, centre));
        const adf::SourcePtr old = adf::makeAdfSource(next);
        const double offset = stroke.tool.op == ToolOp::HeatGun ? stroke.tool.rate * stroke.dwell : stroke.tool.amount;
        const adf::SourcePtr edited = makeStrokeEdit(old, swept, reflect, centre, offset, limits, d.finestCellSize());
        adf::GenerationStats gs;
        adf::AdfPtr after = adf::regenerate(*next, *adf::makeRegionLimited(old, edited, region), region, mPool, &gs);
        mLast.tilesRebuilt += gs.tilesGenerated + gs.coarseTiles;
        mLast.samples += gs.samples;
        bytes += replacedBytes(*mCurrent, *after, region);
        next = std::move(after);
        if (mCorrecting)
            pending = std::make_shared<const PendingZone>(PendingZone{correctionZone(*next, region, mCorrection), pending});
    }
    mLast.colourTilesPainted = 0;
    finish(std::move(next), bytes, std::move(pending), t0);
}

void Sculptor::finish(adf::AdfPtr next, std::size_t replacedBytes, PendingList pending, std::chrono::steady_clock::time_point t0) {
    mLast.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    mLast.replacedBytes = replacedBytes;

    mRedo.clear();
    mUndo.push_back({mCurrent, mLast.replacedBytes, std::move(mPending)});
    mPending = std::move(pending);
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
    mRedo.push_back({mCurrent, r.bytes, std::move(mPending)});
    mCurrent = std::move(r.snapshot);
    mPending = mCorrecting ? std::move(r.pending) : nullptr;
    return true;
}

bool Sculptor::redo() {
    if (mRedo.empty()) return false;
    Record r = std::move(mRedo.back());
    mRedo.pop_back();
    mUndo.push_back({mCurrent, r.bytes, std::move(mPending)});
    mHistoryBytes += r.bytes;
    mCurrent = std::move(r.snapshot);
    mPending = mCorrecting ? std::move(r.pending) : nullptr;
    return true;
}

void Sculptor::setCorrection(const CorrectionSettings& settings, bool enabled) {
    if (!(settings.radiusCells > 0.0) || !(settings.keepCells > 0.0) || settings.keepCells * 2.0 > settings.radiusCells)
        throw std::invalid_argument("correction needs 0 < 2 x keep <= radius (finest cells)");
    mCorrection = settings;
    mCorrecting = enabled;
    if (!enabled) mPending = nullptr;  // undo and redo drop the lists their records hold, too
}

std::vector<adf::BoxWorld> Sculptor::oldestFirst(const PendingList& list) {
    std::vector<adf::BoxWorld> out;
    for (const PendingZone* z = list.get(); z; z = z->older.get()) out.push_back(z->zone);
    std::reverse(out.begin(), out.end());
    return out;
}

Sculptor::PendingList Sculptor::listOf(const std::vector<adf::BoxWorld>& oldestFirst) {
    PendingList list;
    for (const adf::BoxWorld& z : oldestFirst) list = std::make_shared<const PendingZone>(PendingZone{z, list});
    return list;
}

std::vector<adf::BoxWorld> Sculptor::pendingCorrections() const { return oldestFirst(mPending); }

void Sculptor::correct(std::vector<adf::BoxWorld> zones, std::vector<adf::BoxWorld> remaining) {
    if (!zones.empty()) mCurrent = correctZones(mCurrent, std::move(zones), mPool, mCorrection);
    mPending = listOf(remaining);
}

adf::AdfPtr Sculptor::settled() const { return correctZones(mCurrent, oldestFirst(mPending), mPool, mCorrection); }

void Sculptor::correctNear(const adf::BoxWorld& box) {
    std::vector<adf::BoxWorld> now, later;
    for (const adf::BoxWorld& z : oldestFirst(mPending)) {
        const bool overlaps = glm::all(glm::lessThanEqual(z.min, box.max)) && glm::all(glm::lessThanEqual(box.min, z.max));
        (overlaps ? now : later).push_back(z);
    }
    if (!now.empty()) correct(std::move(now), std::move(later));
}

bool Sculptor::correctOne() {
    std::vector<adf::BoxWorld> all = oldestFirst(mPending);
    if (all.empty()) return false;
    const adf::BoxWorld z = all.front();
    all.erase(all.begin());
    correct({z}, std::move(all));
    return true;
}

void Sculptor::finishCorrections() { correct(oldestFirst(mPending), {}); }

void Sculptor::replay(const Step& step) {
    switch (step.kind) {
    case Step::Kind::Stroke: apply(step.stroke); break;
    case Step::Kind::Undo: undo(); break;
    case Step::Kind::Redo: redo(); break;
    case Step::Kind::Correct:
        if (step.zones == 0) {
            finishCorrections();
        } else {
            for (std::size_t i = 0; i < step.zones && correctOne(); ++i) {
            }
        }
        break;
    }
}

}  // namespace kizamu::sculpt
