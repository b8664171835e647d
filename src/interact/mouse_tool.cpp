// SPDX-License-Identifier: Apache-2.0
/// @file mouse_tool.cpp
/// @brief MouseTool: ray, stabiliser, depth and modifiers into the tool's target and stroke.
#include "interact/mouse_tool.h"

#include <glm/geometric.hpp>

#include <algorithm>

namespace kizamu::interact {

MouseTool::MouseTool(const MouseToolSettings& settings) : mSettings(settings) {}

void MouseTool::setDepth(double radii) noexcept { mDepth = std::clamp(radii, mSettings.minDepth, mSettings.maxDepth); }

sculpt::ToolOp MouseTool::strokeOp(sculpt::ToolOp selected, bool ctrl, bool shift) noexcept {
    using sculpt::ToolOp;
    if (shift) return ToolOp::Smooth;
    if (!ctrl) return selected;
    switch (selected) {
    case ToolOp::Carve: return ToolOp::Add;
    case ToolOp::Add: return ToolOp::Carve;
    case ToolOp::Build: return ToolOp::HeatGun;
    case ToolOp::HeatGun: return ToolOp::Build;
    default: return selected;  // smooth, flatten and paint have no opposite
    }
}

MouseToolFrame MouseTool::update(const MouseInput& in, adf::AdfAccessor& clay, const adf::Domain& domain) noexcept {
    if (in.wheel != 0.0) setDepth(mDepth + in.wheel * mSettings.depthStep);
    MouseToolFrame f;
    f.pressure = in.pressure;
    std::optional<RayHit> hit;
    if (in.hasRay) hit = traceRay(clay, domain, in.rayOrigin, in.rayDirection);

    // Press only on the clay; release wherever the cursor is.
    const bool wasStroking = mStroking;
    if (!mStroking && in.primary && hit) {
        mStroking = true;
        mStrokeOp = strokeOp(mTool.op, in.ctrl, in.shift);
        mStrokeOffset = mDepth * mTool.radius;
        mLazy.reset();
        f.strokeBegan = true;
    } else if (mStroking && !in.primary) {
        mStroking = false;
        f.strokeEnded = true;
    }
    f.stroking = mStroking;
    f.op = mStroking || f.strokeEnded ? mStrokeOp : strokeOp(mTool.op, in.ctrl, in.shift);
    f.followOffset = mStroking || f.strokeEnded ? mStrokeOffset : mDepth * mTool.radius;

    if (!hit) {
        // Off the clay: a held stroke stays where it was (the release, or the cursor's return,
        // continues it); with no stroke there is no target.
        f.hasTarget = wasStroking || mStroking;
        f.target = mLastTarget;
        f.normal = mLastNormal;
        return f;
    }
    glm::dvec3 surface = hit->point;
    if (mStroking && mSettings.lazyRadius > 0.0) {
        if (!mLazy) mLazy = surface;
        const glm::dvec3 pull = surface - *mLazy;
        const double len = glm::length(pull);
        if (len > mSettings.lazyRadius) *mLazy += pull * (1.0 - mSettings.lazyRadius / len);
        surface = *mLazy;
    }
    f.hasTarget = true;
    f.normal = hit->normal;
    f.target = surface + hit->normal * f.followOffset;
    mLastTarget = f.target;
    mLastNormal = f.normal;
    return f;
}

}  // namespace kizamu::interact
