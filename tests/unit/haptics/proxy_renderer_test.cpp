// SPDX-License-Identifier: Apache-2.0
// The proxy renderer (haptics/proxy_renderer.h) with the simulated stylus in lock step at 1 kHz
// on small clay: the stiffness it chooses; pressing into a sphere, onto a box edge and into a
// carved groove keeps the device's penetration within what the wall's stiffness allows; sliding
// follows the surface, with and without friction; forces are finite and within the maximum
// whatever the input; soft start, force scale and the off switch.
#include "haptics/proxy_renderer.h"
#include "tests/unit/haptics/lockstep.h"

#include "sculpt/sculptor.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace kizamu {
namespace {

using haptics::ProxyRenderer;
using haptics::ProxySettings;
using haptics::StiffnessLimit;
using test::kPeriod;
using test::Rig;

TEST(ProxyRenderer, ClampsTheStiffnessToThePassivityBoundAndTheDevice) {
    const sim::SimulatedStylus stylus{sim::Hand{}};
    const haptics::DeviceSpec& spec = stylus.spec();  // b = 2 N·s/m, 1 kHz: bound 4000 N/m
    ASSERT_DOUBLE_EQ(haptics::passiveStiffnessBound(spec.damping, 0.0, kPeriod), 4000.0);
    ProxySettings s;
    const ProxyRenderer unlimited(spec, kPeriod, s);
    EXPECT_DOUBLE_EQ(unlimited.gains().passiveBound, 4000.0);
    EXPECT_DOUBLE_EQ(unlimited.gains().stiffness, ProxyRenderer::kPassivitySafety * 4000.0);
    EXPECT_EQ(unlimited.gains().limitedBy, StiffnessLimit::Passivity);
    EXPECT_DOUBLE_EQ(unlimited.maxForce(), spec.maxForce);
    s.stiffness = 1000.0;
    EXPECT_DOUBLE_EQ(ProxyRenderer(spec, kPeriod, s).gains().stiffness, 1000.0);
    EXPECT_EQ(ProxyRenderer(spec, kPeriod, s).gains().limitedBy, StiffnessLimit::Requested);
    // Virtual damping spends the bound: b > K T / 2 + |B|.
    s.stiffness = 1e6;
    s.damping = 0.5;
    const ProxyRenderer damped(spec, kPeriod, s);
    EXPECT_DOUBLE_EQ(damped.gains().passiveBound, 3000.0);
    EXPECT_DOUBLE_EQ(damped.gains().stiffness, ProxyRenderer::kPassivitySafety * 3000.0);
    s.damping = 5.0;  // more than the device has: clamped to b, which leaves no stiffness
    EXPECT_DOUBLE_EQ(ProxyRenderer(spec, kPeriod, s).gains().damping, spec.damping);
    EXPECT_DOUBLE_EQ(ProxyRenderer(spec, kPeriod, s).gains().stiffness, 0.0);
    // A device that states a lower maximum; a slower servo loop.
    haptics::DeviceSpec stiff = spec;
    stiff.maxStiffness = 1500.0;
    s.damping = 0.0;
    EXPECT_EQ(ProxyRenderer(stiff, kPeriod, s).gains().limitedBy, StiffnessLimit::DeviceMaximum);
    EXPECT_DOUBLE_EQ(ProxyRenderer(stiff, kPeriod, s).gains().stiffness, 1500.0);
    EXPECT_DOUBLE_EQ(ProxyRenderer(spec, 2e-3, s).gains().stiffness, ProxyRenderer::kPassivitySafety * 2000.0);
    // The force limit: the smaller of the asked and the device's.
    s.maxForce = 3.0;
    EXPECT_DOUBLE_EQ(ProxyRenderer(spec, kPeriod, s).maxForce(), 3.0);
    s.maxForce = 30.0;
    EXPECT_DOUBLE_EQ(ProxyRenderer(spec, kPeriod, s).maxForce(), spec.maxForce);
    // Tests only: past the bound.
    ProxyRenderer unchecked(spec, kPeriod, {});
    unchecked.setStiffnessUnchecked(6000.0);
    EXPECT_DOUBLE_EQ(unchecked.gains().stiffness, 6000.0);
    EXPECT_EQ(unchecked.gains().limitedBy, StiffnessLimit::Unchecked);
}

/// What a wall of stiffness K lets a hand of stiffness K_h aimed `aim` past it push the device
/// in: the static part K_h aim / K, the impact's overshoot v sqrt(m / K) at the hand's speed v,
/// and the ADF's error at the surface.
double penetrationBound(const Rig& rig, double aim, double speed) {
    const double k = rig.renderer.gains().stiffness;
    const sim::StylusSettings& s = rig.stylus.settings();
    return s.handStiffness * aim / k + speed * std::sqrt(s.mass / k) + test::surfaceError(*rig.clay);
}

/// Runs `rig` to the end of its hand; returns the deepest penetration `depth(device)` reports,
/// and checks every force on the way (finite, within the maximum) and that the proxy stays on or
/// outside the contact surface (`depth(proxy)` <= `errors` x the ADF's error bound).
template <class Depth>
double runPress(Rig& rig, Depth depth, int* contactTicks = nullptr, double errors = 1.0) {
    const double eps = errors * test::surfaceError(*rig.clay);
    const int ticks = int(std::lround(rig.stylus.hand().duration() / kPeriod)) + 50;
    double deepest = 0.0;
    int contacts = 0;
    for (int i = 0; i < ticks; ++i) {
        const haptics::ProxyOutput& out = rig.tick();
        EXPECT_TRUE(std::isfinite(glm::length(out.force)));
        EXPECT_LE(glm::length(out.force), rig.renderer.maxForce());
        EXPECT_LE(depth(out.proxy), eps + 1e-5) << "the proxy went into the clay at tick " << i;
        deepest = std::max(deepest, depth(rig.stylus.position()));
        contacts += out.contact ? 1 : 0;
    }
    EXPECT_FALSE(rig.last.contact) << "the hand went back to free space";
    EXPECT_EQ(rig.last.force, glm::dvec3(0.0));
    if (contactTicks) *contactTicks = contacts;
    return deepest;
}

TEST(ProxyRenderer, PressingIntoASphereKeepsThePenetrationWithinTheWallsStiffness) {
    ProxySettings ps;
    ps.toolRadius = 0.003;  // the tool's shape counts: it touches where the distance is 3 mm
    const double contact = test::kSphereRadius + ps.toolRadius;
    const double aim = 0.005, travel = 0.045 - (contact - aim);
    Rig rig(test::pressHand({0, 0, 0.045}, {0, 0, contact - aim}), test::sphereClay(), ps);
    int contacts = 0;
    const double deepest = runPress(rig, [&](const glm::dvec3& p) { return contact - glm::length(p); }, &contacts);
    const double bound = penetrationBound(rig, aim, travel / 0.2);
    std::printf("[ sphere ] K %.0f N/m: deepest penetration %.3f mm, bound %.3f mm, %d contact ticks\n",
                rig.renderer.gains().stiffness, deepest * 1e3, bound * 1e3, contacts);
    EXPECT_LE(deepest, bound);
    EXPECT_GT(deepest, 0.5 * rig.stylus.settings().handStiffness * aim / rig.renderer.gains().stiffness) << "it did press";
    EXPECT_GT(contacts, 300);
}

TEST(ProxyRenderer, PressingOntoABoxEdgeKeepsThePenetrationWithinTheWallsStiffness) {
    ProxySettings ps;
    ps.toolRadius = 0.002;
    const double h = test::kBoxHalf;
    const glm::dvec3 diagonal = glm::normalize(glm::dvec3(1, 0, 1));
    const glm::dvec3 edge(h, 0.0, h);
    const double aim = 0.004;
    const glm::dvec3 from = edge + 0.015 * diagonal, to = edge + (ps.toolRadius - aim) * diagonal;
    Rig rig(test::pressHand(from, to), test::boxClay(), ps);
    const double deepest =
        runPress(rig, [&](const glm::dvec3& p) { return ps.toolRadius - test::boxDistance(p); });
    const double bound = penetrationBound(rig, aim, glm::length(to - from) / 0.2) + test::surfaceError(*rig.clay);
    std::printf("[ box edge ] deepest penetration %.3f mm, bound %.3f mm\n", deepest * 1e3, bound * 1e3);
    EXPECT_LE(deepest, bound);
    EXPECT_GT(deepest, 0.0);
}

TEST(ProxyRenderer, PressingIntoACarvedGrooveKeepsThePenetrationWithinTheWallsStiffness) {
    // A groove of radius 4 mm along y across the box's top face, then a 2 mm tool pressed into
    // it off its axis: the groove's walls and bottom hold it (the tool slides to the bottom).
    const double h = test::kBoxHalf, grooveRadius = 0.004;
    sculpt::Stroke groove;
    groove.tool.radius = grooveRadius;
    const glm::dquat identity(1.0, 0.0, 0.0, 0.0);
    groove.samples = {{{0.0, -0.015, h}, identity}, {{0.0, 0.015, h}, identity}};
    sculpt::Sculptor sculptor(test::boxClay());
    sculptor.apply(groove);
    // The carved field: max of the box and the groove's complement (the Sculptor's CSG).
    auto carved = [&](const glm::dvec3& p) {
        const glm::dvec3 axis(0.0, std::clamp(p.y, -0.015, 0.015), h);
        return std::max(test::boxDistance(p), grooveRadius - glm::length(p - axis));
    };
    ProxySettings ps;
    ps.toolRadius = 0.002;
    const double aim = 0.004;
    const glm::dvec3 bottom(0.0, 0.0, h - grooveRadius + ps.toolRadius);  // the tool resting on the bottom
    Rig rig(test::pressHand({0.0015, 0.0, h + 0.01}, bottom + glm::dvec3(0.0015, 0.0, -aim)), sculptor.current(), ps);
    // A carved field is within twice the error bound of its CSG (the crease at the groove's rim).
    const double deepest = runPress(rig, [&](const glm::dvec3& p) { return ps.toolRadius - carved(p); }, nullptr, 2.0);
    const double bound = penetrationBound(rig, aim, 0.014 / 0.2) + test::surfaceError(*rig.clay);
    std::printf("[ groove ] deepest penetration %.3f mm, bound %.3f mm\n", deepest * 1e3, bound * 1e3);
    EXPECT_LE(deepest, bound);
    EXPECT_GT(deepest, 0.0);
}

/// A hand that presses `aim` into the sphere's contact surface at angle -0.3 rad in the xz
/// plane, then sweeps to +0.3 rad along it in 0.6 s, then lifts.
sim::Hand arcHand(double contact, double aim) {
    sim::Hand h;
    auto at = [](double r, double a) { return glm::dvec3(r * std::sin(a), 0.0, r * std::cos(a)); };
    h.add(0.0, at(contact + 0.01, -0.3));
    h.add(0.3, at(contact + 0.01, -0.3));
    h.add(0.5, at(contact - aim, -0.3));
    for (int i = 1; i <= 12; ++i) h.add(0.5 + 0.05 * i, at(contact - aim, -0.3 + 0.05 * i));
    h.add(1.3, at(contact + 0.01, 0.3));
    return h;
}

TEST(ProxyRenderer, SlidingAlongASphereFollowsItsSurface) {
    ProxySettings ps;
    ps.toolRadius = 0.003;
    const double contact = test::kSphereRadius + ps.toolRadius;
    Rig rig(arcHand(contact, 0.004), test::sphereClay(), ps);
    const double eps = test::surfaceError(*rig.clay);
    double worstOff = 0.0, worstLag = 0.0, minAngle = 1.0, maxAngle = -1.0;
    for (int i = 0; i < 1300; ++i) {
        const haptics::ProxyOutput& out = rig.tick();
        if (i < 520 || i > 1100 || !out.contact) continue;  // the sweep, in contact
        worstOff = std::max(worstOff, std::abs(glm::length(out.proxy) - contact));
        // Frictionless: the proxy is the device's projection onto the contact sphere.
        worstLag = std::max(worstLag, glm::length(out.proxy - contact * glm::normalize(rig.state.position)));
        const double angle = std::atan2(out.proxy.x, out.proxy.z);
        minAngle = std::min(minAngle, angle);
        maxAngle = std::max(maxAngle, angle);
    }
    std::printf("[ slide ] proxy off the contact sphere <= %.4f mm, off the device's projection <= %.4f mm, "
                "swept %.2f to %.2f rad\n", worstOff * 1e3, worstLag * 1e3, minAngle, maxAngle);
    EXPECT_LE(worstOff, eps + 1e-5);
    EXPECT_LE(worstLag, eps + 1e-4);
    EXPECT_LT(minAngle, -0.2);
    EXPECT_GT(maxAngle, 0.2);
}

TEST(ProxyRenderer, FrictionHoldsTheProxyInsideTheCone) {
    ProxySettings ps;
    ps.toolRadius = 0.003;
    ps.staticFriction = 0.4;
    ps.kineticFriction = 0.3;
    const double contact = test::kSphereRadius + ps.toolRadius;
    Rig rig(arcHand(contact, 0.004), test::sphereClay(), ps);
    double worstRatio = 0.0, worstLag = 0.0;
    for (int i = 0; i < 1300; ++i) {
        const haptics::ProxyOutput& out = rig.tick();
        if (i < 520 || i > 1100 || !out.contact) continue;
        const glm::dvec3 n = glm::normalize(out.proxy);
        const double normal = glm::dot(out.force, n);
        const double tangential = glm::length(out.force - normal * n);
        if (normal > 0.2) worstRatio = std::max(worstRatio, tangential / normal);
        worstLag = std::max(worstLag, glm::length(out.proxy - contact * glm::normalize(rig.state.position)));
    }
    std::printf("[ friction ] tangential / normal force <= %.3f, proxy behind the device's projection <= %.3f mm\n",
                worstRatio, worstLag * 1e3);
    EXPECT_LE(worstRatio, ps.staticFriction + 0.05);  // the cone, plus the curvature's share
    EXPECT_GT(worstRatio, 0.5 * ps.kineticFriction) << "friction did drag";
}

TEST(ProxyRenderer, ForcesAreFiniteAndWithinTheMaximumWhateverComesIn) {
    ProxySettings ps;
    ps.maxForce = 2.0;
    ps.toolRadius = 0.002;
    sim::StylusSettings ss;
    ss.handStiffness = 3000.0;  // a hand that shoves far past the clamp
    sim::Hand h;
    uint64_t state = 12345;
    auto next = [&] {  // a fixed LCG: the same wild path every run
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return double(state >> 11) / double(1ull << 53) * 2.0 - 1.0;
    };
    for (int i = 0; i <= 40; ++i) h.add(0.05 * i, glm::dvec3(next(), next(), next()) * 0.045);
    Rig rig(h, test::sphereClay(), ps, ss);
    double largest = 0.0;
    for (int i = 0; i < 2000; ++i) {
        const haptics::ProxyOutput& out = rig.tick(i % 300 > 250);  // carve now and then too
        ASSERT_TRUE(std::isfinite(out.force.x) && std::isfinite(out.force.y) && std::isfinite(out.force.z)) << i;
        ASSERT_LE(glm::length(out.force), 2.0) << i;
        largest = std::max(largest, glm::length(out.force));
    }
    EXPECT_GT(largest, 1.9) << "the clamp was reached";
    // Non-finite device states: zero force with the fault flag, the proxy held.
    const glm::dvec3 held = rig.last.proxy;
    haptics::DeviceState bad = rig.state;
    for (double v : {std::nan(""), std::numeric_limits<double>::infinity()}) {
        bad.position = glm::dvec3(0.0, v, 0.0);
        haptics::ProxyOutput out = rig.renderer.update(bad, rig.accessor, rig.clayId, kPeriod, false);
        EXPECT_TRUE(out.fault);
        EXPECT_EQ(out.force, glm::dvec3(0.0));
        EXPECT_EQ(out.proxy, held);
        bad.position = rig.state.position;
        bad.velocity = glm::dvec3(v);
        out = rig.renderer.update(bad, rig.accessor, rig.clayId, kPeriod, false);
        EXPECT_TRUE(out.fault);
        EXPECT_EQ(out.force, glm::dvec3(0.0));
        bad.velocity = glm::dvec3(0.0);
        EXPECT_TRUE(rig.renderer.update(bad, rig.accessor, rig.clayId, std::nan(""), false).fault);
    }
    bad.connected = false;
    EXPECT_EQ(rig.renderer.update(bad, rig.accessor, rig.clayId, kPeriod, false).force, glm::dvec3(0.0));
}

TEST(ProxyRenderer, SoftStartScaleAndOff) {
    // The device starts 3 mm inside the sphere: no force at first (it would be a kick), then
    // once the computed force is below the threshold, a ramp.
    ProxySettings ps;
    ps.softStartForce = 0.5;
    ps.softStartTime = 0.1;
    sim::Hand h;
    h.add(0.0, {0.0, 0.0, test::kSphereRadius - 0.003});
    h.add(0.5, {0.0, 0.0, test::kSphereRadius - 0.003});
    h.add(0.7, {0.0, 0.0, test::kSphereRadius + 0.01});
    h.add(1.0, {0.0, 0.0, test::kSphereRadius - 0.002});
    Rig rig(h, test::sphereClay(), ps);
    const haptics::ProxyOutput& first = rig.tick();
    EXPECT_LT(glm::length(first.force), 0.01) << "no kick on start: the proxy starts at the device and backs out";
    double previous = 0.0, largestStep = 0.0;
    for (int i = 0; i < 1200; ++i) {
        const double f = glm::length(rig.tick().force);
        largestStep = std::max(largestStep, std::abs(f - previous));
        previous = f;
    }
    EXPECT_GT(previous, 0.5) << "pressing at the end, at full strength";
    EXPECT_LT(largestStep, 0.5) << "no step larger than the soft start's threshold";
    // Scale and off.
    const double full = glm::length(rig.tick().force);
    rig.renderer.setForceScale(0.5);
    EXPECT_NEAR(glm::length(rig.tick().force), 0.5 * full, 0.1 * full);
    rig.renderer.setEnabled(false);
    EXPECT_EQ(rig.tick().force, glm::dvec3(0.0));
    EXPECT_TRUE(rig.last.contact) << "the proxy is still tracked while off";
    rig.renderer.setForceScale(1.0);  // the computed force (~0.9 N) is above the threshold again
    rig.renderer.setEnabled(true);
    EXPECT_EQ(rig.tick().force, glm::dvec3(0.0)) << "turning on restarts the soft start";
}

}  // namespace
}  // namespace kizamu
