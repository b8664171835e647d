// SPDX-License-Identifier: Apache-2.0
/// @file proxy_renderer.cpp
/// @brief The god-object on a distance field: march, find the crossing, slide, settle, carve; then the
/// spring-damper, the scale, the soft start and the clamp.
///
/// Every loop here has a fixed bound (ProxyRenderer::kMarchSteps and friends), so a tick costs
/// at most a few hundred accessor samples and usually 2-10. Distances are the clay's distance
/// minus the contact level (toolRadius + offset): `gap` < 0 means the tool is in the material.
#include "haptics/proxy_renderer.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

namespace kizamu::haptics {

namespace {

/// m: a proxy this far inside the contact surface counts as inside (projection and the crossing
/// leave it within ~1e-8 m; the float query itself resolves ~4e-9 m at 5 cm from the origin).
constexpr double kInsideTolerance = 1e-6;
/// The fraction of the gap a sphere-tracing step takes: the ADF's gradient may exceed 1 a little.
constexpr double kTraceFactor = 0.9;
/// m: a crossing found this close to the contact surface is taken (0.1 µm, far below the ADF's
/// resolution and a device's).
constexpr double kCrossingTolerance = 1e-7;

bool isFinite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

double clamp01(double v) { return v > 0.0 ? (v < 1.0 ? v : 1.0) : 0.0; }  // NaN -> 0

}  // namespace

ProxyRenderer::ProxyRenderer(const DeviceSpec& spec, double period, const ProxySettings& settings) : mSettings(settings) {
    assert(period > 0.0 && std::isfinite(period) && "ProxyRenderer needs a positive, finite servo period");
    mSettings.forceScale = clamp01(settings.forceScale);
    mSettings.kineticFriction = std::max(0.0, settings.kineticFriction);
    mSettings.staticFriction = std::max(mSettings.kineticFriction, settings.staticFriction);
    mSettings.removalRate = std::max(0.0, settings.removalRate);
    mSettings.settleSpeed = std::max(0.0, settings.settleSpeed);
    const double b = std::max(0.0, spec.damping);
    mGains.damping = std::min(std::max(0.0, settings.damping), b);
    mGains.passiveBound = passiveStiffnessBound(b, mGains.damping, period);
    double k = settings.stiffness > 0.0 ? settings.stiffness : std::numeric_limits<double>::infinity();
    mGains.limitedBy = StiffnessLimit::Requested;
    if (kPassivitySafety * mGains.passiveBound < k) {
        k = kPassivitySafety * mGains.passiveBound;
        mGains.limitedBy = StiffnessLimit::Passivity;
    }
    if (spec.maxStiffness > 0.0 && spec.maxStiffness < k) {
        k = spec.maxStiffness;
        mGains.limitedBy = StiffnessLimit::DeviceMaximum;
    }
    mGains.stiffness = k;
    const double deviceMax = std::max(0.0, spec.maxForce);
    mGains.maxForce = settings.maxForce > 0.0 ? std::min(settings.maxForce, deviceMax) : deviceMax;
}

void ProxyRenderer::reset() noexcept {
    mHasProxy = false;
    mContact = mSticking = mSettling = false;
    mProxyVelocity = glm::dvec3(0.0);
    mWaiting = true;
    mRamp = 0.0;
}

void ProxyRenderer::setForceScale(double scale) noexcept { mSettings.forceScale = clamp01(scale); }

void ProxyRenderer::setEnabled(bool on) noexcept {
    if (on && !mSettings.enabled) {
        mWaiting = true;
        mRamp = 0.0;
    }
    mSettings.enabled = on;
}

void ProxyRenderer::setStiffnessUnchecked(double stiffness) noexcept {
    mGains.stiffness = std::max(0.0, stiffness);
    mGains.limitedBy = StiffnessLimit::Unchecked;
}

double ProxyRenderer::gap(adf::AdfAccessor& clay, const glm::dvec3& p, glm::dvec3* normal) const noexcept {
    const adf::Sample s = clay.sample(glm::vec3(p));
    if (normal) {
        const glm::dvec3 g(s.gradient);
        const double len = glm::length(g);
        *normal = len > 1e-12 && std::isfinite(len) ? g / len : glm::dvec3(0.0);
    }
    const double d = double(s.distance) - level();
    return std::isfinite(d) ? d : 1.0;  // an unusable sample counts as free space (1 m)
}

double ProxyRenderer::freeFraction(adf::AdfAccessor& clay, const glm::dvec3& from, const glm::dvec3& to) const noexcept {
    const glm::dvec3 seg = to - from;
    const double len = glm::length(seg);
    double g = gap(clay, from);
    if (g < -kInsideTolerance) return 0.0;
    if (!(len > 0.0)) return 1.0;
    // Sphere tracing with a floor of len / kMarchSteps per step, so the end is reached within
    // kMarchSteps steps; the floor can step over material thinner than len / kMarchSteps (31 µm
    // for a 1 mm tick), far below what a level-12 ADF resolves in a 10 cm domain (24 µm cells).
    const double minStep = 1.0 / double(kMarchSteps);
    double t = 0.0;
    for (int i = 0; i < kMarchSteps; ++i) {
        const double next = std::min(1.0, t + std::max(kTraceFactor * g / len, minStep));
        const double gNext = gap(clay, from + seg * next);
        if (gNext < 0.0) {
            // The crossing lies in (t, next]: regula falsi on the gap with the Illinois rule (the
            // end that stays halves its weight), so it converges in a few queries where
            // bisection takes kBisectSteps; what it returns is a free parameter (or one
            // within kCrossingTolerance of the surface).
            double lo = t, hi = next, gLo = g, gHi = gNext;
            int side = 0;
            for (int k = 0; k < kBisectSteps; ++k) {
                double mid = (gLo - gHi) > 0.0 ? lo + (hi - lo) * (gLo / (gLo - gHi)) : 0.5 * (lo + hi);
                if (!(mid > lo && mid < hi)) mid = 0.5 * (lo + hi);
                const double gMid = gap(clay, from + seg * mid);
                if (std::abs(gMid) < kCrossingTolerance) return mid;
                if (gMid > 0.0) {
                    lo = mid;
                    gLo = gMid;
                    if (side == 1) gHi *= 0.5;
                    side = 1;
                } else {
                    hi = mid;
                    gHi = gMid;
                    if (side == -1) gLo *= 0.5;
                    side = -1;
                }
                if ((hi - lo) * len < kCrossingTolerance) break;
            }
            return lo;
        }
        if (next >= 1.0) return 1.0;
        t = next;
        g = gNext;
    }
    return t;
}

glm::dvec3 ProxyRenderer::project(adf::AdfAccessor& clay, glm::dvec3 p) const noexcept {
    for (int k = 0; k < kProjectSteps; ++k) {
        glm::dvec3 n;
        const double g = gap(clay, p, &n);
        if (std::abs(g) < 0.1 * kInsideTolerance || n == glm::dvec3(0.0)) break;
        p -= g * n;
    }
    return p;
}

glm::dvec3 ProxyRenderer::constrainedMove(adf::AdfAccessor& clay, const glm::dvec3& from, const glm::dvec3& target,
                                          bool& contact) noexcept {
    glm::dvec3 p = from;
    contact = false;
    bool slid = false;
    for (int it = 0; it < kSlideIterations; ++it) {
        const double t = freeFraction(clay, p, target);
        if (t >= 1.0) {  // the rest of the way is free
            contact = false;
            mSticking = false;
            return target;
        }
        p += (target - p) * t;
        contact = true;
        glm::dvec3 n;
        gap(clay, p, &n);
        if (n == glm::dvec3(0.0)) break;
        // How far the device is behind the tangent plane at the proxy; not behind it (a groove's
        // other wall stopped the path): the proxy stays where the path stopped.
        const double depth = glm::dot(p - target, n);
        if (depth <= 0.0) break;
        // Coulomb: the spring's tangential part K|e| against mu times its normal part K depth.
        const glm::dvec3 e = (target + depth * n) - p;
        const double el = glm::length(e);
        const double mu = mSticking && !slid ? mSettings.staticFriction : mSettings.kineticFriction;
        const double cone = mu * depth;
        if (el <= cone || el < 1e-12) break;  // held inside the friction cone
        slid = true;
        const glm::dvec3 q = project(clay, p + e * ((el - cone) / el));
        if (!isFinite(q) || gap(clay, q) < -kInsideTolerance) break;  // no surface point there: stay
        p = q;
    }
    mSticking = contact && !slid;
    return p;
}

glm::dvec3 ProxyRenderer::carveMove(adf::AdfAccessor& clay, const glm::dvec3& from, const glm::dvec3& target,
                                    double budget, bool& contact) const noexcept {
    // Free space up to the first contact at any speed, then into the material at most `budget`.
    glm::dvec3 p = from;
    const double t = freeFraction(clay, p, target);
    if (t >= 1.0) {
        contact = false;
        return target;
    }
    p += (target - p) * t;
    const glm::dvec3 rest = target - p;
    const double len = glm::length(rest);
    contact = len > budget;
    return len > budget ? p + rest * (budget / len) : target;
}

bool ProxyRenderer::settle(adf::AdfAccessor& clay, const glm::dvec3& target, double step, bool& contact) noexcept {
    glm::dvec3 n;
    const double g = gap(clay, mProxy, &n);
    if (g < -kInsideTolerance) {
        // Inside a surface that moved out over the proxy: back out along the gradient.
        contact = true;
        mSticking = false;
        if (n == glm::dvec3(0.0)) n = glm::dvec3(0.0, 0.0, 1.0);
        mProxy += n * std::min(-g, step);
        return true;
    }
    // Outside: where the god-object would go, but the proxy may close in on the device by at most
    // `step` more than the device itself moved away from it this tick (so a surface that fell
    // away releases the spring gradually, and a hand pulling away is never held back).
    bool c = false;
    const glm::dvec3 want = constrainedMove(clay, mProxy, target, c);
    const glm::dvec3 u = target - mProxy;
    const double ul = glm::length(u);
    if (ul > 0.0) {
        const glm::dvec3 dir = u / ul;
        const double advance = glm::dot(want - mProxy, dir);
        const double allowed = step + std::max(0.0, glm::dot(target - mLastDevice, dir));
        if (advance > allowed) {
            mProxy += (want - mProxy) * (allowed / advance);
            contact = true;
            mSticking = false;
            return true;
        }
    }
    mProxy = want;
    contact = c;
    return false;
}

ProxyOutput ProxyRenderer::hold(bool fault) noexcept {
    mWaiting = true;
    mRamp = 0.0;
    mProxyVelocity = glm::dvec3(0.0);
    ProxyOutput out;
    out.proxy = mProxy;
    out.fault = fault;
    return out;
}

ProxyOutput ProxyRenderer::update(const DeviceState& device, adf::AdfAccessor& clay, uint64_t clayId, double dt,
                                  bool carving) noexcept {
    if (!(dt > 0.0 && std::isfinite(dt)) || !isFinite(device.position) || !isFinite(device.velocity)) return hold(true);
    if (!device.connected) return hold(false);
    const glm::dvec3 x = device.position;
    if (!mHasProxy) {
        mProxy = mLastDevice = x;
        mHasProxy = true;
        mClayId = clayId;
        mContact = mSticking = mSettling = false;
    }
    if (clayId != mClayId) {
        mClayId = clayId;
        mSettling = true;  // the surface may have moved under the proxy
    }
    const glm::dvec3 before = mProxy;
    bool contact = false;
    if (carving) {
        mSettling = mSticking = false;
        mProxy = carveMove(clay, mProxy, x, mSettings.removalRate * dt, contact);
    } else {
        if (!mSettling && gap(clay, mProxy) < -kInsideTolerance) mSettling = true;  // left inside by a carve
        if (mSettling) mSettling = settle(clay, x, mSettings.settleSpeed * dt, contact);
        else mProxy = constrainedMove(clay, mProxy, x, contact);
    }
    if (!isFinite(mProxy)) {  // cannot happen with finite inputs; never let it reach the force
        mProxy = x;
        contact = false;
    }
    mProxyVelocity = (mProxy - before) / dt;
    mContact = contact;
    mLastDevice = x;

    glm::dvec3 f(0.0);
    if (contact) f = mGains.stiffness * (mProxy - x) + mGains.damping * (mProxyVelocity - device.velocity);
    f *= mSettings.forceScale;
    if (!mSettings.enabled) {
        mWaiting = true;
        mRamp = 0.0;
        f = glm::dvec3(0.0);
    } else {
        // Soft start: nothing until the force would be small, then a linear ramp to full.
        if (mWaiting && glm::length(f) < mSettings.softStartForce) {
            mWaiting = false;
            mRamp = 0.0;
        }
        if (mWaiting) {
            f = glm::dvec3(0.0);
        } else {
            mRamp = mSettings.softStartTime > 0.0 ? std::min(1.0, mRamp + dt / mSettings.softStartTime) : 1.0;
            f *= mRamp;
        }
    }
    const double mag = glm::length(f);
    if (!std::isfinite(mag)) f = glm::dvec3(0.0);
    else if (mag > mGains.maxForce) f *= mGains.maxForce / mag * (1.0 - 4.0 * std::numeric_limits<double>::epsilon());

    ProxyOutput out;
    out.force = f;
    out.proxy = mProxy;
    out.contact = contact;
    out.settling = mSettling;
    return out;
}

}  // namespace kizamu::haptics
