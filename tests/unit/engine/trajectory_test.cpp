// SPDX-License-Identifier: Apache-2.0
/// @file trajectory_test.cpp
/// @brief Trajectory files: the round trip bit for bit (awkward doubles, floats, times, tools),
/// omitted fields repeating, records kept in order (equal times in file order), warnings for
/// unknown keys, a one-line error naming the line for each malformed case, and the examples in
/// examples/ parsing and being exactly what their generator writes.
#include "engine/trajectory.h"
#include "tests/util/example_trajectories.h"
#include "util/atomic_file.h"
#include "util/file_error.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace kizamu::engine {
namespace {

template <class T>
bool sameBits(const T& a, const T& b) {
    static_assert(std::is_trivially_copyable_v<T>);
    return std::memcmp(&a, &b, sizeof(T)) == 0;
}

void expectSameSample(const ToolSample& a, const ToolSample& b, std::size_t i) {
    EXPECT_EQ(a.timeNs, b.timeNs) << "sample " << i;
    for (int k = 0; k < 3; ++k) EXPECT_TRUE(sameBits(a.posWorld[k], b.posWorld[k])) << "sample " << i << " p" << k;
    EXPECT_TRUE(sameBits(a.orientation, b.orientation)) << "sample " << i;
    EXPECT_TRUE(sameBits(a.strength, b.strength)) << "sample " << i;
    EXPECT_EQ(a.buttons, b.buttons) << "sample " << i;
}

/// Samples with awkward values: doubles of every magnitude and both zeros, random unit
/// quaternions, strengths 0, 1 and in between, every button bit, equal and odd times.
Trajectory awkward() {
    Trajectory t;
    t.device = "test \"rig\" \\ 1";
    t.start = examples::testPartStart(8);
    std::mt19937_64 rng(31);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    std::uniform_int_distribution<int> exponent(-300, 300);
    const double specials[] = {0.0, -0.0, 1.0, -1.0, 0.1, 1e-320, -5e-324, 1.7976931348623157e308, 123456789012345680000.0,
                               -9007199254740993.0, 18446744073709551616.0, 0.30000000000000004};
    int64_t ns = 0;
    for (int i = 0; i < 600; ++i) {
        ToolSample s;
        ns += i % 7 == 0 ? 0 : int64_t(rng() % 3'000'000'000ull);  // equal times too
        s.timeNs = ns;
        for (int k = 0; k < 3; ++k)
            s.posWorld[k] = i < 36 ? specials[(i + k) % 12] : std::ldexp(unit(rng), exponent(rng) / (i % 3 == 0 ? 1 : 100));
        if (i % 4 != 0) {
            const glm::dquat q = glm::normalize(glm::dquat(unit(rng), unit(rng), unit(rng), unit(rng)));
            s.orientation = glm::quat(float(q.w), float(q.x), float(q.y), float(q.z));
        } else if (i % 8 == 0) {
            s.orientation = glm::quat(-0.0f, 1.0f, 0.0f, -0.0f);
        }
        s.strength = i % 5 == 0 ? 0.0f : i % 5 == 1 ? 1.0f : float(std::abs(unit(rng)));
        s.buttons = i % 11 == 0 ? 0xFFFF'FFFFu : uint32_t(rng() & 7u);
        t.add(s);
        if (i % 97 == 0) {
            ToolChange c = examples::toolChange(ns, sculpt::ToolOp::Paint, sculpt::ToolShape::Sphere, 0.0123456789);
            c.tool.colour = {1, 2, 250};
            c.tool.strength = 0.3;
            c.mirror = 5;
            t.add(c);
        }
        if (i % 131 == 0) t.add(CommandEvent{ns, TrajectoryCommand(i / 131 % 3)});
    }
    ns += 1;  // odd nanoseconds and the largest time
    ToolChange cyl = examples::toolChange(ns, sculpt::ToolOp::Carve, sculpt::ToolShape::Cylinder, 0.004);
    cyl.tool.halfLength = 0.0101;
    cyl.constraints.followOffset = -0.002;
    cyl.constraints.depthLimit = 0.003;
    sculpt::Shape mask;
    mask.kind = sculpt::Shape::Kind::Sphere;
    mask.centre = glm::dvec3(0.1, 0.2, 0.3);
    mask.radius = 0.05;
    cyl.constraints.masks.push_back(mask);
    cyl.constraints.keepOut.push_back(mask);
    t.add(cyl);
    ToolSample last = t.samples.back();
    last.timeNs = int64_t(kTrajectoryMaxSeconds * 1e9);
    t.add(last);
    return t;
}

void expectSame(const Trajectory& a, const Trajectory& b) {
    ASSERT_EQ(a.events.size(), b.events.size());
    ASSERT_EQ(a.samples.size(), b.samples.size());
    ASSERT_EQ(a.toolChanges.size(), b.toolChanges.size());
    ASSERT_EQ(a.commands.size(), b.commands.size());
    EXPECT_EQ(a.device, b.device);
    ASSERT_EQ(a.start.has_value(), b.start.has_value());
    if (a.start) {
        EXPECT_EQ(a.start->domain.maxLevel, b.start->domain.maxLevel);
        EXPECT_EQ(a.start->domain.sizeWorld, b.start->domain.sizeWorld);
        EXPECT_EQ(a.start->shape.kind, b.start->shape.kind);
    }
    for (std::size_t i = 0; i < a.events.size(); ++i) {
        EXPECT_EQ(a.events[i].kind, b.events[i].kind) << "event " << i;
        EXPECT_EQ(a.events[i].index, b.events[i].index) << "event " << i;
    }
    for (std::size_t i = 0; i < a.samples.size(); ++i) expectSameSample(a.samples[i], b.samples[i], i);
    for (std::size_t i = 0; i < a.toolChanges.size(); ++i) {
        const ToolChange& x = a.toolChanges[i];
        const ToolChange& y = b.toolChanges[i];
        EXPECT_EQ(x.timeNs, y.timeNs);
        EXPECT_EQ(x.tool.op, y.tool.op);
        EXPECT_EQ(x.tool.shape, y.tool.shape);
        EXPECT_TRUE(sameBits(x.tool.radius, y.tool.radius));
        EXPECT_TRUE(sameBits(x.tool.strength, y.tool.strength));
        if (x.tool.shape == sculpt::ToolShape::Cylinder) {
            EXPECT_TRUE(sameBits(x.tool.halfLength, y.tool.halfLength));
        }
        if (x.tool.op == sculpt::ToolOp::Paint) {
            EXPECT_EQ(x.tool.colour, y.tool.colour);
        }
        EXPECT_EQ(x.mirror, y.mirror);
        EXPECT_EQ(x.constraints.followOffset, y.constraints.followOffset);
        EXPECT_EQ(x.constraints.depthLimit, y.constraints.depthLimit);
        EXPECT_EQ(x.constraints.heightLimit, y.constraints.heightLimit);
        EXPECT_EQ(x.constraints.masks.size(), y.constraints.masks.size());
        EXPECT_EQ(x.constraints.keepOut.size(), y.constraints.keepOut.size());
    }
    for (std::size_t i = 0; i < a.commands.size(); ++i) {
        EXPECT_EQ(a.commands[i].timeNs, b.commands[i].timeNs);
        EXPECT_EQ(a.commands[i].command, b.commands[i].command);
    }
}

TEST(Trajectory, RoundTripIsBitForBit) {
    const Trajectory t = awkward();
    const std::string text = formatTrajectory(t);
    std::vector<std::string> warnings;
    const Trajectory back = parseTrajectory(text, "awkward", &warnings);
    EXPECT_TRUE(warnings.empty()) << warnings.front();
    expectSame(t, back);
    EXPECT_EQ(formatTrajectory(back), text);  // and the text is a fixed point
}

TEST(Trajectory, WriteAndReadAFile) {
    const auto dir = std::filesystem::temp_directory_path() / ("kizamu_trajectory_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    const std::string path = (dir / "t.trajectory.jsonl").string();
    const Trajectory t = awkward();
    writeTrajectory(t, path);
    expectSame(t, readTrajectory(path));
    EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));
    std::filesystem::remove_all(dir);
    EXPECT_THROW(readTrajectory((dir / "missing.jsonl").string()), FileError);
}

TEST(Trajectory, OmittedFieldsRepeatThePreviousSample) {
    const Trajectory t = parseTrajectory(R"({"kizamu_trajectory": 1}
{"t": 0, "p": [1, 2, 3]}
{"t": 0.001, "p": [1, 2, 4], "q": [0, 1, 0, 0], "s": 0.25, "b": 3}
{"t": 0.002}
{"t": 0.003, "cmd": "undo"}
{"t": 0.003, "p": [5, 6, 7], "b": 0}
)",
                                         "omit");
    ASSERT_EQ(t.samples.size(), 4u);
    EXPECT_FALSE(t.start.has_value());
    // Before the first sample: identity, strength 1, no buttons.
    EXPECT_EQ(t.samples[0].orientation, glm::quat(1, 0, 0, 0));
    EXPECT_EQ(t.samples[0].strength, 1.0f);
    EXPECT_EQ(t.samples[0].buttons, 0u);
    EXPECT_EQ(t.samples[2].timeNs, 2'000'000);
    EXPECT_EQ(t.samples[2].posWorld, glm::dvec3(1, 2, 4));
    EXPECT_EQ(t.samples[2].orientation, glm::quat(0, 1, 0, 0));
    EXPECT_EQ(t.samples[2].strength, 0.25f);
    EXPECT_EQ(t.samples[2].buttons, 3u);
    EXPECT_EQ(t.samples[3].posWorld, glm::dvec3(5, 6, 7));
    EXPECT_EQ(t.samples[3].orientation, glm::quat(0, 1, 0, 0));  // across a command too
    EXPECT_EQ(t.samples[3].strength, 0.25f);
    EXPECT_EQ(t.samples[3].buttons, 0u);
    // A non-unit quaternion is normalised.
    const Trajectory n = parseTrajectory("{\"kizamu_trajectory\": 1}\n{\"t\": 0, \"p\": [0, 0, 0], \"q\": [2, 0, 0, 0]}\n", "n");
    EXPECT_EQ(n.samples[0].orientation, glm::quat(1, 0, 0, 0));
}

