// SPDX-License-Identifier: Apache-2.0
// Passivity of the rendered wall (haptics/proxy_renderer.h) on the simulated stylus in lock
// step: press-and-return cycles against the box's top face, with the energy the rendering puts
// into the device measured over each cycle.
//
// What is measured, and why this and not the rendered force's work alone: a wall sampled at T
// and held (zero-order hold) pushes back with the penetration of up to T ago, so on a
// press-and-return cycle its force alone always returns a little more than it took, about
// (K T / 2) times the integral of v^2 over the contact. That is what the device's physical
// damping b is there to absorb, and the passivity bound b > K T / 2 + |B| (Colgate and
// Schenkel; haptics/device.h) says exactly when it does. So the energy put into the device by
// the rendering, over a cycle, is the rendered force's work plus the work of the physical
// damping while the force acts (SimulatedStylus's energy().rendered - energy().dampedUnderForce):
// positive means the wall feeds energy in and grows a limit cycle on a real device.
#include "haptics/proxy_renderer.h"
#include "tests/unit/haptics/lockstep.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

namespace kizamu {
namespace {

using haptics::ProxySettings;
using test::kPeriod;
using test::Rig;

constexpr double kCycle = 0.25;    ///< s per press-and-return cycle
constexpr double kStart = 0.3;     ///< s at rest before the first
/// J: what "not positive" allows per cycle. The integrator's accounting is exact (each figure is
/// the work of the forces it applied), so this covers only rounding over ~10^4 substeps of
/// ~10^-5 J terms; a cycle's energies are ~10^-4 J.
constexpr double kTolerance = 1e-9;

/// Cycles of pressing 4 mm into the box's top face and back (0.1 s each way, 50 ms held).
sim::Hand wallCycles(int cycles) {
    const double top = test::kBoxHalf;
    sim::Hand h;
    h.add(0.0, {0.0, 0.0, top + 0.01});
    h.add(kStart, {0.0, 0.0, top + 0.01});
    for (int c = 0; c < cycles; ++c) {
        const double t0 = kStart + kCycle * c;
        h.add(t0 + 0.1, {0.0, 0.0, top - 0.004});
        h.add(t0 + 0.15, {0.0, 0.0, top - 0.004});
        h.add(t0 + kCycle, {0.0, 0.0, top + 0.01});
    }
    return h;
}

/// The energy the rendering put into the device over each cycle, J (rendered work plus the
/// physical damping's work while the force acted), with the wall at `stiffness` (0: what the
/// renderer chooses) and virtual damping `damping`.
std::vector<double> cycleEnergies(int cycles, double stiffness, double damping = 0.0, double* chosen = nullptr) {
    ProxySettings ps;
    ps.damping = damping;
    Rig rig(wallCycles(cycles), test::boxClay(6), ps);
    if (stiffness > 0.0) rig.renderer.setStiffnessUnchecked(stiffness);
    if (chosen) *chosen = rig.renderer.gains().stiffness;
    auto net = [&] { return rig.stylus.energy().rendered - rig.stylus.energy().dampedUnderForce; };
    const int startTicks = int(std::lround(kStart / kPeriod)), cycleTicks = int(std::lround(kCycle / kPeriod));
    for (int i = 0; i < startTicks; ++i) rig.tick();
    EXPECT_EQ(rig.last.force, glm::dvec3(0.0));
    std::vector<double> out;
    int contacts = 0;
    for (int c = 0; c < cycles; ++c) {
        const double before = net();
        for (int i = 0; i < cycleTicks; ++i) contacts += rig.tick().contact ? 1 : 0;
        out.push_back(net() - before);
    }
    EXPECT_GT(contacts, cycles * 50) << "every cycle pressed into the wall";
    EXPECT_EQ(rig.last.force, glm::dvec3(0.0)) << "each cycle ends in free space";
    return out;
}

void print(const char* what, double k, const std::vector<double>& e) {
    double sum = 0.0, most = -1e300;
    for (double v : e) {
        sum += v;
        most = std::max(most, v);
    }
    std::printf("[ passivity ] %s K = %.0f N/m: energy put in per cycle: max %.3g J, total over %zu cycles %.3g J\n", what, k, most,
                e.size(), sum);
}

TEST(ProxyRendererPassivity, AWallWithinTheBoundPutsNoEnergyIntoTheDevice) {
    double k = 0.0;
    const std::vector<double> e = cycleEnergies(20, 0.0, 0.0, &k);  // the renderer's own choice
    print("chosen", k, e);
    double total = 0.0;
    for (std::size_t c = 0; c < e.size(); ++c) {
        EXPECT_LE(e[c], kTolerance) << "cycle " << c;
        total += e[c];
        EXPECT_LE(total, kTolerance) << "grew by cycle " << c;
    }
    // With virtual damping: the bound shrinks to 2 (b - B) / T, and the renderer keeps to it.
    double kDamped = 0.0;
    const std::vector<double> damped = cycleEnergies(10, 0.0, 0.5, &kDamped);
    print("damped B = 0.5", kDamped, damped);
    for (std::size_t c = 0; c < damped.size(); ++c) EXPECT_LE(damped[c], kTolerance) << "cycle " << c;
}

TEST(ProxyRendererPassivity, AWallPastTheBoundPutsEnergyIn) {
    // The same cycles with the stiffness 1.5x the bound (only the test-only setter allows it):
    // each cycle puts energy in, and it adds up.
    const std::vector<double> e = cycleEnergies(20, 1.5 * 4000.0);
    print("1.5x the bound", 6000.0, e);
    double total = 0.0;
    int positive = 0;
    for (double v : e) {
        total += v;
        positive += v > kTolerance ? 1 : 0;
    }
    EXPECT_GT(total, 1000.0 * kTolerance);
    EXPECT_GE(positive, 15) << "most cycles put energy in";
    // Exactly at the bound the first-order leak (K T / 2) and the damping (b) cancel, and what is
    // left is the unilateral contact's share (entering and leaving the wall within a period):
    // small and of either sign, which is why the renderer keeps to kPassivitySafety of the bound.
    const std::vector<double> atBound = cycleEnergies(20, 4000.0);
    print("exactly at the bound", 4000.0, atBound);
    double totalAtBound = 0.0;
    for (double v : atBound) totalAtBound += v;
    EXPECT_LT(totalAtBound, 0.25 * total) << "far less than past the bound";
}

}  // namespace
}  // namespace kizamu
