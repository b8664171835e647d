// SPDX-License-Identifier: Apache-2.0
/// @file sculptor.h
/// @brief Applies strokes to the clay as local CSG edits, with undo and redo.
///
/// Each stroke is the swept tool (swept_tool.h) subtracted from or added to the old field
/// (`makeAdfSource` of the current snapshot, min/max CSG), limited to the box around the swept
/// volume plus the accurate band, and regenerated there (`regenerate`): only the tiles the
/// stroke touches are rebuilt, everything else is shared. The surface moves continuously with
/// the tool because the CSG of two continuous fields is continuous (no popping). A paint stroke
/// (paint.h) changes only the colour layer: the new snapshot shares every distance tile, and
/// later strokes keep the paint (regeneration carries the layer along).
///
/// Undo history: the snapshot before each stroke. Snapshots share untouched tiles, so a record
/// costs the tiles the stroke replaced, and undo/redo are a pointer swap. The history keeps at
/// most `historyBytes` of such tiles, dropping the oldest records first.
///
/// Live strokes (beginStroke, extendStroke, endStroke, cancelStroke): while the button is held,
/// each extendStroke applies the segment of the path since the last applied pose and publishes
/// the result as current(); endStroke makes the whole stroke one undo record and one correction
/// zone, cancelStroke restores the start. endStroke returns the stroke with its live record
/// (Stroke::live: where the segments were cut and their dwells), and replay() of that record
/// repeats the same calls, so a journal reaches the live result bit for bit. Everything the
/// stroke measures against (surface following, depth and height limits, flatten's plane,
/// smooth's mean) reads the snapshot from the stroke's start. A stroke applied live in any number of segments equals apply() of the
/// whole stroke within the error bound plus one quantisation step (tested):
/// - carve, add: min/max of the previous segment's result with the segment's swept tool; min and
///   max are associative and the segments' volumes (each including the joint) make up the whole.
/// - build, smooth, flatten: a segment applies only the growth of the stroke's running maximum
///   weight (LiveSegment, stroke_edit.h); each is linear in the weight, the rest read from the
///   start snapshot.
/// - heat gun: the dwell comes with the samples (extendStroke's `dwell`, s); a segment applies
///   rate x (dwell so far x W so far) less what was applied, over the whole path when the dwell grew.
/// - paint: a point's colour is its start colour blended by each mirrored copy's weight in
///   turn, and a path's weight is the maximum of its pieces'; a segment rewrites only the points
///   where some copy's running maximum weight grows, blending from the start colour with the
///   weights so far (paintLiveSegment, paint.h). Bit for bit for a sphere on a free path,
///   mirrored or not (the pieces' distances are the same closed-form capsules); other shapes
///   within one 8-bit step per channel (their searched distance at a joint may round
///   differently). One undo record of the colour tiles replaced, no correction zone, every
///   distance tile shared, as apply().
/// Mirrored live strokes of the gradual tools read the start snapshot in every copy, where
/// apply() lets a copy read the one before it: they differ only where copies overlap.
/// Owned by the edit thread; not thread-safe.
#pragma once

#include "adf/adf.h"
#include "sculpt/remote_field.h"
#include "sculpt/stroke.h"

#include <chrono>
#include <cstddef>
#include <deque>
#include <memory>
#include <span>

namespace kizamu::util {
class ThreadPool;
}

namespace kizamu::sculpt {

struct ToolLimits;

struct EditStats {
    double ms = 0.0;                 ///< wall time of the last stroke's regeneration
    std::size_t tilesRebuilt = 0;    ///< tiles that stroke rebuilt
    std::size_t samples = 0;         ///< distances it evaluated
    std::size_t colourTilesPainted = 0;  ///< colour tiles a paint stroke rewrote
    std::size_t replacedBytes = 0;   ///< bytes of the tiles (distance or colour) it replaced (its undo record)
};

class Sculptor {
public:
    /// @param historyBytes  budget of replaced tiles kept for undo
    explicit Sculptor(adf::AdfPtr start, util::ThreadPool* pool = nullptr, std::size_t historyBytes = std::size_t(1) << 30);
    ~Sculptor();

