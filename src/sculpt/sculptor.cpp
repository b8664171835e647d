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
#include <array>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>
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

adf::BoxWorld boxUnion(const adf::BoxWorld& a, const adf::BoxWorld& b) { return {glm::min(a.min, b.min), glm::max(a.max, b.max)}; }

}  // namespace

/// The state of a live stroke (Sculptor::beginStroke): what it measures against and what it
/// has applied.
struct Sculptor::LiveStroke {
    Stroke stroke;                 ///< the header with every pose so far and the total dwell
    adf::AdfPtr start;             ///< the snapshot before the stroke (undo and cancel return to it)
    adf::SourcePtr startSource;    ///< its field: what following, smooth and flatten read
    ToolLimits limits;
    std::vector<ToolSample> path;  ///< resolved poses applied so far; back() is the next joint
    std::shared_ptr<const SweptTool> applied;  ///< swept along `path` (gradual tools); null before the first segment
    double appliedDwell = 0.0;     ///< s, the dwell the applied segments melted for
    std::array<std::optional<adf::BoxWorld>, 8> regions;  ///< per mirrored copy: the union of its segments' regions
    LiveRecord record;             ///< the segments so far, as replay repeats them (cuts, dwells)
    /// Records a call that was given samples or dwell. Calls before the first samples apply
    /// nothing and only add dwell: they are folded into the first segment, whose dwell is then
    /// the dwell so far (0 + that sum is that sum, so replay adds the same values).
    void recordSegment(std::size_t newSamples, double dwell, double dwellNow) {
        if (newSamples == 0 && !(dwell > 0.0)) return;
        if (record.cuts.empty() && stroke.samples.empty()) return;  // nothing applied yet: folded
        record.cuts.push_back(uint32_t(stroke.samples.size()));
        record.dwells.push_back(record.cuts.size() == 1 ? dwellNow : dwell);
    }
};

Sculptor::Sculptor(adf::AdfPtr start, util::ThreadPool* pool, std::size_t historyBytes)
    : mPool(pool), mCurrent(std::move(start)), mBudget(historyBytes) {
    if (!mCurrent) throw std::invalid_argument("sculptor needs a start snapshot");
}

Sculptor::~Sculptor() = default;

void Sculptor::requireNoLiveStroke(const char* what) const {
    if (mLive) throw std::logic_error(std::string(what) + " while a live stroke is open (endStroke or cancelStroke first)");
}

void Sculptor::beginStroke(const Stroke& header) {
    requireNoLiveStroke("beginStroke");
    if (header.bezier) throw std::invalid_argument("a live stroke is a polyline: its header cannot be a Bezier curve");
    Stroke check = header;
    if (check.samples.empty()) check.samples.push_back({});  // validate() wants a pose; the tool and constraints matter here
    validate(check);
    ToolLimits limits = limitsFor(header);
    // Following reads the field away from the surface; the path is not known yet, so every
    // pending zone is corrected now (apply() corrects those near its path).
    if (header.constraints.followOffset && mCorrecting) finishCorrections();
    auto live = std::make_unique<LiveStroke>();
    live->stroke = header;
    live->stroke.live.reset();
    live->stroke.samples.clear();
    live->stroke.dwell = 0.0;
    live->start = mCurrent;
    live->startSource = adf::makeAdfSource(mCurrent);
    live->limits = std::move(limits);
    mLive = std::move(live);
    if (header.samples.empty() && !(header.dwell > 0.0)) return;
    try {
        extendStroke(header.samples, header.dwell);
    } catch (...) {
        mLive.reset();
        throw;
    }
}

