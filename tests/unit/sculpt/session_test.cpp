// SPDX-License-Identifier: Apache-2.0
// Sessions never lose a finished stroke: reopen equals the live state; a process killed with
// SIGKILL mid-run reopens with every finished stroke; a journal cut mid-record opens with the
// strokes before it and a warning; a damaged checkpoint falls back to an older one or the journal.
#include "sculpt/session.h"
#include "sculpt/session_lock.h"

#include "adf/adf_file.h"
#include "sculpt/script_start.h"
#include "tests/util/adf_compare.h"
#include "util/file_error.h"

#include <gtest/gtest.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <random>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

namespace kizamu {
namespace {

using namespace sculpt;
namespace fs = std::filesystem;

const glm::dquat kIdentity(1.0, 0.0, 0.0, 0.0);

Script slab(int level, int strokes, uint64_t seed) {
    Script s;
    s.domain.maxLevel = level;
    s.domain.tileSpanLevels = 3;
    s.start.kind = Shape::Kind::Box;
    s.start.centre = {0.5, 0.5, 0.4};
    s.start.halfSize = {0.35, 0.35, 0.1};
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int i = 0; i < strokes; ++i) {
        Stroke st;
        st.tool.shape = ToolShape::Cylinder;
        st.tool.radius = 0.01 + 0.01 * u(rng);
        st.tool.halfLength = 0.02;
        const glm::dvec3 a(0.2 + 0.6 * u(rng), 0.2 + 0.6 * u(rng), 0.5), b = a + glm::dvec3(0.1 * u(rng) - 0.05, 0.1 * u(rng) - 0.05, 0);
        st.samples = {{a, kIdentity}, {b, kIdentity}};
        s.add(st);
    }
    return s;
}

/// The ADF after the first `steps` steps, replayed in memory.
adf::AdfPtr replay(const Script& s, std::size_t steps) {
    auto sc = makeSculptor(s, 0);
    for (std::size_t i = 0; i < steps; ++i) sc->replay(s.steps[i]);
    return sc->current();
}

/// A session's journal without the remote-field corrections it recorded at checkpoints.
std::vector<std::string> editLines(const Script& journal) {
    std::vector<std::string> out;
    for (const Step& st : journal.steps)
        if (st.kind != Step::Kind::Correct) out.push_back(stepLine(st));
    return out;
}
std::vector<std::string> editLines(const Script& script, std::size_t steps) {
    Script head = script;
    head.steps.resize(steps);
    return editLines(head);
}

class SessionTest : public ::testing::Test {
protected:
    void SetUp() override {
        mDir = fs::temp_directory_path() / ("kizamu_session_" + std::to_string(::getpid()) + "_" +
                                            ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(mDir);
    }
    void TearDown() override { fs::remove_all(mDir); }
    fs::path mDir;
};

TEST_F(SessionTest, ReopensToTheSameClayWithUndoAndCheckpoints) {
    Script s = slab(6, 6, 1);
    s.steps.insert(s.steps.begin() + 4, Step::undo());
    s.steps.insert(s.steps.begin() + 5, Step::redo());
    s.steps.insert(s.steps.begin() + 6, Step::undo());
    {
        auto live = Session::create(mDir.string(), s, 0);
        for (std::size_t i = 0; i < s.steps.size(); ++i) {
            live->record(s.steps[i]);
            if (i == 2 || i == 7) live->checkpoint();
        }
        std::vector<std::string> warnings;
        auto again = Session::open(mDir.string(), nullptr, &warnings, /*readOnly=*/true);  // a second reader
        EXPECT_TRUE(warnings.empty());
        // The journal holds the script's steps, plus a correction before each checkpoint; the
        // clay is the journal's replay bit for bit.
        EXPECT_EQ(editLines(again->journal()), editLines(s));
        EXPECT_EQ(again->steps(), s.steps.size() + 2);
        EXPECT_TRUE(test::sameAdf(*again->sculptor().current(), *live->sculptor().current()));
        EXPECT_TRUE(test::sameAdf(*again->sculptor().current(), *replay(again->journal(), again->steps())));
    }
    // Only the newest checkpoint is kept.
    std::size_t cps = 0;
    for (const auto& e : fs::directory_iterator(mDir)) cps += e.path().extension() == ".kza";
    EXPECT_EQ(cps, 1u);
    EXPECT_THROW(Session::create(mDir.string(), s, 0), FileError);  // never overwrites a session
    EXPECT_THROW(Session::open((mDir / "nothing").string()), FileError);
}

TEST_F(SessionTest, UndoAfterReopeningFromACheckpointReachesTheWholeHistory) {
    const Script s = slab(6, 4, 5);
    {
        auto live = Session::create(mDir.string(), s, 0);
        for (const Step& st : s.steps) live->record(st);
        live->checkpoint();
    }
    {
        auto reopened = Session::open(mDir.string());
        EXPECT_EQ(reopened->checkpointSteps(), 5u);  // 4 strokes and the correction before it
        reopened->record(Step::undo());  // reaches before the checkpoint
        reopened->record(Step::undo());
        // Corrections are not edits: undo returns to the snapshot (and pending zones) before
        // the stroke, as if the correction had not happened.
        EXPECT_TRUE(test::sameAdf(*reopened->sculptor().current(), *replay(s, 2)));
    }
    auto third = Session::open(mDir.string());
    EXPECT_EQ(third->steps(), 7u);
    EXPECT_TRUE(test::sameAdf(*third->sculptor().current(), *replay(s, 2)));
}

TEST_F(SessionTest, AJournalCutMidRecordOpensWithTheStrokesBeforeItAndAWarning) {
    const Script s = slab(6, 4, 2);
    {
        auto live = Session::create(mDir.string(), s, 0);
        for (const Step& st : s.steps) live->record(st);
    }
    const fs::path journal = mDir / "journal.jsonl";
    const auto size = fs::file_size(journal);
    const std::string last = stepLine(s.steps.back());
    fs::resize_file(journal, size - last.size() / 2 - 1);  // cut the last record in the middle
    std::vector<std::string> warnings;
    auto reopened = Session::open(mDir.string(), nullptr, &warnings);
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find("cut short"), std::string::npos) << warnings[0];
    EXPECT_EQ(reopened->steps(), 3u);
    EXPECT_TRUE(test::sameAdf(*reopened->sculptor().current(), *replay(s, 3)));
    // The session goes on, and the journal is whole again.
    reopened->record(s.steps.back());
    reopened.reset();
    warnings.clear();
    auto third = Session::open(mDir.string(), nullptr, &warnings);
    EXPECT_TRUE(warnings.empty());
    EXPECT_EQ(third->steps(), 4u);
    EXPECT_TRUE(test::sameAdf(*third->sculptor().current(), *replay(s, 4)));
}

TEST_F(SessionTest, ADamagedCheckpointFallsBackWithAWarning) {
    const Script s = slab(6, 4, 3);
    {
        auto live = Session::create(mDir.string(), s, 0);
        for (const Step& st : s.steps) live->record(st);
        live->checkpoint();
    }
    fs::path cp;
    for (const auto& e : fs::directory_iterator(mDir))
        if (e.path().extension() == ".kza") cp = e.path();
    ASSERT_FALSE(cp.empty());
    fs::resize_file(cp, fs::file_size(cp) / 2);
    std::vector<std::string> warnings;
    auto reopened = Session::open(mDir.string(), nullptr, &warnings);
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find("truncated"), std::string::npos) << warnings[0];
    EXPECT_TRUE(test::sameAdf(*reopened->sculptor().current(), *replay(reopened->journal(), reopened->steps())));
    EXPECT_EQ(editLines(reopened->journal()), editLines(s));
}

