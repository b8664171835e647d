// SPDX-License-Identifier: Apache-2.0
// The haptic pipeline end to end in lock step: the simulated stylus follows the example hand
// examples/slide_and_carve.hand.jsonl, the servo ticker calls EngineHapticClient, which feels the
// live engine's published clay through the proxy renderer and pushes the proxy's pose to the
// engine. Checked: forces finite and within the maximum, the proxy never inside the clay it felt
// while touching, one carve stroke journaled, and the clay carved along the proxy's carving path.
#include "haptics/engine_client.h"

#include "engine/engine.h"
#include "haptics/servo_loop.h"
#include "sim/hand_file.h"
#include "sim/simulated_stylus.h"
#include "tests/unit/haptics/lockstep.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <thread>
#include <vector>

namespace kizamu {
namespace {

TEST(EngineHapticClient, TheStylusFeelsAndCarvesTheLiveEnginesClay) {
    sculpt::Shape sphere;
    sphere.kind = sculpt::Shape::Kind::Sphere;
    sphere.centre = glm::dvec3(0.0);
    sphere.radius = test::kSphereRadius;
    engine::EngineSettings settings;
    settings.start = test::hapticScript(sphere, 7);
    settings.threads = 2;
    settings.correctAfterIdle = std::chrono::milliseconds(0);
    engine::Engine e(settings);
    constexpr double kToolRadius = 0.003;
    engine::ToolSettings carve;
    carve.tool.radius = kToolRadius;  // the engine carves the haptic tool's own sphere
    ASSERT_TRUE(e.setTool(carve).get().ok);

    sim::SimulatedStylus stylus(sim::readHand(std::string(KIZAMU_SOURCE_DIR) + "/examples/slide_and_carve.hand.jsonl"));
    haptics::ProxySettings ps;
    ps.toolRadius = kToolRadius;
    haptics::ProxyRenderer renderer(stylus.spec(), test::kPeriod, ps);
    haptics::EngineHapticClient client(e.snapshots(), e.samples(), renderer);
    haptics::ServoTicker ticker(stylus, client, 1.0 / test::kPeriod);
    const int64_t periodNs = ticker.periodNs();
    ticker.begin(0);
    std::vector<glm::dvec3> carvedPath;
    double worstForce = 0.0;
    bool touched = false;
    const int ticks = int(stylus.hand().duration() / test::kPeriod) + 200;
    for (int i = 0; i < ticks; ++i) {
        ticker.step(int64_t(i) * periodNs);
        const haptics::ProxyOutput& out = client.last();
        ASSERT_TRUE(std::isfinite(out.force.x + out.force.y + out.force.z)) << "tick " << i;
        worstForce = std::max(worstForce, glm::length(out.force));
        touched = touched || out.contact;
        haptics::DeviceState st;
        stylus.read(st);
        if ((st.buttons & engine::kButtonPrimary) && out.contact) carvedPath.push_back(out.proxy);
        stylus.step(test::kPeriod);
        if (i % 50 == 0) e.sync().get();  // let the engine keep up, as a real one does at 1 kHz
    }
    while (!e.samples().flush()) std::this_thread::yield();
    ASSERT_TRUE(e.sync().get().ok);
    EXPECT_TRUE(touched);
    EXPECT_LE(worstForce, renderer.maxForce() + 1e-9);
    EXPECT_EQ(client.refusedSamples(), 0u);
    EXPECT_EQ(e.stats().strokes, 1u) << "the hand's carve press is one stroke";
    ASSERT_GT(carvedPath.size(), 20u);
    // The published clay is carved where the proxy went while carving: each point of that path
    // is outside the clay now, by about the tool radius (within a few cells).
    adf::SnapshotStore::Reader reader(e.snapshots());
    const auto guard = reader.acquire();
    const double h = guard.adf().domain().finestCellSize();
    int inside = 0;
    for (const glm::dvec3& p : carvedPath)
        if (double(guard.adf().distance(glm::vec3(p))) < kToolRadius - 2.0 * h) ++inside;
    EXPECT_EQ(inside, 0) << "of " << carvedPath.size() << " carving proxy positions";
    // And the proxy advanced into the material: a touching proxy's centre sits a tool radius
    // above the start sphere; while carving it went below that sphere's surface.
    double deepest = 1.0;
    for (const glm::dvec3& p : carvedPath) deepest = std::min(deepest, glm::length(p) - test::kSphereRadius);
    std::printf("[ haptic ] %zu carving ticks; the proxy went %.2f mm past the touching level\n", carvedPath.size(),
                (kToolRadius - deepest) * 1e3);
    EXPECT_LT(deepest, 0.0) << "the proxy advanced into the clay";
}

}  // namespace
}  // namespace kizamu