TEST(Trajectory, ToolChangesAndCommandsStayInOrder) {
    const Trajectory t = parseTrajectory(R"(# comment, then a blank line

{"kizamu_trajectory": 1, "units": "m", "device": "sim", "domain": {"size": 1.0, "level": 9}, "start": {"shape": "test-part"}}
{"t": 0, "tool": {"op": "carve", "shape": "chisel", "radius": 0.01, "length": 0.03, "mirror": "xz", "depth": 0.002}}
{"t": 0, "p": [0.5, 0.5, 0.8], "b": 1}
{"t": 0.5, "p": [0.6, 0.5, 0.8], "b": 0}
{"t": 0.5, "cmd": "undo"}
{"t": 0.5, "cmd": "redo"}
{"t": 0.75, "tool": {"op": "paint", "shape": "sphere", "radius": 0.02, "strength": 0.5, "color": [200, 30, 30]}}
{"t": 1, "cmd": "cancel"}
)",
                                         "order");
    using K = TrajectoryEvent::Kind;
    const std::vector<K> kinds = {K::ToolChange, K::Sample, K::Sample, K::Command, K::Command, K::ToolChange, K::Command};
    ASSERT_EQ(t.events.size(), kinds.size());
    for (std::size_t i = 0; i < kinds.size(); ++i) EXPECT_EQ(t.events[i].kind, kinds[i]) << i;
    EXPECT_EQ(t.device, "sim");
    ASSERT_TRUE(t.start.has_value());
    EXPECT_EQ(t.start->domain.maxLevel, 9);
    EXPECT_EQ(t.start->shape.kind, sculpt::Shape::Kind::TestPart);
    ASSERT_EQ(t.toolChanges.size(), 2u);
    EXPECT_EQ(t.toolChanges[0].tool.shape, sculpt::ToolShape::Cylinder);
    EXPECT_DOUBLE_EQ(t.toolChanges[0].tool.halfLength, 0.015);
    EXPECT_EQ(t.toolChanges[0].mirror, 1 | 4);
    EXPECT_EQ(t.toolChanges[0].constraints.depthLimit, 0.002);
    EXPECT_EQ(t.toolChanges[1].tool.op, sculpt::ToolOp::Paint);
    EXPECT_EQ(t.toolChanges[1].tool.colour, glm::u8vec3(200, 30, 30));
    EXPECT_EQ(t.toolChanges[1].timeNs, 750'000'000);
    ASSERT_EQ(t.commands.size(), 3u);
    EXPECT_EQ(t.commands[0].command, TrajectoryCommand::Undo);
    EXPECT_EQ(t.commands[1].command, TrajectoryCommand::Redo);
    EXPECT_EQ(t.commands[2].command, TrajectoryCommand::Cancel);
    EXPECT_EQ(t.timeNs(t.events.back()), 1'000'000'000);
}

