// SPDX-License-Identifier: Apache-2.0
// How the device becomes the tool: the workspace map and the spec it implies (passive on the
// device at every scale), the predictive input filter, the clutch and the fine mode, a 2-DOF
// input projected onto the clay, and the servo trace. Lock step at 1 kHz on the simulated
// stylus; the clay is a SnapshotStore and the engine's side a SampleQueue read back directly.
#include "engine/sample_queue.h"
#include "haptics/engine_client.h"
#include "haptics/haptic_trace.h"
#include "haptics/input_filter.h"
#include "haptics/workspace.h"
#include "tests/unit/haptics/lockstep.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>
#include <string>
#include <vector>

namespace kizamu {
namespace {

using haptics::DeviceState;
using haptics::WorkspaceMapping;
using test::kPeriod;

TEST(WorkspaceMapping, MapsPointsVectorsAndForcesAndReanchorsWithoutMoving) {
    WorkspaceMapping m;
    m.scale = 2.0;
    m.rotation = glm::angleAxis(glm::radians(90.0), glm::dvec3(0.0, 0.0, 1.0));
    m.anchor(glm::dvec3(0.01, 0.0, 0.0), glm::dvec3(1.0, 2.0, 3.0));
    const glm::dvec3 w = m.toWorld(glm::dvec3(0.02, 0.0, 0.0));  // 1 cm along device x: 2 cm along world y
    EXPECT_NEAR(glm::length(w - glm::dvec3(1.0, 2.02, 3.0)), 0.0, 1e-12);
    EXPECT_NEAR(glm::length(m.toDevice(w) - glm::dvec3(0.02, 0.0, 0.0)), 0.0, 1e-12);
    EXPECT_NEAR(glm::length(m.vectorToWorld(glm::dvec3(0.0, 1.0, 0.0)) - glm::dvec3(-2.0, 0.0, 0.0)), 0.0, 1e-12);
    // Forces turn back and keep their size.
    EXPECT_NEAR(glm::length(m.forceToDevice(glm::dvec3(0.0, 3.0, 0.0)) - glm::dvec3(3.0, 0.0, 0.0)), 0.0, 1e-12);
    // Re-anchoring a device point on its own world point changes nothing.
    const glm::dvec3 p(0.003, -0.004, 0.005);
    const glm::dvec3 before = m.toWorld(glm::dvec3(0.03, 0.01, -0.02));
    m.anchor(p, m.toWorld(p));
    EXPECT_NEAR(glm::length(m.toWorld(glm::dvec3(0.03, 0.01, -0.02)) - before), 0.0, 1e-12);
}

TEST(WorkspaceMapping, FitsTheWorkspaceAndScalesTheSpecToStayPassiveOnTheDevice) {
    haptics::DeviceSpec spec;
    spec.maxForce = 9.0;
    spec.maxStiffness = 4000.0;
    spec.damping = 2.0;
    spec.workspaceMin = glm::dvec3(-0.05);
    spec.workspaceMax = glm::dvec3(0.05);
    const WorkspaceMapping m = WorkspaceMapping::fit(spec, glm::dvec3(1.0, 1.0, 1.0), glm::dvec3(1.4, 1.2, 1.3));
    EXPECT_DOUBLE_EQ(m.scale, 2.0);  // the y extent (0.2 m over 0.1 m) limits
    EXPECT_NEAR(glm::length(m.toWorld(glm::dvec3(0.0)) - glm::dvec3(1.2, 1.1, 1.15)), 0.0, 1e-12);
    const haptics::DeviceSpec w = m.worldSpec(spec);
    EXPECT_DOUBLE_EQ(w.maxForce, spec.maxForce);
    for (const double virtualDamping : {0.0, 0.2}) {
        // The world bound times the scale is the device's bound with the damper felt as B * scale.
        const double worldBound = haptics::passiveStiffnessBound(w.damping, virtualDamping, kPeriod);
        EXPECT_NEAR(worldBound * m.scale, haptics::passiveStiffnessBound(spec.damping, virtualDamping * m.scale, kPeriod),
                    1e-9);
    }
    EXPECT_NEAR(w.workspaceMax.y - w.workspaceMin.y, 0.2, 1e-12);
}

/// Press-and-return cycles against the box's top face through a map of `scale` (the hand in
/// the device frame, the clay in the world); returns the energy the rendering put into the
/// device over the whole run (see proxy_renderer_passivity_test.cpp for why this measure).
double mappedCycleEnergy(double scale, double stiffnessOverBound, double* deviceStiffness) {
    WorkspaceMapping m;
    m.scale = scale;
    const double top = test::kBoxHalf / scale;  // the face in the device frame
    sim::Hand h;
    h.add(0.0, {0.0, 0.0, top + 0.006});
    h.add(0.3, {0.0, 0.0, top + 0.006});
    for (int c = 0; c < 10; ++c) {
        const double t0 = 0.3 + 0.25 * c;
        h.add(t0 + 0.1, {0.0, 0.0, top - 0.003});
        h.add(t0 + 0.15, {0.0, 0.0, top - 0.003});
        h.add(t0 + 0.25, {0.0, 0.0, top + 0.006});
    }
    sim::SimulatedStylus stylus(h);
    haptics::ProxyRenderer renderer(m.worldSpec(stylus.spec()), kPeriod, {});
    if (stiffnessOverBound > 0.0)
        renderer.setStiffnessUnchecked(stiffnessOverBound * renderer.gains().passiveBound);
    *deviceStiffness = renderer.gains().stiffness * scale;
    adf::AdfPtr clay = test::boxClay(6);
    adf::AdfAccessor accessor(*clay);
    DeviceState s;
    int contacts = 0;
    for (int i = 0; i < int(h.duration() / kPeriod) + 100; ++i) {
        stylus.read(s);
        const haptics::ProxyOutput out = renderer.update(m.toWorld(s), accessor, 1, kPeriod, false);
        contacts += out.contact ? 1 : 0;
        stylus.write(m.forceToDevice(out.force));
        stylus.step(kPeriod);
    }
    EXPECT_GT(contacts, 500) << "every cycle pressed into the face";
    return stylus.energy().rendered - stylus.energy().dampedUnderForce;
}

TEST(WorkspaceMapping, AScaledWorkspaceStaysPassiveOnTheDeviceAndFailsPastItsBound) {
    for (const double scale : {0.5, 2.0}) {
        double k = 0.0;
        const double within = mappedCycleEnergy(scale, 0.0, &k);
        std::printf("[ mapped ] scale %.1f: the device feels %.0f N/m; energy put in over 10 cycles %.3g J\n", scale, k, within);
        EXPECT_NEAR(k, haptics::ProxyRenderer::kPassivitySafety * 4000.0, 1e-6) << "the device feels the same wall";
        EXPECT_LE(within, 1e-9);
        const double past = mappedCycleEnergy(scale, 1.5, &k);
        std::printf("[ mapped ] scale %.1f, 1.5x the bound (%.0f N/m on the device): %.3g J\n", scale, k, past);
        EXPECT_GT(past, 1e-6);
    }
}

TEST(InputFilter, FollowsAConstantVelocityWithoutLagAndSmoothsNoise) {
    haptics::InputFilterSettings fs;
    fs.enabled = true;
    haptics::InputFilter filter(fs);
    std::mt19937 rng(7);
    std::normal_distribution<double> noise(0.0, 1e-4);  // 0.1 mm of sensor noise
    const glm::dvec3 v(0.05, -0.02, 0.01);               // m/s
    double rawError = 0.0, filteredError = 0.0;
    int n = 0;
    for (int i = 0; i < 2000; ++i) {
        const glm::dvec3 truth = v * (i * kPeriod);
        DeviceState s;
        s.position = truth + glm::dvec3(noise(rng), noise(rng), noise(rng));
        const glm::dvec3 raw = s.position;
        filter.update(s, kPeriod);
        if (i >= 500) {  // after the tracker has converged
            rawError += glm::dot(raw - truth, raw - truth);
            filteredError += glm::dot(s.position - truth, s.position - truth);
            ++n;
        }
    }
    std::printf("[ filter ] rms error %.1f um raw, %.1f um filtered\n", std::sqrt(rawError / n) * 1e6,
                std::sqrt(filteredError / n) * 1e6);
    EXPECT_LT(filteredError, 0.6 * rawError);
    // Noise-free constant velocity: no steady-state lag, and the velocity is estimated.
    haptics::InputFilter clean(fs);
    DeviceState s;
    for (int i = 0; i < 3000; ++i) {
        s.position = v * (i * kPeriod);
        clean.update(s, kPeriod);
    }
    EXPECT_NEAR(glm::length(s.position - v * (2999 * kPeriod)), 0.0, 1e-9);
    EXPECT_NEAR(glm::length(s.velocity - v), 0.0, 1e-6);
    // Off: untouched; bad gains: refused.
    haptics::InputFilter off;
    DeviceState t;
    t.position = glm::dvec3(1.0, 2.0, 3.0);
    off.update(t, kPeriod);
    EXPECT_EQ(t.position, glm::dvec3(1.0, 2.0, 3.0));
    haptics::InputFilterSettings bad = fs;
    bad.beta = 3.5;
    EXPECT_THROW(haptics::InputFilter{bad}, std::invalid_argument);
    bad = fs;
    bad.alpha = 0.0;
    EXPECT_THROW(haptics::InputFilter{bad}, std::invalid_argument);
}

/// The client on a sphere's snapshot with the stylus in lock step; what reaches the engine is
/// read back from the queue.
struct ClientRig {
    sim::SimulatedStylus stylus;
    adf::SnapshotStore store;
    engine::SampleQueue samples;
    haptics::ProxyRenderer renderer;
    haptics::EngineHapticClient client;
    DeviceState state;
    glm::dvec3 force{0.0};

