// SPDX-License-Identifier: Apache-2.0
// The stroke edit's promise to regeneration: wherever it says the old field stands
// (unchangedRange), it answers the old field exactly, for every tool, shape, turn, mask and
// mirror.
#include "sculpt/stroke_edit.h"

#include "adf/adf_source.h"
#include "adf/distance_source.h"
#include "adf/generate.h"

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace kizamu::sculpt {
namespace {

/// A unit domain at level 6 in 8-cell tiles, and a snapshot of a sphere in it (the old field
/// the lattice tests edit).
adf::Domain smallDomain() {
    adf::Domain d;
    d.originWorld = glm::dvec3(0.0);
    d.maxLevel = 6;
    d.tileSpanLevels = 3;
    return d;
}
adf::AdfPtr sphereSnapshot(const adf::Domain& d) {
    return adf::generate(*adf::makeTranslated(adf::makeSphere(0.3), glm::dvec3(0.5)), d, adf::GenerationSettings{});
}

glm::dquat randomRotation(std::mt19937_64& rng) {
    std::normal_distribution<double> n(0.0, 1.0);
    return glm::normalize(glm::dquat(n(rng), n(rng), n(rng), n(rng)));
}

TEST(StrokeEdit, AnswersTheOldFieldWhereverItSaysItStands) {
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const double cell = 1.0 / 512.0;
    // The old field: a wavy union of shapes, so old values vary across every ball.
    const adf::SourcePtr old = adf::makeCsg(
        adf::CsgOp::Union, adf::makeTranslated(adf::makeSphere(0.2), glm::dvec3(0.5, 0.5, 0.4)),
        adf::makeTranslated(adf::makeBox(glm::dvec3(0.3, 0.3, 0.05)), glm::dvec3(0.5, 0.5, 0.6)));
    const glm::dvec3 centre(0.5);
    int kept = 0, checked = 0, turningKept = 0;
    for (int trial = 0; trial < 240; ++trial) {
        Tool tool;
        tool.shape = ToolShape(trial % 3);
        tool.op = ToolOp(trial / 3 % 6);  // carve, add, build, heat gun, smooth, flatten
        tool.radius = 0.02 + 0.04 * u(rng);
        tool.halfLength = 0.02 + 0.04 * u(rng);
        tool.strength = 0.5 + 0.5 * u(rng);
        tool.amount = 3.0 * cell;
        tool.rate = 0.01;
        const bool turning = trial % 2 == 1;
        std::vector<ToolSample> samples;
        const glm::dvec3 start(0.3 + 0.4 * u(rng), 0.3 + 0.4 * u(rng), 0.55 + 0.1 * u(rng));
        const glm::dquat q0 = randomRotation(rng);
        for (int k = 0; k < 4; ++k)
            samples.push_back({start + 0.03 * double(k) * glm::dvec3(1.0, 0.5, -0.2), turning ? randomRotation(rng) : q0});
        const auto swept = makeSweptTool(tool, samples);
        ToolLimits limits;
        if (trial % 5 == 0) limits.masks.push_back(adf::makeTranslated(adf::makeSphere(0.04), start));
        const auto reflect = uint8_t(trial % 4 == 0 ? 1 : 0);
        const adf::SourcePtr edit = makeStrokeEdit(old, swept, reflect, centre, 3.0 * cell, limits, cell);
        for (int b = 0; b < 40; ++b) {
            // Balls of 1 to 16 cells, near the tool or its mirror image.
            const double radius = cell * std::exp2(4.0 * u(rng));
            glm::dvec3 c = start + (0.12 * glm::dvec3(u(rng), u(rng), u(rng)) - 0.06);
            if (reflect && u(rng) < 0.5) c.x = 2.0 * centre.x - c.x;
            const adf::DistanceSource::Range range = edit->unchangedRange(c, radius);
            if (range.lo > range.hi) continue;
            ++kept;
            if (turning && tool.shape != ToolShape::Sphere) ++turningKept;
            for (int k = 0; k < 20; ++k) {
                glm::dvec3 d(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5);
                const glm::dvec3 p = c + radius * u(rng) * glm::normalize(d);
                const double was = old->distance(p);
                if (was < range.lo || was > range.hi) continue;
                ++checked;
                ASSERT_EQ(edit->distance(p), was) << "trial " << trial << " ball " << b;
            }
        }
    }
    EXPECT_GT(kept, 2000);
    EXPECT_GT(checked, 20000);
    EXPECT_GT(turningKept, 100) << "turning cubes and cylinders keep cells too (a box bound, no search)";
}

TEST(StrokeEdit, AtLatticePointsAnswersWhatItAnswersAtTheirWorldPositions) {
    // An edit of a snapshot is asked for lattice points (the generator's cheaper way); it must
    // give the same bits as at the points' world positions, for every tool and a mask.
    const adf::Domain d = smallDomain();
    const adf::SourcePtr old = adf::makeAdfSource(sphereSnapshot(d));
    ASSERT_TRUE(old->answersLattice(d));
    adf::Domain other = d;
    other.maxLevel = 7;
    EXPECT_FALSE(old->answersLattice(other)) << "another lattice goes through world positions";
    std::mt19937_64 rng(9);
    std::uniform_int_distribution<uint32_t> at(0, d.latticeSize());
    int compared = 0;
    for (int op = 0; op < 6; ++op) {
        Tool tool;
        tool.shape = ToolShape(op % 3);
        tool.op = ToolOp(op);
        tool.radius = 0.08;
        tool.halfLength = 0.05;
        tool.amount = 0.02;
        tool.rate = 0.01;
        const auto swept = makeSweptTool(tool, {{glm::dvec3(0.5, 0.5, 0.8), glm::dquat(1.0, 0.0, 0.0, 0.0)},
                                                {glm::dvec3(0.6, 0.5, 0.75), glm::dquat(1.0, 0.0, 0.0, 0.0)}});
        ToolLimits limits;
        if (op == 0) limits.masks.push_back(adf::makeTranslated(adf::makeSphere(0.05), glm::dvec3(0.55, 0.5, 0.8)));
        const adf::SourcePtr edit = makeStrokeEdit(old, swept, uint8_t(op == 1 ? 1 : 0), glm::dvec3(0.5), 0.01, limits, d.finestCellSize());
        ASSERT_TRUE(edit->answersLattice(d));
        std::vector<glm::uvec3> lattice(500);
        std::vector<glm::dvec3> world(lattice.size());
        for (std::size_t i = 0; i < lattice.size(); ++i) {
            lattice[i] = {at(rng), at(rng), at(rng)};
            if (i % 2) lattice[i].z = d.latticeSize() * 3 / 4 + lattice[i].z % 8;  // many near the tool
            world[i] = d.latticeToWorld(lattice[i].x, lattice[i].y, lattice[i].z);
        }
        std::vector<double> byLattice(lattice.size()), byWorld(lattice.size());
        edit->latticeDistances(d, lattice, byLattice);
        edit->distances(world, byWorld);
        for (std::size_t i = 0; i < lattice.size(); ++i, ++compared) ASSERT_EQ(byLattice[i], byWorld[i]) << "op " << op << " point " << i;
    }
    EXPECT_EQ(compared, 3000);
}

TEST(StrokeEdit, PlainCarvesAndAdditionsInRunsAnswerWhatEachPointAnswers) {
    // A carve or an addition with neither symmetry nor limits asks the tool for a run of points
    // at once (the common dab); it must give what combining point by point gives.
    const adf::Domain d = smallDomain();
    const adf::SourcePtr old = adf::makeAdfSource(sphereSnapshot(d));
    std::mt19937_64 rng(13);
    std::uniform_int_distribution<uint32_t> at(0, d.latticeSize());
    const glm::dquat turned = glm::angleAxis(0.7, glm::normalize(glm::dvec3(1.0, 2.0, 0.5)));
    int changed = 0;
    for (int c = 0; c < 16; ++c) {
        Tool tool;
        tool.shape = c % 8 == 7 ? ToolShape::Cube : ToolShape::Sphere;  // and one shape the run does not take directly
        tool.op = c % 2 ? ToolOp::Add : ToolOp::Carve;
        tool.radius = 0.08;
        tool.strength = c % 4 < 2 ? 1.0 : 0.6;
        const glm::dquat o = c % 8 < 4 ? glm::dquat(1.0, 0.0, 0.0, 0.0) : turned;
        std::vector<ToolSample> samples{{glm::dvec3(0.5, 0.5, 0.8), o}};
        if (c >= 8) samples.push_back({glm::dvec3(0.6, 0.5, 0.75), o});  // a straight stroke: a capsule
        const adf::SourcePtr edit = makeStrokeEdit(old, makeSweptTool(tool, samples), 0, glm::dvec3(0.5), 0.0, {}, d.finestCellSize());
        std::vector<glm::uvec3> lattice(300);
        std::vector<glm::dvec3> world(lattice.size());
        for (std::size_t i = 0; i < lattice.size(); ++i) {
            lattice[i] = {at(rng), at(rng), at(rng)};
            if (i % 2) lattice[i] = glm::uvec3(d.latticeSize() / 2 + at(rng) % 12, d.latticeSize() / 2 + at(rng) % 12, d.latticeSize() * 3 / 4 + at(rng) % 8);  // at the tool
            world[i] = d.latticeToWorld(lattice[i].x, lattice[i].y, lattice[i].z);
        }
        std::vector<double> inRuns(lattice.size()), oldValues(lattice.size());
        edit->latticeDistances(d, lattice, inRuns);
        old->latticeDistances(d, lattice, oldValues);
        for (std::size_t i = 0; i < lattice.size(); ++i) {
            ASSERT_EQ(inRuns[i], edit->distance(world[i])) << "case " << c << " point " << i;
            changed += inRuns[i] != oldValues[i];
        }
    }
    EXPECT_GT(changed, 300) << "the tool decided too few points to test its runs";
}

}  // namespace
}  // namespace kizamu::sculpt