TEST_F(SessionTest, AnOlderJournalReopensChecksPointsAndReopensAgain) {
    // A journal written by a build before correct records existed (script version 1).
    Script s = slab(6, 3, 7);
    s.version = 1;
    fs::create_directories(mDir);
    {
        std::ofstream j(mDir / "journal.jsonl");
        j << formatScript(s);
    }
    {
        auto reopened = Session::open(mDir.string());
        EXPECT_EQ(reopened->steps(), 3u);
        reopened->record(s.steps.front());
        reopened->checkpoint();  // journals a correct record in the version-1 journal
    }
    std::vector<std::string> warnings;
    auto again = Session::open(mDir.string(), nullptr, &warnings);
    EXPECT_TRUE(warnings.empty());
    EXPECT_EQ(again->steps(), 5u);
    EXPECT_TRUE(test::sameAdf(*again->sculptor().current(), *replay(again->journal(), again->steps())));
}

TEST_F(SessionTest, StrokesThatCannotReplayAreNeitherJournaledNorApplied) {
    const Script s = slab(6, 1, 8);
    auto live = Session::create(mDir.string(), s, 0);
    live->record(s.steps.front());
    const adf::AdfPtr before = live->sculptor().current();
    const auto size = fs::file_size(mDir / "journal.jsonl");
    Stroke bezier = s.steps.front().stroke;
    bezier.bezier = true;  // two points, not four
    Stroke depthOnAdd = s.steps.front().stroke;
    depthOnAdd.tool.op = ToolOp::Add;
    depthOnAdd.constraints.depthLimit = 0.01;
    Stroke badMask = s.steps.front().stroke;
    badMask.constraints.masks.push_back(Shape{Shape::Kind::Sphere, glm::dvec3(0.5), glm::dvec3(0.1), -1.0, 0.0});
    for (const Stroke& bad : {bezier, depthOnAdd, badMask}) {
        EXPECT_THROW(live->record({Step::Kind::Stroke, bad, 0}), std::invalid_argument);
        EXPECT_EQ(fs::file_size(mDir / "journal.jsonl"), size);
        EXPECT_EQ(live->sculptor().current(), before);
    }
}

