// SPDX-License-Identifier: Apache-2.0
/// @file clay_grab.h
/// @brief Holding the clay with the hands: one hand moves and turns it as if held; two hands
/// move it with their midpoint, turn it with the line between them and scale it with their
/// distance, as in every VR sculpting tool.
///
/// The grab is relative: each time the set of holding hands changes, the placement and the hands'
/// poses are taken as the new reference, so letting go with one hand or taking hold with the
/// other never makes the clay jump. Pure; owned by one thread.
#pragma once

#include "xr/pose.h"

#include <array>
#include <optional>

namespace kizamu::xr {

class ClayGrab {
public:
    /// Scale stays within [minScale, maxScale] of real size.
    explicit ClayGrab(double minScale = 0.05, double maxScale = 20.0) : mMinScale(minScale), mMaxScale(maxScale) {}

    /// The clay's placement after this frame: `hands[i]` is hand i's grip while it holds the
    /// clay, nothing while it does not; `placement` is the clay's placement now.
    Similarity update(const std::array<std::optional<Pose>, 2>& hands, const Similarity& placement);
    bool holding() const { return mHeld[0] || mHeld[1]; }

private:
    std::array<bool, 2> mHeld{};
    std::array<Pose, 2> mStartHands{};
    Similarity mStartPlacement;
    double mMinScale, mMaxScale;
};

}  // namespace kizamu::xr