TEST(Trajectory, UnknownKeysAreWarnedOnceAndSkipped) {
    std::vector<std::string> warnings;
    const Trajectory t = parseTrajectory(
        "{\"kizamu_trajectory\": 1, \"rig\": 7}\r\n"
        "{\"t\": 0, \"p\": [0, 0, 0], \"force\": [1, 2, 3]}\r\n"
        "{\"t\": 0.001, \"p\": [0, 0, 0], \"force\": [1, 2, 3]}\r\n"
        "{\"t\": 0.002, \"tool\": {\"op\": \"add\", \"shape\": \"cube\", \"radius\": 0.01, \"hue\": 3}}",  // no final newline
        "warn", &warnings);
    EXPECT_EQ(t.samples.size(), 2u);
    EXPECT_EQ(t.toolChanges.size(), 1u);
    ASSERT_EQ(warnings.size(), 3u);
    EXPECT_EQ(warnings[0], "warn: line 1: unknown key 'rig' ignored");
    EXPECT_EQ(warnings[1], "warn: line 2: unknown key 'force' ignored");
    EXPECT_EQ(warnings[2], "warn: line 4: unknown key 'tool.hue' ignored");
}

struct Malformed {
    const char* record;  ///< line 3, after a header and one good sample
    const char* expect;  ///< part of the message
};