TEST_F(SessionTest, SigkillMidRunLosesNoFinishedStroke) {
    const Script s = slab(7, 400, 4);
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
        // The child sculpts until it is killed.
        auto live = Session::create(mDir.string(), s, 0);
        for (std::size_t i = 0; i < s.steps.size(); ++i) {
            live->record(s.steps[i]);
            if (i % 7 == 6) live->checkpoint();
        }
        ::_exit(0);
    }
    // Wait until a dozen strokes are journaled, then kill it without warning.
    const fs::path journal = mDir / "journal.jsonl";
    for (int i = 0; i < 6000; ++i) {
        std::error_code ec;
        std::ifstream in(journal);
        const auto lines = std::count(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>(), '\n');
        if (lines >= 13) break;
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    ::kill(child, SIGKILL);
    int status = 0;
    ::waitpid(child, &status, 0);
    ASSERT_TRUE(WIFSIGNALED(status)) << "the child finished before it could be killed";
    // The killed process left its lock file behind, held by nobody: the session was interrupted
    // (what the app offers to restore).
    EXPECT_TRUE(sculpt::SessionLock::interrupted(mDir.string()));
    EXPECT_FALSE(sculpt::SessionLock::holder(mDir.string()));
    std::vector<std::string> warnings;
    auto reopened = Session::open(mDir.string(), nullptr, &warnings);
    EXPECT_FALSE(sculpt::SessionLock::interrupted(mDir.string())) << "held again";
    const std::vector<std::string> edits = editLines(reopened->journal());
    const std::size_t k = edits.size();
    EXPECT_GE(k, 11u);
    EXPECT_LT(k, s.steps.size());
    // Every finished stroke is there: the script's first k, and the clay is the journal's
    // replay (strokes and the corrections made at checkpoints) bit for bit.
    EXPECT_EQ(edits, editLines(s, k));
    EXPECT_TRUE(test::sameAdf(*reopened->sculptor().current(), *replay(reopened->journal(), reopened->steps())));
}

TEST_F(SessionTest, OneWriterPerSessionAndACleanCloseLeavesNoTrace) {
    const Script s = slab(6, 3, 1);
    {
        auto live = Session::create(mDir.string(), s, 0);
        EXPECT_EQ(sculpt::SessionLock::holder(mDir.string()), std::optional<pid_t>(::getpid()));
        EXPECT_FALSE(sculpt::SessionLock::interrupted(mDir.string())) << "held: open, not interrupted";
        try {
            Session::open(mDir.string());
            ADD_FAILURE() << "a second writer opened the session";
        } catch (const FileError& e) {
            EXPECT_NE(std::string(e.what()).find("open in another Kizamu (pid " + std::to_string(::getpid()) + ")"),
                      std::string::npos)
                << e.what();
        }
        // A reader is welcome, and changes nothing.
        EXPECT_NO_THROW(Session::open(mDir.string(), nullptr, nullptr, /*readOnly=*/true));
        live->record(s.steps[0]);
    }
    EXPECT_FALSE(fs::exists(mDir / "lock")) << "a clean close removes the lock file";
    EXPECT_FALSE(sculpt::SessionLock::interrupted(mDir.string()));
    EXPECT_FALSE(sculpt::SessionLock::holder(mDir.string()));
    auto again = Session::open(mDir.string());
    EXPECT_EQ(again->steps(), 1u);
}

}  // namespace
}  // namespace kizamu
