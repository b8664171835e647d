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
/// Owned by the edit thread; not thread-safe.
#pragma once

#include "adf/adf.h"
#include "sculpt/stroke_script.h"

#include <chrono>
#include <cstddef>
#include <deque>

namespace kizamu::util {
class ThreadPool;
}

namespace kizamu::sculpt {

struct EditStats {
    double ms = 0.0;                 ///< wall time of the last stroke's regeneration
    std::size_t tilesRebuilt = 0;    ///< tiles that stroke rebuilt
    std::size_t colourTilesPainted = 0;  ///< colour tiles a paint stroke rewrote
    std::size_t replacedBytes = 0;   ///< bytes of the tiles (distance or colour) it replaced (its undo record)
};

class Sculptor {
public:
    /// @param historyBytes  budget of replaced tiles kept for undo
    explicit Sculptor(adf::AdfPtr start, util::ThreadPool* pool = nullptr, std::size_t historyBytes = std::size_t(1) << 30);

    /// Applies one stroke; drops any redo records. @throw std::invalid_argument for a bad stroke.
    void apply(const Stroke& stroke);
    /// Steps back one stroke; false when there is nothing to undo. Complexity: O(1).
    bool undo();
    /// Re-applies the last undone stroke; false when there is none. Complexity: O(1).
    bool redo();
    /// A script step: apply, undo or redo.
    void replay(const Step& step);

    const adf::AdfPtr& current() const { return mCurrent; }
    std::size_t undoDepth() const { return mUndo.size(); }
    std::size_t redoDepth() const { return mRedo.size(); }
    const EditStats& lastEdit() const { return mLast; }
    std::size_t historyBytes() const { return mHistoryBytes; }

private:
    /// Makes `next` current with an undo record of `replacedBytes`.
    void finish(adf::AdfPtr next, std::size_t replacedBytes, std::chrono::steady_clock::time_point t0);

    struct Record {
        adf::AdfPtr snapshot;
        std::size_t bytes;
    };
    util::ThreadPool* mPool;
    adf::AdfPtr mCurrent;
    std::deque<Record> mUndo;
    std::deque<Record> mRedo;
    std::size_t mBudget, mHistoryBytes = 0;
    EditStats mLast;
};

/// The snapshot a script starts from, at `level` (0: the script's own level).
adf::AdfPtr startAdf(const Script& script, int level, util::ThreadPool* pool = nullptr);

/// The region a stroke regenerates: its swept box plus the band and two finest cells, clipped
/// to the domain.
adf::BoxWorld strokeRegion(const adf::Adf& adf, const adf::BoxWorld& swept);

}  // namespace kizamu::sculpt