void Sculptor::extendStroke(std::span<const ToolSample> samples, double dwell) {
    if (!mLive) throw std::logic_error("extendStroke without a live stroke (beginStroke first)");
    LiveStroke& live = *mLive;
    const Tool& tool = live.stroke.tool;
    if (!std::isfinite(dwell) || dwell < 0.0) throw std::invalid_argument("a live stroke's dwell must be finite and >= 0 s");
    const auto t0 = std::chrono::steady_clock::now();
    // The segment starts at the joint: the last pose applied, so consecutive segments overlap there.
    std::vector<ToolSample> raw;
    if (!live.stroke.samples.empty()) raw.push_back(live.stroke.samples.back());
    raw.insert(raw.end(), samples.begin(), samples.end());
    if (!samples.empty()) validateStroke(tool, raw);
    const double dwellNow = live.stroke.dwell + dwell;
    const bool melts = tool.op == ToolOp::HeatGun && dwell > 0.0;
    if (raw.empty() || (samples.empty() && !melts)) {  // nothing new to sweep
        live.stroke.dwell = dwellNow;
        live.recordSegment(0, dwell, dwellNow);
        return;
    }
    const adf::Domain d = live.start->domain();
    const double h = d.finestCellSize();
    Stroke segment = live.stroke;
    segment.samples = std::move(raw);
    // Resolved against the start snapshot; the joint resolves to the previous segment's last pose.
    std::vector<ToolSample> segPath = resolvePath(segment, *live.start, 0.1 * h);
    std::vector<ToolSample> pathNow = live.path;
    pathNow.insert(pathNow.end(), segPath.begin() + (live.path.empty() ? 0 : 1), segPath.end());
    if (tool.op == ToolOp::Paint) {
        extendPaint(samples, segPath, std::move(pathNow), dwell, dwellNow, t0);
        return;
    }
    const auto segTool = makeSweptTool(tool, segPath);
    const bool csg = tool.op == ToolOp::Carve || tool.op == ToolOp::Add;
    const std::shared_ptr<const SweptTool> appliedNow = csg ? nullptr : makeSweptTool(tool, pathNow);
    // The heat gun's grown dwell melts the whole path so far.
    const adf::BoxWorld toolBox = melts && live.applied ? boxUnion(segTool->bounds(), live.applied->bounds()) : segTool->bounds();
    const glm::dvec3 centre = d.originWorld + glm::dvec3(0.5 * d.sizeWorld);
    adf::AdfPtr next = mCurrent;
    std::array<std::optional<adf::BoxWorld>, 8> regions = live.regions;
    std::size_t tiles = 0, evaluated = 0;
    for (uint8_t reflect = 0; reflect < 8; ++reflect) {
        if ((reflect & ~live.stroke.mirror) != 0) continue;
        const adf::BoxWorld region = strokeRegion(*next, mirroredBox(toolBox, reflect, centre));
        const adf::SourcePtr old = adf::makeAdfSource(next);
        adf::SourcePtr edited;
        if (csg) {
            edited = makeStrokeEdit(old, segTool, reflect, centre, 0.0, live.limits, h);
        } else {
            const bool heat = tool.op == ToolOp::HeatGun;
            LiveSegment seg{live.startSource, segTool, live.applied, heat ? tool.rate * live.appliedDwell : tool.amount,
                            heat ? tool.rate * dwellNow : tool.amount, pathNow.front()};
            edited = makeLiveSegmentEdit(old, std::move(seg), reflect, centre, live.limits, h);
        }
        adf::GenerationStats gs;
        next = adf::regenerate(*next, *adf::makeRegionLimited(old, edited, region), region, mPool, &gs);
        tiles += gs.tilesGenerated + gs.coarseTiles;
        evaluated += gs.samples;
        regions[reflect] = regions[reflect] ? boxUnion(*regions[reflect], region) : region;
    }
    // Nothing has changed the live state before this point: a throw above leaves it as it was.
    mCurrent = std::move(next);
    live.stroke.samples.insert(live.stroke.samples.end(), samples.begin(), samples.end());
    live.stroke.dwell = dwellNow;
    live.path = std::move(pathNow);
    live.applied = appliedNow;
    live.appliedDwell = dwellNow;
    live.regions = regions;
    live.recordSegment(samples.size(), dwell, dwellNow);
    mLast.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    mLast.tilesRebuilt = tiles;
    mLast.samples = evaluated;
    mLast.colourTilesPainted = 0;
    mLast.replacedBytes = 0;
}

