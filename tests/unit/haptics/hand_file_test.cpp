// SPDX-License-Identifier: Apache-2.0
// Hand files (sim/hand_file.h, docs/HAND.md) and the Hand they give (sim/hand.h): the examples
// load and drive the stylus and the renderer; text round-trips; interpolation; every malformed
// file gives one line naming the file and the line.
#include "sim/hand_file.h"
#include "tests/unit/haptics/lockstep.h"

#include "util/file_error.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace kizamu {
namespace {

const std::string kExamples = std::string(KIZAMU_SOURCE_DIR) + "/examples/";

TEST(HandFile, TheExamplesLoadAndDriveTheStylus) {
    for (const char* name : {"press_sphere.hand.jsonl", "slide_and_carve.hand.jsonl"}) {
        const sim::Hand hand = sim::readHand(kExamples + name);
        ASSERT_GE(hand.waypoints.size(), 5u) << name;
        for (std::size_t i = 1; i < hand.waypoints.size(); ++i) EXPECT_GE(hand.waypoints[i].t, hand.waypoints[i - 1].t);
        // On the sphere they were written for, with a 3 mm tool: the presses are felt, the tool
        // stays out of the clay unless carving, and every force is finite and within the maximum.
        haptics::ProxySettings ps;
        ps.toolRadius = 0.003;
        test::Rig rig(hand, test::sphereClay(), ps);
        const double contact = test::kSphereRadius + ps.toolRadius, eps = test::surfaceError(*rig.clay);
        int contacts = 0, carving = 0;
        const int ticks = int(std::lround(hand.duration() / test::kPeriod)) + 100;
        for (int i = 0; i < ticks; ++i) {
            const haptics::ProxyOutput& out = rig.tick();
            ASSERT_TRUE(std::isfinite(glm::length(out.force)));
            ASSERT_LE(glm::length(out.force), rig.renderer.maxForce());
            contacts += out.contact ? 1 : 0;
            // Carving lets the proxy into the clay; after it, the proxy settles back out.
            if (rig.state.buttons & 1u) {
                ++carving;
            } else if (!out.settling) {
                EXPECT_GE(glm::length(out.proxy), contact - eps - 1e-5) << name << " tick " << i;
            }
        }
        EXPECT_GT(contacts, 300) << name;
        if (std::string(name).find("carve") != std::string::npos) {
            EXPECT_GT(carving, 500);
        }
        EXPECT_FALSE(rig.last.contact) << name << " ends in free space";
    }
}

TEST(HandFile, RoundTripsAndInterpolates) {
    sim::Hand h;
    h.add(0.0, {0.1, -0.2, 0.3});
    h.add(0.5, {0.2, -0.2, 0.1}, 1u);
    h.add(0.5, {0.2, -0.2, 0.1}, 3u);
    h.add(2.0 + 1.0 / 3.0, {0.0, 0.0, 0.0});  // numbers that need 16-17 digits
    const sim::Hand back = sim::parseHand(sim::formatHand(h), "mem");
    ASSERT_EQ(back.waypoints.size(), h.waypoints.size());
    for (std::size_t i = 0; i < h.waypoints.size(); ++i) {
        EXPECT_EQ(back.waypoints[i].t, h.waypoints[i].t);
        EXPECT_EQ(back.waypoints[i].position, h.waypoints[i].position);
        EXPECT_EQ(back.waypoints[i].buttons, h.waypoints[i].buttons);
    }
    // Before, between, at a jump, after.
    EXPECT_EQ(h.at(-1.0).position, glm::dvec3(0.1, -0.2, 0.3));
    EXPECT_EQ(h.at(-1.0).velocity, glm::dvec3(0.0));
    const sim::HandPose mid = h.at(0.25);
    EXPECT_NEAR(mid.position.x, 0.15, 1e-15);
    EXPECT_NEAR(mid.velocity.x, 0.2, 1e-12);
    EXPECT_EQ(mid.buttons, 0u);
    EXPECT_EQ(h.at(0.5).buttons, 3u) << "the later of two waypoints at one time";
    EXPECT_EQ(h.at(5.0).position, glm::dvec3(0.0));
    EXPECT_EQ(h.at(5.0).velocity, glm::dvec3(0.0));
    // Omitted fields repeat.
    const sim::Hand omitted = sim::parseHand("{\"kizamu_hand\": 1}\n{\"t\": 0, \"p\": [1, 2, 3], \"b\": 2}\n{\"t\": 1}\n", "mem");
    ASSERT_EQ(omitted.waypoints.size(), 2u);
    EXPECT_EQ(omitted.waypoints[1].position, glm::dvec3(1, 2, 3));
    EXPECT_EQ(omitted.waypoints[1].buttons, 2u);
}

TEST(HandFile, MalformedFilesGiveOneLineErrorsWithFileAndLine) {
    const std::string header = "{\"kizamu_hand\": 1, \"units\": \"m\"}\n";
    const std::string ok = "{\"t\": 0, \"p\": [0, 0, 0]}\n";
    struct Case {
        std::string text, expect, also = {};
    };
    const Case cases[] = {
        {header + ok + "{\"t\": 0.1, \"p\": [0, 0,]}\n", "bad.hand.jsonl: line 3: "},            // bad JSON
        {header + ok + "{\"t\": 0.5, \"p\": [0, 0, 0]}\n{\"t\": 0.4}\n", "line 4: time goes backwards"},
        // Non-finite numbers: JSON has no NaN or Inf, and the parser refuses an overflow itself.
        {header + ok + "{\"t\": 1, \"p\": [0, 1e999, 0]}\n", "line 3: ", "1e999"},
        {header + "{\"t\": 1e999, \"p\": [0, 0, 0]}\n", "line 2: ", "1e999"},
        {header + "{\"t\": -1, \"p\": [0, 0, 0]}\n", "line 2: \"t\" is negative"},
        {header + "{\"t\": 0, \"p\": [0, 0]}\n", "line 2: \"p\" must be [x, y, z]"},
        {header + "{\"t\": 0}\n", "line 2: the first waypoint needs \"p\""},
        {header + "{\"p\": [0, 0, 0]}\n", "line 2: a waypoint needs \"t\""},
        {header + ok + "{\"t\": 1, \"b\": -1}\n", "line 3: \"b\" must be an integer"},
        {header + ok + "{\"t\": 1, \"q\": [1, 0, 0, 0]}\n", "line 3: unknown field \"q\""},
        {"{\"kizamu_hand\": 2}\n" + ok, "line 1: hand file version 2 is not supported"},
        {"{\"kizamu_hand\": 1, \"units\": \"mm\"}\n" + ok, "line 1: \"units\" must be \"m\""},
        {"\n# a comment\n" + ok, "line 3: not a Kizamu hand file"},
        {"# nothing\n", "bad.hand.jsonl: not a Kizamu hand file"},
        {header, "bad.hand.jsonl: no waypoints"},
    };
    for (const Case& c : cases) {
        try {
            sim::parseHand(c.text, "bad.hand.jsonl");
            ADD_FAILURE() << "accepted: " << c.text;
        } catch (const FileError& e) {
            const std::string what = e.what();
            EXPECT_EQ(what.rfind("bad.hand.jsonl: ", 0), 0u) << what;
            EXPECT_NE(what.find(c.expect), std::string::npos) << what << "\n  expected: " << c.expect;
            EXPECT_NE(what.find(c.also), std::string::npos) << what << "\n  expected: " << c.also;
            EXPECT_EQ(what.find('\n'), std::string::npos) << "one line: " << what;
        }
    }
    EXPECT_THROW(sim::readHand(kExamples + "no_such.hand.jsonl"), FileError);
}

}  // namespace
}  // namespace kizamu
