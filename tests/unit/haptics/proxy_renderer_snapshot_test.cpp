// SPDX-License-Identifier: Apache-2.0
// The proxy renderer (haptics/proxy_renderer.h) across new snapshots, with the simulated stylus
// in lock step: a surface moved 2 mm under a resting proxy changes the force without a jump,
// and carving (the proxy advancing into the clay at the removal rate, its path carved live by
// a Sculptor whose snapshots the renderer then reads) removes material along the proxy's path
// and never runs ahead of the hand.
#include "haptics/proxy_renderer.h"
#include "tests/unit/haptics/lockstep.h"

#include "adf/guarded_accessor.h"
#include "adf/snapshot_store.h"
#include "sculpt/sculptor.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <vector>

namespace kizamu {
namespace {

using haptics::ProxySettings;
using test::kPeriod;
using test::Rig;

TEST(ProxyRendererSnapshots, ASurfaceMovedUnderARestingProxyChangesTheForceWithoutAJump) {
    const double toolRadius = 0.003, aim = 0.003;
    for (const double moved : {0.002, -0.002}) {
        ProxySettings ps;
        ps.toolRadius = toolRadius;
        const double contact = test::kSphereRadius + toolRadius;
        Rig rig(test::pressHand({0, 0, contact + 0.01}, {0, 0, contact - aim}, 0.3, 0.2, 2.0), test::sphereClay(), ps);
        const adf::AdfPtr movedClay = test::sphereClay(test::kSphereRadius + moved);
        for (int i = 0; i < 1000; ++i) rig.tick();  // resting, pressed in
        ASSERT_TRUE(rig.last.contact);
        const double k = rig.renderer.gains().stiffness;
        glm::dvec3 previous = rig.last.force;
        double restingStep = 0.0;
        for (int i = 0; i < 100; ++i) {
            restingStep = std::max(restingStep, glm::length(rig.tick().force - previous));
            previous = rig.last.force;
        }
        // The bound, 0.5 N per tick: settling moves the proxy at most settleSpeed T (50 µm, so
        // K settleSpeed T = 0.16 N), and the device's own motion adds K |dx| (the wall it then
        // meets); a proxy put on the new surface at once would step by K x 2 mm = 6.4 N.
        rig.setClay(movedClay);
        double worst = 0.0;
        int settlingTicks = 0;
        for (int i = 0; i < 400; ++i) {
            const haptics::ProxyOutput& out = rig.tick();
            worst = std::max(worst, glm::length(out.force - previous));
            settlingTicks += out.settling ? 1 : 0;
            previous = out.force;
        }
        std::printf("[ moved %+.0f mm ] largest force step per tick %.3f N (resting %.3f N; a jump would be %.1f N), "
                    "%d ticks settling\n", moved * 1e3, worst, restingStep, k * std::abs(moved), settlingTicks);
        EXPECT_LT(worst, 0.5) << "moved " << moved;
        EXPECT_GT(settlingTicks, 5) << "the proxy was moved gradually";
        // Settled on the new contact surface, still pressed.
        EXPECT_FALSE(rig.last.settling);
        EXPECT_TRUE(rig.last.contact);
        EXPECT_NEAR(glm::length(rig.last.proxy), contact + moved, test::surfaceError(*rig.clay) + 1e-5);
    }
}

TEST(ProxyRendererSnapshots, TheServoLoopShapeReadsPublishedSnapshotsThroughGuards) {
    // As the servo thread does it: a guard per tick, the GuardedAccessor bound to it, the
    // snapshot's sequence number as its identity. A publish that moves the surface 2 mm out is
    // seen on the next tick and the proxy settles onto it gradually.
    ProxySettings ps;
    ps.toolRadius = 0.003;
    const double contact = test::kSphereRadius + ps.toolRadius;
    sim::SimulatedStylus stylus(test::pressHand({0, 0, contact + 0.01}, {0, 0, contact - 0.003}, 0.3, 0.2, 2.0));
    haptics::ProxyRenderer renderer(stylus.spec(), kPeriod, ps);
    adf::SnapshotStore store(test::sphereClay());
    adf::SnapshotStore::Reader reader(store);
    std::optional<adf::GuardedAccessor> accessor;
    haptics::ProxyOutput out;
    glm::dvec3 previous(0.0);
    double worst = 0.0;
    int settling = 0;
    for (int i = 0; i < 1400; ++i) {
        if (i == 1000) store.publish(test::sphereClay(test::kSphereRadius + 0.002));
        haptics::DeviceState state;
        stylus.read(state);
        {
            const auto guard = reader.acquire();
            if (!accessor) accessor.emplace(guard);
            out = renderer.update(state, *accessor, guard, kPeriod, false);
        }
        stylus.write(out.force);
        stylus.step(kPeriod);
        if (i > 1000) {
            worst = std::max(worst, glm::length(out.force - previous));
            settling += out.settling ? 1 : 0;
        }
        previous = out.force;
    }
    EXPECT_EQ(accessor->sequence(), adf::SnapshotStore::kInitialSequence + 1);
    EXPECT_GT(settling, 10);
    EXPECT_LT(worst, 0.5);
    EXPECT_TRUE(out.contact);
    EXPECT_NEAR(glm::length(out.proxy), contact + 0.002, 2e-4 + 1e-5);
}

TEST(ProxyRendererCarving, TheProxyAdvancesAtTheRemovalRateAndItsPathIsCarved) {
    const double top = test::kBoxHalf, r = 0.003;
    ProxySettings ps;
    ps.toolRadius = r;
    ps.removalRate = 0.01;
    // Rest above, then with the carve button down 4 mm past the touching level, across 2 cm, up.
    const double zAim = top + r - 0.004;
    sim::Hand hand;
    hand.add(0.0, {-0.01, 0.0, top + 0.01});
    hand.add(0.3, {-0.01, 0.0, top + 0.01}, 1u);
    hand.add(0.5, {-0.01, 0.0, zAim}, 1u);
    hand.add(1.1, {0.01, 0.0, zAim}, 1u);
    hand.add(1.2, {0.01, 0.0, zAim}, 0u);
    hand.add(1.4, {0.01, 0.0, top + 0.01}, 0u);
    Rig rig(hand, test::boxClay(), ps);
    const adf::AdfPtr start = rig.clay;
    sculpt::Sculptor sculptor(start);
    sculpt::Stroke header;
    header.tool.radius = r;  // a carving sphere the size of the haptic tool
    std::vector<sculpt::ToolSample> pending;
    std::vector<glm::dvec3> path;
    bool stroking = false;
    double deepest = 0.0, strongest = 0.0, ahead = -1.0;
    int touched = -1, twoMm = -1;  // ticks the proxy went below the touching level, and 2 mm below
    for (int i = 0; i < 1500; ++i) {
        const glm::dvec3 before = rig.last.proxy;
        const haptics::ProxyOutput& out = rig.tick();
        const bool carving = (rig.state.buttons & 1u) != 0;
        if (!carving) {
            if (stroking) {  // release: the rest of the path, then the stroke ends
                if (!pending.empty()) sculptor.extendStroke(pending);
                sculptor.endStroke();
                rig.setClay(sculptor.current());
                stroking = false;
                pending.clear();
            }
            continue;
        }
        // The caller carves at the proxy's pose, in segments, as the engine does.
        path.push_back(out.proxy);
        pending.push_back({out.proxy, glm::dquat(1.0, 0.0, 0.0, 0.0)});
        if (!stroking) {
            sculptor.beginStroke(header);
            stroking = true;
        }
        if (pending.size() >= 25) {
            sculptor.extendStroke(pending);
            pending.clear();
            rig.setClay(sculptor.current());
        }
        // Into the start clay: how deep below the touching level, and how fast.
        const double depth = r - double(start->distance(glm::vec3(out.proxy)));
        deepest = std::max(deepest, depth);
        if (depth > 0.0 && touched < 0) touched = i;
        if (depth > 0.002 && twoMm < 0) twoMm = i;
        strongest = std::max(strongest, glm::length(out.force));
        // Never ahead of the hand: behind the device along the stroke (x), and toward it.
        ahead = std::max(ahead, out.proxy.x - rig.state.position.x);
        if (i > 0 && out.contact) {
            const glm::dvec3 moved = out.proxy - before;
            EXPECT_LE(glm::dot(moved, rig.state.position - before), glm::dot(rig.state.position - before, rig.state.position - before) + 1e-12);
        }
    }
    ASSERT_FALSE(stroking);
    ASSERT_GT(path.size(), 500u);
    std::printf("[ carve ] the proxy went %.2f mm below the touching level; carving force up to %.2f N; "
                "proxy ahead of the device by at most %.4f mm\n", deepest * 1e3, strongest, ahead * 1e3);
    EXPECT_GT(deepest, 0.002) << "the proxy advanced into the material";
    EXPECT_LE(ahead, 1e-9) << "the proxy never ran ahead of the hand";
    EXPECT_GT(strongest, 0.5) << "carving meets resistance";
    // Material was removed along the whole path: every pose is now outside the clay (by about
    // the tool's radius), and much of the path had the tool at least 1 mm into the start clay.
    const adf::Adf& carved = *sculptor.current();
    int wasInside = 0;
    for (const glm::dvec3& p : path) {
        EXPECT_GT(carved.distance(glm::vec3(p)), 0.5 * r) << p.x << " " << p.z;
        wasInside += start->distance(glm::vec3(p)) < r - 0.001 ? 1 : 0;  // the tool 1 mm into the start clay
    }
    EXPECT_GT(wasInside, 200);
    // The rate: 2 mm into the material took at least (2 mm - the ADF's error) / removalRate.
    ASSERT_GE(twoMm, 0);
    const double took = (twoMm - touched) * kPeriod, least = (0.002 - test::surfaceError(*start)) / ps.removalRate;
    std::printf("[ carve ] 2 mm into the material in %.3f s (the removal rate allows %.3f s at least)\n", took, least);
    EXPECT_GE(took, least);
    EXPECT_EQ(sculptor.undoDepth(), 1u);
}

}  // namespace
}  // namespace kizamu