void Sculptor::extendPaint(std::span<const ToolSample> samples, std::span<const ToolSample> segPath, std::vector<ToolSample> pathNow,
                            double dwell, double dwellNow, std::chrono::steady_clock::time_point t0) {
    LiveStroke& live = *mLive;
    PaintStats ps;
    adf::ColourLayerPtr colours = paintLiveSegment(*mCurrent, live.stroke, live.start->colours().get(), live.path, segPath, mPool, &ps);
    // Nothing has changed the live state before this point: a throw above leaves it as it was.
    if (colours != mCurrent->colours()) {  // only the colour layer changes: every distance tile is shared
        adf::AdfBuilder builder(*mCurrent);
        builder.setColours(std::move(colours));
        mCurrent = builder.build(mCurrent->version() + 1);
    }
    live.stroke.samples.insert(live.stroke.samples.end(), samples.begin(), samples.end());
    live.stroke.dwell = dwellNow;
    live.path = std::move(pathNow);
    live.recordSegment(samples.size(), dwell, dwellNow);
    mLast.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    mLast.tilesRebuilt = 0;
    mLast.samples = 0;
    mLast.colourTilesPainted = ps.slotsPainted;
    mLast.replacedBytes = 0;
}

Stroke Sculptor::endStroke() {
    if (!mLive) throw std::logic_error("endStroke without a live stroke (beginStroke first)");
    const auto t0 = std::chrono::steady_clock::now();
    const std::unique_ptr<LiveStroke> live = std::move(mLive);
    live->stroke.live = live->record;
    if (live->path.empty()) {  // nothing applied: no record
        mCurrent = live->start;
        return live->stroke;
    }
    adf::AdfPtr last = std::move(mCurrent);
    PendingList pending = mPending;
    std::size_t bytes = 0;
    for (const std::optional<adf::BoxWorld>& region : live->regions) {
        if (!region) continue;
        bytes += replacedBytes(*live->start, *last, *region);
        if (mCorrecting) pending = std::make_shared<const PendingZone>(PendingZone{correctionZone(*last, *region, mCorrection), pending});
    }
    // Paint: the colour tiles the stroke replaced, as apply() counts them; no correction is owed.
    const PaintStats painted = live->stroke.tool.op == ToolOp::Paint
                                   ? paintedBetween(live->start->colours().get(), last->colours().get())
                                   : PaintStats{};
    bytes += painted.replacedBytes;
    mCurrent = live->start;  // the undo record's snapshot
    mLast.colourTilesPainted = painted.slotsPainted;
    finish(std::move(last), bytes, std::move(pending), t0);
    return live->stroke;
}

Stroke Sculptor::liveStroke() const {
    if (!mLive) throw std::logic_error("liveStroke without a live stroke (beginStroke first)");
    Stroke out = mLive->stroke;
    out.live = mLive->record;
    return out;
}

bool Sculptor::liveChanged() const {
    if (!mLive) throw std::logic_error("liveChanged without a live stroke (beginStroke first)");
    return !mLive->path.empty();
}

void Sculptor::replayLive(const Stroke& stroke) {
    validate(stroke);  // before anything changes
    const LiveRecord& r = *stroke.live;
    const std::span<const ToolSample> all(stroke.samples);
    Stroke header = stroke;
    header.live.reset();
    header.samples.assign(all.begin(), all.begin() + r.cuts[0]);
    header.dwell = r.dwells[0];
    beginStroke(header);
    try {
        for (std::size_t i = 1; i < r.cuts.size(); ++i) extendStroke(all.subspan(r.cuts[i - 1], r.cuts[i] - r.cuts[i - 1]), r.dwells[i]);
    } catch (...) {
        cancelStroke();
        throw;
    }
    endStroke();
}

void Sculptor::cancelStroke() {
    if (!mLive) throw std::logic_error("cancelStroke without a live stroke (beginStroke first)");
    mCurrent = mLive->start;
    mLive.reset();
}

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
    requireNoLiveStroke("apply");
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
    requireNoLiveStroke("undo");
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
    requireNoLiveStroke("redo");
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
    requireNoLiveStroke("a correction");
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
    case Step::Kind::Stroke:
        if (step.stroke.live)
            replayLive(step.stroke);
        else
            apply(step.stroke);
        break;
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