    /// The original surface that depth and height limits (Kizamu 4.4) measure from; a stroke
    /// with such a limit throws std::invalid_argument while none is set. Usually the script's
    /// start shape: analytic, so the limit means the same at every level.
    void setReference(adf::SourcePtr reference) { mReference = std::move(reference); }

    /// Applies one stroke; drops any redo records. @throw std::invalid_argument for a bad stroke.
    void apply(const Stroke& stroke);
    /// Steps back one stroke; false when there is nothing to undo. Complexity: O(1).
    bool undo();
    /// Re-applies the last undone stroke; false when there is none. Complexity: O(1).
    bool redo();
    /// Opens a live stroke: `header` gives the tool, the constraints, the mirror mask, and any
    /// first poses and dwell (applied at once, as extendStroke would). A stroke that follows the
    /// surface first completes every pending correction (its path is not known yet). Undo, redo,
    /// apply and corrections throw std::logic_error until the stroke ends or is cancelled.
    /// @throw std::invalid_argument for a bad tool or constraints, or a Bezier header;
    ///        std::logic_error while a stroke is open.
    /// Complexity: O(1) plus what the first poses cost. Threading: the edit thread.
    void beginStroke(const Stroke& header);
    /// Applies the swept tool from the last applied pose (the joint, so segments leave no gap)
    /// through `samples`, and `dwell` (s, the heat gun's time since the last call; ignored by
    /// the other tools), and makes the result current(). Empty `samples` with a dwell melts
    /// the path so far further.
    /// @throw std::logic_error without an open stroke; std::invalid_argument for bad samples or
    ///        dwell (nothing changes).
    /// Complexity: one regeneration of the segment's region (the heat gun: the path's, when the
    /// dwell grew; paint: no regeneration, the colour tiles the segment reaches); the poses so
    /// far are kept, O(poses) memory.
    void extendStroke(std::span<const ToolSample> samples, double dwell = 0.0);
    /// Ends the live stroke: one undo record (undo returns the snapshot before beginStroke, redo
    /// this one), one pending correction zone per mirrored copy (the union of its segments'
    /// regions; paint: none, and the record counts the colour tiles replaced, as apply()), redo
    /// records dropped. A stroke that applied nothing leaves no record.
    /// @return the whole stroke (header, every pose, the total dwell) with its live record (the
    ///         cuts and dwells of every beginStroke and extendStroke call given samples or dwell;
    ///         no time stamps or strengths): what a journal records. replay() of it reproduces
    ///         the live result bit for bit; apply() of it, within the bound above.
    /// @throw std::logic_error without an open stroke.
    /// Complexity: O(tiles in the stroke's regions), counting the replaced bytes; no regeneration.
    Stroke endStroke();
    /// Drops the live stroke: current() is the snapshot before beginStroke again; no record.
    /// @throw std::logic_error without an open stroke. Complexity: O(1).
    void cancelStroke();
    /// Whether a live stroke is open.
    bool stroking() const { return mLive != nullptr; }
    /// The open live stroke so far, as endStroke would return it (so a journal can be written
    /// before endStroke commits). Its live record is empty while nothing has been applied.
    /// @throw std::logic_error without an open stroke. Complexity: O(poses) (a copy).
    Stroke liveStroke() const;
    /// Whether the open live stroke applied anything (endStroke would leave an undo record).
    /// @throw std::logic_error without an open stroke. Complexity: O(1).
    bool liveChanged() const;

    /// A script step: apply, undo, redo or correct. A stroke with a live record is applied as
    /// it was live: beginStroke with samples [0, cuts[0]) and dwells[0], extendStroke with each
    /// later segment and its dwell, endStroke (bit for bit what the live calls made).
    /// @throw std::invalid_argument for a bad stroke (nothing changes); std::logic_error while
    ///        a live stroke is open.
    void replay(const Step& step);

