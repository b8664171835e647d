// SPDX-License-Identifier: Apache-2.0
// Live strokes in the journal (stroke script version 3): a stroke applied live in uneven
// segments through a Session is one journal record, and reopening the session (replay of the
// live record) reaches the live clay bit for bit, for every tool that segments, mirrored and
// following the surface; undo after reopening returns the snapshot before each stroke. The live
// record round-trips through the script text bit for bit, version 1 and 2 scripts cannot hold
// one, validate() checks each of its rules, a journal write failure cancels the stroke, an
// in-memory session writes nothing, and checkpoints written on another thread reopen the same.
#include "sculpt/session.h"

#include "sculpt/script_start.h"
#include "sculpt/stroke_script.h"
#include "tests/util/adf_compare.h"
#include "util/atomic_file.h"
#include "util/file_error.h"

#include <glm/common.hpp>
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <limits>
#include <span>
#include <stdexcept>
#include <string>
#include <thread>
#include <unistd.h>
#include <vector>

namespace kizamu {
namespace {

using namespace sculpt;
namespace fs = std::filesystem;

const glm::dquat kIdentity(1.0, 0.0, 0.0, 0.0);

Script slab() {
    Script s;
    s.domain.maxLevel = 6;
    s.domain.tileSpanLevels = 3;
    s.start.kind = Shape::Kind::Box;  // top face at z = 0.5
    s.start.centre = {0.5, 0.5, 0.4};
    s.start.halfSize = {0.35, 0.35, 0.1};
    return s;
}

std::vector<ToolSample> curve(glm::dvec3 a, glm::dvec3 b, int n, double bend) {
    std::vector<ToolSample> out;
    for (int i = 0; i < n; ++i) {
        const double t = double(i) / (n - 1);
        out.push_back({glm::mix(a, b, t) + glm::dvec3(0.0, bend * 4.0 * t * (1.0 - t), 0.0), kIdentity});
    }
    return out;
}

/// A stroke and how to apply it live: the header's poses, then one extendStroke per segment
/// (end index into the poses, dwell); `leadingDwell` is a dwell-only call before any pose.
struct LiveCase {
    std::string name;
    Stroke stroke;        ///< tool, constraints, mirror, every pose (dwell unused)
    std::size_t header = 0;
    double headerDwell = 0.0;
    double leadingDwell = 0.0;
    std::vector<std::pair<std::size_t, double>> segments;
};

std::vector<LiveCase> cases() {
    const double h = 1.0 / 64.0;
    std::vector<LiveCase> out;
    {
        LiveCase c{"carve", {}, 1, 0.0, 0.0, {{4, 0.0}, {5, 0.0}, {11, 0.0}, {12, 0.0}}};
        c.stroke.tool.radius = 0.03;
        c.stroke.samples = curve({0.3, 0.35, 0.5}, {0.7, 0.55, 0.51}, 12, 0.08);
        out.push_back(c);
    }
    {
        LiveCase c{"add", {}, 3, 0.01, 0.0, {{3, 0.02}, {9, 0.01}, {12, 0.0}}};  // dwell ignored by add, but recorded
        c.stroke.tool.op = ToolOp::Add;
        c.stroke.tool.shape = ToolShape::Cube;
        c.stroke.tool.radius = 0.02;
        c.stroke.samples = curve({0.3, 0.6, 0.52}, {0.7, 0.75, 0.52}, 12, 0.05);
        out.push_back(c);
    }
    {
        LiveCase c{"build", {}, 2, 0.0, 0.0, {{7, 0.0}, {8, 0.0}, {12, 0.0}}};
        c.stroke.tool.op = ToolOp::Build;
        c.stroke.tool.radius = 0.05;
        c.stroke.tool.amount = 3.0 * h;
        c.stroke.samples = curve({0.3, 0.4, 0.5}, {0.7, 0.6, 0.5}, 12, 0.06);
        out.push_back(c);
    }
    {
        // A dwell before the first pose (folded into the first segment), a dwell alone in the
        // middle (melts the path so far further), uneven dwells.
        LiveCase c{"heat gun", {}, 0, 0.0, 0.05, {{2, 0.03}, {2, 0.07}, {9, 0.1}, {12, 0.013}}};
        c.stroke.tool.op = ToolOp::HeatGun;
        c.stroke.tool.radius = 0.05;
        c.stroke.tool.rate = 0.02;
        c.stroke.samples = curve({0.35, 0.4, 0.5}, {0.65, 0.6, 0.5}, 12, 0.05);
        out.push_back(c);
    }
    {
        LiveCase c{"smooth", {}, 5, 0.0, 0.0, {{6, 0.0}, {12, 0.0}}};
        c.stroke.tool.op = ToolOp::Smooth;
        c.stroke.tool.radius = 0.05;
        c.stroke.samples = curve({0.15, 0.3, 0.5}, {0.15, 0.7, 0.5}, 12, 0.0);
        out.push_back(c);
    }
    {
        LiveCase c{"flatten", {}, 1, 0.0, 0.0, {{2, 0.0}, {10, 0.0}, {12, 0.0}}};
        c.stroke.tool.op = ToolOp::Flatten;
        c.stroke.tool.radius = 0.05;
        c.stroke.samples = curve({0.38, 0.48, 0.5}, {0.62, 0.52, 0.505}, 12, 0.03);
        out.push_back(c);
    }
    {
        LiveCase c{"carve mirrored", {}, 4, 0.0, 0.0, {{5, 0.0}, {12, 0.0}}};
        c.stroke.tool.radius = 0.02;
        c.stroke.mirror = 1;
        c.stroke.samples = curve({0.25, 0.25, 0.5}, {0.4, 0.3, 0.5}, 12, 0.02);
        out.push_back(c);
    }
    {
        LiveCase c{"carve following", {}, 2, 0.0, 0.0, {{3, 0.0}, {8, 0.0}, {12, 0.0}}};
        c.stroke.tool.radius = 0.02;
        c.stroke.constraints.followOffset = -0.005;
        c.stroke.samples = curve({0.3, 0.45, 0.53}, {0.7, 0.5, 0.56}, 12, 0.04);  // drawn loosely above
        out.push_back(c);
    }
    return out;
}

/// Applies `c` live through the session, with time stamps and strengths per pose.
bool applyLive(Session& s, const LiveCase& c) {
    Stroke header = c.stroke;
    header.samples.assign(c.stroke.samples.begin(), c.stroke.samples.begin() + long(c.header));
    header.dwell = c.headerDwell;
    s.beginStroke(header);
    if (c.leadingDwell > 0.0) s.extendStroke({}, c.leadingDwell);
    const std::span<const ToolSample> all(c.stroke.samples);
    std::size_t at = c.header;
    for (const auto& [end, dwell] : c.segments) {
        s.extendStroke(all.subspan(at, end - at), dwell);
        at = end;
    }
    std::vector<int64_t> times;
    std::vector<float> strengths;
    for (std::size_t i = 0; i < all.size(); ++i) {
        times.push_back(1'700'000'000'000'000'000 + int64_t(i) * 1'000'017);
        strengths.push_back(float(i + 1) / float(all.size() + 2));
    }
    return s.endStroke(std::move(times), std::move(strengths));
}

/// The journal's descriptor, found by its path in /proc/self/fd.
int journalFd(const fs::path& journal) {
    const fs::path want = fs::canonical(journal);
    for (const auto& e : fs::directory_iterator("/proc/self/fd")) {
        std::error_code ec;
        const fs::path target = fs::read_symlink(e.path(), ec);
        if (!ec && target == want) return std::stoi(e.path().filename().string());
    }
    return -1;
}

class LiveJournalTest : public ::testing::Test {
protected:
    void SetUp() override {
        mDir = fs::temp_directory_path() / ("kizamu_live_journal_" + std::to_string(::getpid()) + "_" +
                                            ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(mDir);
    }
    void TearDown() override { fs::remove_all(mDir); }
    fs::path mDir;
};

TEST_F(LiveJournalTest, ReopeningReplaysLiveStrokesBitForBitForEveryTool) {
    const Script script = slab();
    std::vector<adf::AdfPtr> before;
    adf::AdfPtr end;
    {
        auto live = Session::create(mDir.string(), script, 0);
        Stroke bump;  // something for flatten to flatten
        bump.tool.op = ToolOp::Add;
        bump.tool.radius = 0.03;
        bump.samples = curve({0.45, 0.5, 0.5}, {0.55, 0.5, 0.5}, 2, 0.0);
        live->record({Step::Kind::Stroke, bump, 0});
        for (const LiveCase& c : cases()) {
            // A stroke that follows the surface first makes every pending correction: its
            // start is the corrected clay (what settled() shows).
            before.push_back(c.stroke.constraints.followOffset ? live->sculptor().settled() : live->sculptor().current());
            const std::size_t steps = live->steps();
            ASSERT_TRUE(applyLive(*live, c)) << c.name;
            EXPECT_FALSE(live->stroking());
            EXPECT_EQ(live->steps(), steps + 1) << c.name << ": one journal record";
            const Stroke& journaled = live->journal().steps.back().stroke;
            ASSERT_TRUE(journaled.live) << c.name;
            EXPECT_EQ(journaled.live->cuts.back(), c.stroke.samples.size()) << c.name;
            EXPECT_EQ(journaled.live->timesNs.size(), c.stroke.samples.size()) << c.name;
            EXPECT_FALSE(test::sameAdf(*live->sculptor().current(), *before.back())) << c.name << " changed nothing";
        }
        // The heat gun's leading dwell is folded into its first segment.
        const Stroke& heat = live->journal().steps[4].stroke;
        ASSERT_EQ(heat.tool.op, ToolOp::HeatGun);
        EXPECT_EQ(heat.live->cuts, (std::vector<uint32_t>{2, 2, 9, 12}));
        EXPECT_EQ(heat.live->dwells.front(), 0.05 + 0.03);
        // A live stroke that changes nothing leaves no record.
        const auto size = fs::file_size(mDir / "journal.jsonl");
        const adf::AdfPtr now = live->sculptor().current();
        Stroke nothing;
        nothing.tool.radius = 0.03;
        live->beginStroke(nothing);
        live->extendStroke({}, 0.0);
        EXPECT_FALSE(live->endStroke());
        EXPECT_EQ(fs::file_size(mDir / "journal.jsonl"), size);
        EXPECT_EQ(live->sculptor().current(), now);
        end = live->sculptor().current();
    }
    const std::string text = util::readWholeFile((mDir / "journal.jsonl").string());
    EXPECT_NE(text.find("\"version\":3"), std::string::npos) << text.substr(0, 200);
    auto reopened = Session::open(mDir.string());
    EXPECT_TRUE(test::sameAdf(*reopened->sculptor().current(), *end));
    {
        // The live record is what makes the bits: the same strokes applied whole differ.
        auto whole = makeSculptor(reopened->journal(), 0);
        for (Step st : reopened->journal().steps) {
            st.stroke.live.reset();
            whole->replay(st);
        }
        EXPECT_FALSE(test::sameAdf(*whole->current(), *end));
    }
    // Undo after reopening returns each stroke's start, bit for bit.
    for (std::size_t k = before.size(); k-- > 0;) {
        reopened->record(Step::undo());
        EXPECT_TRUE(test::sameAdf(*reopened->sculptor().current(), *before[k])) << cases()[k].name;
    }
}

TEST_F(LiveJournalTest, ALiveRecordRoundTripsThroughTheScriptTextBitForBit) {
    Script s = slab();
    Stroke st;
    st.tool.op = ToolOp::HeatGun;
    st.tool.rate = 0.013;
    st.samples = {{{0.1 / 3.0, 0.7, std::nextafter(0.5, 1.0)}, kIdentity},
                  {{0.2, 1.0 / 7.0, 0.5}, glm::normalize(glm::dquat(0.9, 0.1, 0.2, 0.3))},
                  {{0.3, 0.4, 1e-17}, kIdentity}};
    LiveRecord r;
    r.cuts = {1, 1, 3};
    r.dwells = {0.1, 1.0 / 3.0, std::nextafter(0.2, 0.0)};
    r.timesNs = {-5, std::numeric_limits<int64_t>::max() - 1, std::numeric_limits<int64_t>::max()};
    r.strengths = {0.1f, 1.0f / 3.0f, std::nextafter(1.0f, 0.0f)};
    st.dwell = (0.0 + r.dwells[0] + r.dwells[1]) + r.dwells[2];
    st.live = r;
    s.add(st);
    Stroke carve;  // a non-heat-gun live stroke keeps its dwell too
    carve.samples = {{{0.5, 0.5, 0.5}, kIdentity}, {{0.6, 0.5, 0.5}, kIdentity}};
    carve.live = LiveRecord{{2}, {0.25}, {}, {}};
    carve.dwell = 0.25;
    s.add(carve);
    const std::string text = formatScript(s);
    const Script back = parseScript(text, "live.jsonl");
    ASSERT_EQ(back.version, 3);
    ASSERT_EQ(back.steps.size(), 2u);
    const Stroke& b = back.steps[0].stroke;
    ASSERT_TRUE(b.live);
    EXPECT_EQ(b.live->cuts, r.cuts);
    EXPECT_EQ(b.live->timesNs, r.timesNs);
    ASSERT_EQ(b.live->dwells.size(), r.dwells.size());
    for (std::size_t i = 0; i < r.dwells.size(); ++i) EXPECT_EQ(std::bit_cast<uint64_t>(b.live->dwells[i]), std::bit_cast<uint64_t>(r.dwells[i]));
    ASSERT_EQ(b.live->strengths.size(), r.strengths.size());
    for (std::size_t i = 0; i < r.strengths.size(); ++i)
        EXPECT_EQ(std::bit_cast<uint32_t>(b.live->strengths[i]), std::bit_cast<uint32_t>(r.strengths[i]));
    EXPECT_EQ(std::bit_cast<uint64_t>(b.dwell), std::bit_cast<uint64_t>(st.dwell));
    ASSERT_EQ(b.samples.size(), st.samples.size());
    for (std::size_t i = 0; i < st.samples.size(); ++i) {
        for (int k = 0; k < 3; ++k)
            EXPECT_EQ(std::bit_cast<uint64_t>(b.samples[i].position[k]), std::bit_cast<uint64_t>(st.samples[i].position[k]));
        EXPECT_EQ(b.samples[i].orientation, st.samples[i].orientation);
    }
    const Stroke& c = back.steps[1].stroke;
    ASSERT_TRUE(c.live);
    EXPECT_EQ(c.dwell, 0.25);
    EXPECT_TRUE(c.live->timesNs.empty());
    EXPECT_TRUE(c.live->strengths.empty());
    EXPECT_EQ(formatScript(back), text);  // and the text is stable
    EXPECT_EQ(strokeLine(c).find("\"t\""), std::string::npos);  // empty lists are left out
}

TEST_F(LiveJournalTest, OlderScriptsCannotHoldALiveRecord) {
    Script s = slab();
    Stroke carve;
    carve.samples = {{{0.5, 0.5, 0.5}, kIdentity}};
    carve.live = LiveRecord{{1}, {0.0}, {}, {}};
    s.add(carve);
    for (int version : {1, 2}) {
        s.version = version;
        try {
            parseScript(formatScript(s), "old.jsonl");
            ADD_FAILURE() << "version " << version << " read a live record";
        } catch (const FileError& e) {
            EXPECT_NE(std::string(e.what()).find("live strokes need version 3"), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find("version " + std::to_string(version)), std::string::npos) << e.what();
        }
        EXPECT_THROW(parseStep(strokeLine(carve), version), std::invalid_argument);
    }
    // Without live records, they read as before.
    s.steps[0].stroke.live.reset();
    s.version = 2;
    EXPECT_EQ(parseScript(formatScript(s), "v2.jsonl").version, 2);
}

TEST_F(LiveJournalTest, ValidateChecksEachRuleOfALiveRecord) {
    Stroke good;
    good.samples = {{{0.5, 0.5, 0.5}, kIdentity}, {{0.6, 0.5, 0.5}, kIdentity}, {{0.7, 0.5, 0.5}, kIdentity}};
    good.live = LiveRecord{{1, 3}, {0.5, 0.25}, {10, 20, 20}, {0.0f, 0.5f, 1.0f}};
    good.dwell = 0.75;
    EXPECT_NO_THROW(validate(good));
    auto bad = [&](const char* what, auto change) {
        Stroke s = good;
        change(s);
        EXPECT_THROW(validate(s), std::invalid_argument) << what;
    };
    bad("bezier", [](Stroke& s) {
        s.samples.push_back(s.samples.back());
        s.bezier = true;
        s.live->cuts.back() = 4;
        s.live->timesNs.push_back(30);
        s.live->strengths.push_back(1.0f);
    });
    bad("no segments", [](Stroke& s) { s.live->cuts.clear(), s.live->dwells.clear(), s.dwell = 0.0; });
    bad("a dwell per cut", [](Stroke& s) { s.live->dwells.push_back(0.0); });
    bad("cuts[0] >= 1", [](Stroke& s) { s.live->cuts = {0, 3}; });
    bad("cuts non-decreasing", [](Stroke& s) { s.live->cuts = {2, 1, 3}, s.live->dwells = {0.5, 0.25, 0.0}; });
    bad("last cut", [](Stroke& s) { s.live->cuts = {1, 2}; });
    bad("negative dwell", [](Stroke& s) { s.live->dwells = {1.0, -0.25}; });
    bad("NaN dwell", [](Stroke& s) { s.live->dwells[1] = std::nan(""); });
    bad("infinite dwell", [](Stroke& s) { s.live->dwells[1] = s.dwell = std::numeric_limits<double>::infinity(); });
    bad("dwell sum", [](Stroke& s) { s.dwell = 0.7; });
    bad("a time per sample", [](Stroke& s) { s.live->timesNs.pop_back(); });
    bad("times non-decreasing", [](Stroke& s) { s.live->timesNs = {10, 9, 20}; });
    bad("a strength per sample", [](Stroke& s) { s.live->strengths.push_back(0.5f); });
    bad("strength above 1", [](Stroke& s) { s.live->strengths[1] = 1.5f; });
    bad("strength below 0", [](Stroke& s) { s.live->strengths[1] = -0.01f; });
    bad("NaN strength", [](Stroke& s) { s.live->strengths[1] = std::nanf(""); });
}

TEST_F(LiveJournalTest, AnInMemorySessionWorksAndWritesNothing) {
    const Script script = slab();
    auto mem = Session::createInMemory(script, 0);
    auto disk = Session::create(mDir.string(), script, 0);
    EXPECT_TRUE(mem->dir().empty());
    const std::vector<LiveCase> all = cases();
    for (std::size_t i : {0u, 3u}) {
        ASSERT_TRUE(applyLive(*mem, all[i]));
        ASSERT_TRUE(applyLive(*disk, all[i]));
    }
    mem->record(Step::undo());
    disk->record(Step::undo());
    mem->checkpoint();
    const Session::CheckpointJob job = mem->prepareCheckpoint();
    EXPECT_TRUE(job.path.empty());
    Session::writeCheckpoint(job);
    mem->checkpointWritten(job);
    EXPECT_EQ(mem->steps(), 3u);  // no correction journaled: in memory, checkpoints do nothing
    EXPECT_EQ(mem->checkpointSteps(), 0u);
    EXPECT_TRUE(test::sameAdf(*mem->sculptor().current(), *disk->sculptor().current()));
    EXPECT_EQ(mem->journal().version, 3);
    // Its journal replays to its clay.
    auto replayed = makeSculptor(mem->journal(), 0);
    for (const Step& st : mem->journal().steps) replayed->replay(st);
    EXPECT_TRUE(test::sameAdf(*replayed->current(), *mem->sculptor().current()));
}

TEST_F(LiveJournalTest, StepsWhileAStrokeIsOpenAreRefusedBeforeTheyAreJournaled) {
    auto s = Session::create(mDir.string(), slab(), 0);
    const LiveCase c = cases()[0];
    ASSERT_TRUE(applyLive(*s, c));
    const auto size = fs::file_size(mDir / "journal.jsonl");
    Stroke header = c.stroke;
    header.samples.resize(2);
    s->beginStroke(header);
    EXPECT_TRUE(s->stroking());
    EXPECT_THROW(s->record(Step::undo()), std::logic_error);
    EXPECT_THROW(s->record({Step::Kind::Stroke, c.stroke, 0}), std::logic_error);
    EXPECT_THROW(s->checkpoint(), std::logic_error);
    EXPECT_THROW(s->endStroke({1, 2, 3}), std::invalid_argument);  // three times for two poses: the stroke stays open
    EXPECT_TRUE(s->stroking());
    EXPECT_EQ(fs::file_size(mDir / "journal.jsonl"), size);
    s->cancelStroke();
    EXPECT_FALSE(s->stroking());
    EXPECT_THROW(s->endStroke(), std::logic_error);
}

TEST_F(LiveJournalTest, AJournalWriteFailureCancelsTheStrokeAndStopsTheSession) {
    const std::vector<LiveCase> all = cases();
    {
        auto s = Session::create(mDir.string(), slab(), 0);
        ASSERT_TRUE(applyLive(*s, all[0]));
        const adf::AdfPtr start = s->sculptor().current();
        // The disk fills up: the journal's descriptor now writes to /dev/full (ENOSPC).
        const int fd = journalFd(mDir / "journal.jsonl");
        ASSERT_GE(fd, 0);
        const int full = ::open("/dev/full", O_WRONLY | O_CLOEXEC);
        ASSERT_GE(full, 0);
        ASSERT_EQ(::dup2(full, fd), fd);
        ::close(full);
        EXPECT_THROW(applyLive(*s, all[2]), FileError);
        EXPECT_FALSE(s->stroking());
        EXPECT_EQ(s->sculptor().current(), start);  // the stroke's start, as on disk
        EXPECT_EQ(s->steps(), 1u);
        EXPECT_THROW(s->record(Step::undo()), FileError);
        EXPECT_THROW(s->beginStroke(all[0].stroke), FileError);
    }
    auto reopened = Session::open(mDir.string());
    EXPECT_EQ(reopened->steps(), 1u);
}

TEST_F(LiveJournalTest, CheckpointsWrittenOnAnotherThreadReopenTheSame) {
    const std::vector<LiveCase> all = cases();
    adf::AdfPtr end;
    Session::CheckpointJob first, second;
    {
        auto s = Session::create(mDir.string(), slab(), 0);
        ASSERT_TRUE(applyLive(*s, all[0]));
        ASSERT_TRUE(applyLive(*s, all[1]));
        first = s->prepareCheckpoint();
        EXPECT_EQ(first.steps, 3u);  // two strokes and the correction before the checkpoint
        std::thread writer([&] { Session::writeCheckpoint(first); });
        ASSERT_TRUE(applyLive(*s, all[3]));  // the edit thread goes on meanwhile
        writer.join();
        s->checkpointWritten(first);
        EXPECT_EQ(s->checkpointSteps(), 3u);
        second = s->prepareCheckpoint();
        std::thread(Session::writeCheckpoint, second).join();
        s->checkpointWritten(second);
        EXPECT_FALSE(fs::exists(first.path));
        s->checkpointWritten(first);  // late: never removes the newer one
        EXPECT_TRUE(fs::exists(second.path));
        EXPECT_EQ(s->checkpointSteps(), second.steps);
        ASSERT_TRUE(applyLive(*s, all[5]));
        end = s->sculptor().current();
    }
    auto reopened = Session::open(mDir.string());
    EXPECT_EQ(reopened->checkpointSteps(), second.steps);
    EXPECT_TRUE(test::sameAdf(*reopened->sculptor().current(), *end));
    // Undo reaching before the checkpoint rebuilds the history from the journal, live records
    // replayed as live.
    for (int i = 0; i < 3; ++i) reopened->record(Step::undo());
    auto replayed = makeSculptor(reopened->journal(), 0);
    for (const Step& st : reopened->journal().steps) replayed->replay(st);
    EXPECT_TRUE(test::sameAdf(*reopened->sculptor().current(), *replayed->current()));
    EXPECT_EQ(replayed->undoDepth(), 1u);
}

TEST_F(LiveJournalTest, AnOlderJournalGetsAVersion3HeaderBeforeItsFirstLiveRecord) {
    Script s = slab();
    s.version = 2;
    Stroke carve;
    carve.tool.radius = 0.02;
    carve.samples = curve({0.3, 0.3, 0.5}, {0.4, 0.3, 0.5}, 2, 0.0);
    s.add(carve);
    fs::create_directories(mDir);
    {
        std::ofstream j(mDir / "journal.jsonl");
        j << "# written by an older build\n" << formatScript(s);
    }
    adf::AdfPtr end;
    {
        auto live = Session::open(mDir.string());
        EXPECT_EQ(live->journal().version, 2);
        ASSERT_TRUE(applyLive(*live, cases()[0]));
        EXPECT_EQ(live->journal().version, 3);
        ASSERT_TRUE(applyLive(*live, cases()[3]));  // appends to the new journal
        end = live->sculptor().current();
    }
    const std::string text = util::readWholeFile((mDir / "journal.jsonl").string());
    EXPECT_EQ(text.rfind("# written by an older build\n", 0), 0u);
    EXPECT_NE(text.find(stepLine(s.steps[0])), std::string::npos);  // records kept byte for byte
    auto reopened = Session::open(mDir.string());
    EXPECT_EQ(reopened->journal().version, 3);
    EXPECT_EQ(reopened->steps(), 3u);
    EXPECT_TRUE(test::sameAdf(*reopened->sculptor().current(), *end));
}

}  // namespace
}  // namespace kizamu