TEST(Trajectory, EachMalformedRecordGivesOneLineNamingIt) {
    const Malformed cases[] = {
        {R"({"t": 0.1, "p": [0, 0, 0])", "parse error"},
        {R"([1, 2])", "must be a JSON object"},
        {R"({"p": [0, 0, 0]})", "missing \"t\""},
        {R"({"t": "soon", "p": [0, 0, 0]})", "t must be a number"},
        {R"({"t": 0.0009, "p": [0, 0, 0]})", "time goes backwards"},
        {R"({"t": -1, "p": [0, 0, 0]})", "outside [0, 1e6] s"},
        {R"({"t": 2e6, "p": [0, 0, 0]})", "outside [0, 1e6] s"},
        {R"({"t": 1e999, "p": [0, 0, 0]})", "overflow"},
        {R"({"t": 0.1, "p": [0, 0]})", "p must be [x, y, z]"},
        {R"({"t": 0.1, "p": [0, 0, null]})", "p must be a number"},
        {R"({"t": 0.1, "p": [0, 0, -1e400]})", "overflow"},
        {R"({"t": 0.1, "q": [0, 0, 0, 0]})", "non-zero quaternion"},
        {R"({"t": 0.1, "q": [1, 0, 0]})", "q must be [w, x, y, z]"},
        {R"({"t": 0.1, "q": [1e300, 1e300, 0, 0]})", "finite length"},
        {R"({"t": 0.1, "s": 1.5})", "within [0, 1]"},
        {R"({"t": 0.1, "s": -0.01})", "within [0, 1]"},
        {R"({"t": 0.1, "b": -1})", "integer bitmask"},
        {R"({"t": 0.1, "b": 1.0})", "integer bitmask"},
        {R"({"t": 0.1, "b": 4294967296})", "integer bitmask"},
        {R"({"t": 0.1, "cmd": "jump"})", "unknown command 'jump'"},
        {R"({"t": 0.1, "cmd": "undo", "p": [0, 0, 0]})", "not several"},
        {R"({"t": 0.1, "tool": {"op": "drill", "shape": "sphere", "radius": 0.01}})", "tool: "},
        {R"({"t": 0.1, "tool": {"op": "carve", "shape": "sphere", "radius": -0.01}})", "tool: "},
        {R"({"t": 0.1, "tool": {"op": "carve", "shape": "sphere"}})", "tool: "},
        {R"({"t": 0.1, "tool": {"op": "paint", "shape": "sphere", "radius": 0.01}})", "color"},
        {R"({"t": 0.1, "tool": {"op": "carve", "shape": "sphere", "radius": 0.01, "path": [[0, 0, 0]]}})", "belongs to"},
        {R"({"t": 0.1, "tool": "sphere"})", "tool must be an object"},
    };
    for (const Malformed& c : cases) {
        const std::string text = std::string("{\"kizamu_trajectory\": 1}\n{\"t\": 0.001, \"p\": [0, 0, 0]}\n") + c.record + "\n";
        try {
            parseTrajectory(text, "bad.jsonl");
            ADD_FAILURE() << "accepted: " << c.record;
        } catch (const FileError& e) {
            const std::string m = e.what();
            EXPECT_EQ(m.rfind("bad.jsonl: line 3: ", 0), 0u) << m;
            EXPECT_NE(m.find(c.expect), std::string::npos) << c.record << " -> " << m;
            EXPECT_EQ(m.find('\n'), std::string::npos) << m;
        }
    }
}