    /// Remote-field correction (Kizamu 5.4, remote_field.h). A stroke leaves its zone pending;
    /// a stroke that follows the surface first corrects the pending zones around its path (on
    /// demand near the tool); the rest wait for idle time. Pending zones are part of the undo
    /// state, so the field after every pending correction completes depends only on the steps.
    void setCorrection(const CorrectionSettings& settings, bool enabled = true);
    /// Corrects the pending zones that intersect `box` (m): what the haptic thread is near.
    void correctNear(const adf::BoxWorld& box);
    /// Idle time: corrects the oldest pending zone; false when none is pending.
    bool correctOne();
    /// Corrects every pending zone (merged where that is cheaper).
    void finishCorrections();
    /// The current field with every pending correction made, leaving this sculptor unchanged
    /// (what a read-only export shows).
    adf::AdfPtr settled() const;
    /// The pending zones, oldest first. Complexity: O(zones).
    std::vector<adf::BoxWorld> pendingCorrections() const;

    const adf::AdfPtr& current() const { return mCurrent; }
    std::size_t undoDepth() const { return mUndo.size(); }
    std::size_t redoDepth() const { return mRedo.size(); }
    const EditStats& lastEdit() const { return mLast; }
    std::size_t historyBytes() const { return mHistoryBytes; }

private:
    /// Pending zones as an immutable list, newest first: a stroke adds one node and shares the
    /// rest, so undo records holding the list cost O(1) each, not O(zones).
    struct PendingZone {
        adf::BoxWorld zone;
        std::shared_ptr<const PendingZone> older;
    };
    using PendingList = std::shared_ptr<const PendingZone>;
    static std::vector<adf::BoxWorld> oldestFirst(const PendingList& list);
    static PendingList listOf(const std::vector<adf::BoxWorld>& oldestFirst);

    ToolLimits limitsFor(const Stroke& stroke) const;
    /// replay() of a stroke with a live record.
    void replayLive(const Stroke& stroke);
    /// @throw std::logic_error naming `what` while a live stroke is open.
    void requireNoLiveStroke(const char* what) const;
    struct LiveStroke;
    /// extendStroke for paint: `segPath` resolved from the joint, `pathNow` the path after it.
    void extendPaint(std::span<const ToolSample> samples, std::span<const ToolSample> segPath, std::vector<ToolSample> pathNow,
                     double dwell, double dwellNow, std::chrono::steady_clock::time_point t0);
    /// Makes `next` current, with `pending` corrections, and an undo record of `replacedBytes`.
    void finish(adf::AdfPtr next, std::size_t replacedBytes, PendingList pending, std::chrono::steady_clock::time_point t0);

    struct Record {
        adf::AdfPtr snapshot;
        std::size_t bytes;
        PendingList pending;  ///< corrections still owed by that snapshot
    };
    /// Corrects `zones`, then makes `remaining` the pending list (nothing changes on a throw).
    void correct(std::vector<adf::BoxWorld> zones, std::vector<adf::BoxWorld> remaining);
    util::ThreadPool* mPool;
    adf::AdfPtr mCurrent;
    adf::SourcePtr mReference;
    CorrectionSettings mCorrection;
    bool mCorrecting = true;
    PendingList mPending;
    std::deque<Record> mUndo;
    std::deque<Record> mRedo;
    std::size_t mBudget, mHistoryBytes = 0;
    EditStats mLast;
    std::unique_ptr<LiveStroke> mLive;
};

/// The region a stroke regenerates: its swept box plus the band and two finest cells, clipped
/// to the domain.
adf::BoxWorld strokeRegion(const adf::Adf& adf, const adf::BoxWorld& swept);

}  // namespace kizamu::sculpt