    ClientRig(sim::Hand hand, const haptics::HapticToolSettings& tool, double toolRadius = 0.003)
        : stylus(std::move(hand)), store(test::sphereClay()),
          renderer(tool.mapping.worldSpec(stylus.spec()), kPeriod, proxySettings(toolRadius)),
          client(store, samples, renderer, tool) {}
    static haptics::ProxySettings proxySettings(double r) {
        haptics::ProxySettings ps;
        ps.toolRadius = r;
        return ps;
    }
    void tick() {
        stylus.read(state);
        client.tick(state, kPeriod, force);
        stylus.write(force);
        stylus.step(kPeriod);
    }
    /// Every sample the engine would have taken so far.
    std::vector<engine::ToolSample> taken() {
        std::vector<engine::ToolSample> out(4096);
        samples.flush();
        out.resize(samples.drain(out.data(), out.size()));
        return out;
    }
};

TEST(EngineHapticClient, TheClutchHoldsTheToolAndReleasingItDoesNotJump) {
    // Hand: rest above the sphere, clutch (button 2) and move 2 cm sideways, release, move back
    // down onto the sphere with the carve button.
    sim::Hand h;
    const glm::dvec3 above(0.0, 0.0, 0.045);
    h.add(0.0, above);
    h.add(0.2, above, engine::kButtonSecondary);
    h.add(0.5, above + glm::dvec3(0.02, 0.0, 0.0), engine::kButtonSecondary);
    h.add(0.6, above + glm::dvec3(0.02, 0.0, 0.0), engine::kButtonPrimary | engine::kButtonSecondary);
    h.add(0.7, above + glm::dvec3(0.02, 0.0, 0.0), 0);
    h.add(1.0, above + glm::dvec3(0.02, 0.0, -0.01), 0);
    ClientRig rig(h, {});
    for (int i = 0; i < 200; ++i) rig.tick();
    const glm::dvec3 held = rig.client.last().proxy;
    EXPECT_NEAR(glm::length(held - above), 0.0, 1e-3);
    rig.taken();
    double drift = 0.0;
    for (int i = 0; i < 480; ++i) {  // clutched: the device moves 2 cm, the tool stays, no force, no carving
        rig.tick();
        if (!rig.client.clutched()) break;
        drift = std::max(drift, glm::length(rig.client.last().proxy - held));
        EXPECT_EQ(rig.force, glm::dvec3(0.0));
    }
    EXPECT_EQ(drift, 0.0);
    for (const engine::ToolSample& s : rig.taken()) {
        EXPECT_EQ(s.buttons & engine::kButtonPrimary, 0u) << "no carving while clutched";
        EXPECT_EQ(s.posWorld, held);
    }
    // Released at 0.7 s: the tool continues from where it was held, then follows the hand's
    // motion (1 cm down) relative to there.
    for (int i = 0; i < 20; ++i) rig.tick();
    EXPECT_LT(glm::length(rig.client.last().proxy - held), 1e-3) << "no jump on release";
    for (int i = 0; i < 500; ++i) rig.tick();
    EXPECT_NEAR(rig.client.last().proxy.x, held.x, 1e-3) << "the 2 cm moved while clutched are not the tool's";
    EXPECT_NEAR(rig.client.last().proxy.z, held.z - 0.01, 1e-3);
}

TEST(EngineHapticClient, TheFineModeScalesMotionAroundTheToolAndBack) {
    sim::Hand h;
    const glm::dvec3 start(0.0, 0.0, 0.045);
    h.add(0.0, start);
    h.add(0.2, start, engine::kButtonTertiary);  // press: fine mode on
    h.add(0.25, start, 0);
    h.add(0.75, start + glm::dvec3(0.02, 0.0, 0.0), 0);  // 2 cm of hand: 5 mm of tool at 0.25
    h.add(1.0, start + glm::dvec3(0.02, 0.0, 0.0), engine::kButtonTertiary);  // press: back to normal
    h.add(1.05, start + glm::dvec3(0.02, 0.0, 0.0), 0);
    h.add(1.55, start + glm::dvec3(0.03, 0.0, 0.0), 0);  // 1 cm more: 1 cm of tool
    haptics::HapticToolSettings tool;
    tool.fineScale = 0.25;
    ClientRig rig(h, tool);
    for (int i = 0; i < 200; ++i) rig.tick();
    const glm::dvec3 a = rig.client.last().proxy;
    for (int i = 0; i < 790; ++i) rig.tick();
    EXPECT_TRUE(rig.client.fine());
    const glm::dvec3 b = rig.client.last().proxy;
    EXPECT_NEAR(b.x - a.x, 0.005, 3e-4);
    for (int i = 0; i < 800; ++i) rig.tick();
    EXPECT_FALSE(rig.client.fine());
    EXPECT_NEAR(rig.client.last().proxy.x - b.x, 0.01, 3e-4);
}

TEST(EngineHapticClient, ATwoAxisInputRidesTheSurfaceAndFeelsItsSlope) {
    // A 2-DOF device: only x and y mean anything; the tool comes down onto the sphere along -z.
    haptics::HapticToolSettings tool;
    tool.planar = true;
    tool.planarPress = 0.001;
    sim::Hand h;
    h.add(0.0, {0.0, 0.0, 0.0});
    h.add(0.3, {0.0, 0.0, 0.0});
    h.add(1.3, {0.02, 0.0, 0.0});  // slides 2 cm towards +x, over the sphere's flank
    ClientRig rig(h, tool);
    double worstOffSurface = 0.0;
    for (int i = 0; i < 1300; ++i) {
        rig.tick();
        if (i < 250) continue;
        const glm::dvec3 p = rig.client.last().proxy;
        worstOffSurface = std::max(worstOffSurface, std::abs(glm::length(p) - (test::kSphereRadius + 0.003)));
        EXPECT_TRUE(rig.client.last().contact) << "tick " << i;
        EXPECT_GT(p.z, 0.0) << "on the top of the sphere";
    }
    EXPECT_LT(worstOffSurface, 5e-4) << "the tool rides the surface (within the ADF's error)";
    // On the flank the surface slopes down towards +x: the force's in-plane part pushes that way.
    EXPECT_GT(rig.client.last().force.x, 0.1);
}

TEST(HapticTrace, TheRingDropsWhenFullAndTheLinesAreJson) {
    haptics::TraceRing ring(4);
    haptics::TraceRecord r;
    for (int i = 0; i < 6; ++i) {
        r.timeNs = 1'000'000 * i;
        EXPECT_EQ(ring.push(r), i < 4);
    }
    EXPECT_EQ(ring.dropped(), 2u);
    haptics::TraceRecord out;
    for (int i = 0; i < 4; ++i) {
        ASSERT_TRUE(ring.pop(out));
        EXPECT_EQ(out.timeNs, 1'000'000 * i);
    }
    EXPECT_FALSE(ring.pop(out));

    haptics::TraceHeader h;
    h.device = "sim \"quoted\"";
    h.maxForce = 9.0;
    h.stiffness = 3200.0;
    h.rate = 1000.0;
    const auto header = nlohmann::json::parse(haptics::formatTraceHeader(h));
    EXPECT_EQ(header["device"], "sim \"quoted\"");
    EXPECT_EQ(header["max_force"], 9.0);
    EXPECT_EQ(header["stiffness"], 3200.0);
    EXPECT_EQ(header["rate"], 1000.0);
    r.timeNs = 2'500'000;
    r.device = glm::dvec3(0.001, -0.002, 0.003);
    r.force = glm::dvec3(1.5, 0.0, -2.0);
    r.contact = true;
    const auto line = nlohmann::json::parse(haptics::formatTraceRecord(r, 500'000));
    EXPECT_DOUBLE_EQ(line["t"].get<double>(), 0.002);
    EXPECT_EQ(line["device"][1], -0.002);
    EXPECT_EQ(line["force"][2], -2.0);
    EXPECT_EQ(line["contact"], true);
    for (const char* key : {"velocity", "proxy"}) EXPECT_TRUE(line.contains(key));
}

}  // namespace
}  // namespace kizamu