TEST(Trajectory, MalformedHeadersAreRejected) {
    const Malformed cases[] = {
        {R"({"kizamu_trajectory": 2})", "version 2 is not supported (this build reads 1)"},
        {R"({"kizamu_trajectory": 4294967297})", "not supported"},
        {R"({"kizamu_trajectory": "1"})", "an integer"},
        {R"({"kizamu_trajectory": 1, "units": "mm"})", "units \"mm\" are not supported"},
        {R"({"kizamu_trajectory": 1, "start": {"shape": "test-part"}})", "come together"},
        {R"({"kizamu_trajectory": 1, "domain": {"size": 1}, "start": {"shape": "torus"}})", "unknown shape 'torus'"},
        {R"({"kizamu_trajectory": 1, "domain": {"size": -1}, "start": {"shape": "test-part"}})", "invalid domain"},
        {R"({"t": 0, "p": [0, 0, 0]})", "not a Kizamu trajectory"},
    };
    for (const Malformed& c : cases) {
        try {
            parseTrajectory(std::string("# a comment\n") + c.record + "\n", "bad.jsonl");
            ADD_FAILURE() << "accepted: " << c.record;
        } catch (const FileError& e) {
            const std::string m = e.what();
            EXPECT_EQ(m.rfind("bad.jsonl: line 2: ", 0), 0u) << m;
            EXPECT_NE(m.find(c.expect), std::string::npos) << c.record << " -> " << m;
            EXPECT_EQ(m.find('\n'), std::string::npos) << m;
        }
    }
    EXPECT_THROW(parseTrajectory("", "empty"), FileError);
    EXPECT_THROW(parseTrajectory("# only a comment\n", "empty"), FileError);
    EXPECT_THROW(parseTrajectory("{\"kizamu_trajectory\": 1}\n{\"t\": 0}\n", "nop"), FileError);  // first sample needs p
}

TEST(Trajectory, WriterRefusesWhatCannotReadBack) {
    Trajectory t;
    ToolSample s;
    s.timeNs = 5;
    t.add(s);
    s.timeNs = 4;
    t.add(s);
    EXPECT_THROW(formatTrajectory(t), std::invalid_argument);
    t = {};
    s.posWorld.x = std::numeric_limits<double>::quiet_NaN();
    t.add(s);
    EXPECT_THROW(formatTrajectory(t), std::invalid_argument);
    t = {};
    s.posWorld.x = 0.0;
    s.strength = 2.0f;
    t.add(s);
    EXPECT_THROW(formatTrajectory(t), std::invalid_argument);
}

TEST(Trajectory, ExamplesParseAndAreWhatTheGeneratorWrites) {
    struct Example {
        const char* file;
        Trajectory trajectory;
    };
    const Example all[] = {{"carve_line.trajectory.jsonl", examples::carveLine()},
                           {"sculpt_session.trajectory.jsonl", examples::sculptSession()}};
    const bool rewrite = std::getenv("KIZAMU_WRITE_EXAMPLES") != nullptr;
    for (const Example& e : all) {
        const std::string path = std::string(KIZAMU_SOURCE_DIR) + "/examples/" + e.file;
        if (rewrite) writeTrajectory(e.trajectory, path);
        std::vector<std::string> warnings;
        const Trajectory read = readTrajectory(path, &warnings);
        EXPECT_TRUE(warnings.empty()) << e.file;
        expectSame(e.trajectory, read);
        const std::string text = util::readWholeFile(path);
        EXPECT_EQ(text, formatTrajectory(e.trajectory)) << e.file << " differs from its generator's output";
        EXPECT_LT(text.size(), 300u * 1024u) << e.file;
        ASSERT_TRUE(read.start.has_value());
        EXPECT_EQ(read.start->shape.kind, sculpt::Shape::Kind::TestPart);
    }
    const Trajectory line = readTrajectory(std::string(KIZAMU_SOURCE_DIR) + "/examples/carve_line.trajectory.jsonl");
    ASSERT_EQ(line.samples.size(), 2001u);
    EXPECT_EQ(line.samples.back().timeNs, 2'000'000'000);
    EXPECT_DOUBLE_EQ(line.samples.back().posWorld.x - line.samples.front().posWorld.x, 0.2);  // 10 cm/s for 2 s
    EXPECT_DOUBLE_EQ(line.toolChanges.at(0).tool.radius, 0.01);
    const Trajectory session = readTrajectory(std::string(KIZAMU_SOURCE_DIR) + "/examples/sculpt_session.trajectory.jsonl");
    EXPECT_EQ(session.toolChanges.size(), 6u);
    EXPECT_EQ(session.commands.size(), 4u);
}

}  // namespace
}  // namespace kizamu::engine
