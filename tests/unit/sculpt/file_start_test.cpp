// SPDX-License-Identifier: Apache-2.0
// Starts from a file (stroke_script.h, script_start.h, session.h): a header {"shape": "file"}
// round-trips and loads; a level or domain that is not the file's, a missing file, a file
// start in a version 2 header and a file used as a mask are readable errors; a session made
// from clay (Session::createFromClay) reopens to the live clay bit for bit, on disk and in memory.
#include "sculpt/script_start.h"
#include "sculpt/session.h"
#include "sculpt/stroke_script.h"

#include "adf/adf_file.h"
#include "util/file_error.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <unistd.h>

namespace kizamu {
namespace {

using namespace sculpt;
namespace fs = std::filesystem;

const glm::dquat kIdentity(1.0, 0.0, 0.0, 0.0);

/// A sphere's clay at `level` (what an import would give: clay that is no simple shape's
/// header, once stored).
adf::AdfPtr sphereClay(int level) {
    Script s;
    s.domain.maxLevel = level;
    s.domain.tileSpanLevels = 3;
    s.start.kind = Shape::Kind::Sphere;
    s.start.centre = {0.5, 0.5, 0.5};
    s.start.radius = 0.3;
    return startAdf(s, 0);
}

Stroke carveAcross(double y, std::optional<double> depth = std::nullopt) {
    Stroke st;
    st.tool.radius = 0.03;
    st.samples = {{{0.4, y, 0.8}, kIdentity}, {{0.6, y, 0.8}, kIdentity}};
    st.constraints.depthLimit = depth;
    return st;
}

class FileStartTest : public ::testing::Test {
protected:
    void SetUp() override {
        mDir = fs::temp_directory_path() / ("kizamu_file_start_" + std::to_string(::getpid()) + "_" +
                                            ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(mDir);
        fs::create_directories(mDir);
        mClay = sphereClay(5);
        adf::saveAdf(*mClay, (mDir / "clay.kza").string());
        mScript.domain = mClay->domain();
        mScript.start.kind = Shape::Kind::File;
        mScript.start.file = "clay.kza";
        mScript.baseDir = mDir.string();
    }
    void TearDown() override { fs::remove_all(mDir); }
    fs::path mDir;
    adf::AdfPtr mClay;
    Script mScript;
};

std::string what(const std::function<void()>& f) {
    try {
        f();
    } catch (const std::exception& e) {
        return e.what();
    }
    return "(no error)";
}

TEST_F(FileStartTest, AFileStartRoundTripsAndLoads) {
    mScript.add(carveAcross(0.5));
    const std::string text = formatScript(mScript);
    EXPECT_NE(text.find(R"("start":{"file":"clay.kza","shape":"file"})"), std::string::npos) << text;
    Script back = parseScript(text, "script.jsonl");
    EXPECT_EQ(back.start.kind, Shape::Kind::File);
    EXPECT_EQ(back.start.file, "clay.kza");
    EXPECT_EQ(back.domain, mClay->domain());
    EXPECT_EQ(formatScript(back), text);
    back.baseDir = mDir.string();
    EXPECT_TRUE(adf::encodeAdf(*startAdf(back, 0)) == adf::encodeAdf(*mClay));
    EXPECT_TRUE(adf::encodeAdf(*startAdf(back, 5)) == adf::encodeAdf(*mClay)) << "the file's own level is allowed";
    // readScript reads the start relative to the script's directory.
    std::ofstream((mDir / "script.jsonl").string()) << text;
    const Script read = readScript((mDir / "script.jsonl").string());
    EXPECT_EQ(read.baseDir, mDir.string());
    EXPECT_TRUE(adf::encodeAdf(*startAdf(read, 0)) == adf::encodeAdf(*mClay));
    // An absolute path needs no base directory.
    Script absolute = mScript;
    absolute.start.file = (mDir / "clay.kza").string();
    absolute.baseDir.clear();
    EXPECT_TRUE(adf::encodeAdf(*startAdf(absolute, 0)) == adf::encodeAdf(*mClay));
    // The reference of a sculptor there is the file's surface: a depth limit measures from it.
    auto sculptor = makeSculptor(back, 0);
    sculptor->replay(back.steps[0]);
    EXPECT_NE(sculptor->current(), mClay);
}

TEST_F(FileStartTest, MismatchesMissingFilesOldVersionsAndMasksAreReadableErrors) {
    EXPECT_NE(what([&] { startAdf(mScript, 6); }).find("a start from a file keeps its level 5"), std::string::npos);
    Script other = mScript;
    other.domain.sizeWorld = 2.0;
    EXPECT_NE(what([&] { startAdf(other, 0); }).find("has the domain"), std::string::npos);
    other = mScript;
    other.start.file = "missing.kza";
    EXPECT_THROW(startAdf(other, 0), FileError);
    EXPECT_NE(what([&] { startAdf(other, 0); }).find("missing.kza"), std::string::npos);

    Script v2 = mScript;
    v2.version = 2;
    const std::string old = headerLine(v2) + "\n";
    const std::string e = what([&] { parseScript(old, "old.jsonl"); });
    EXPECT_NE(e.find("old.jsonl: line 1"), std::string::npos) << e;
    EXPECT_NE(e.find("version 3"), std::string::npos) << e;

    Script plain;
    plain.add(carveAcross(0.5));
    std::string line = strokeLine(plain.steps[0].stroke);
    line.insert(line.size() - 1, R"(,"masks":[{"shape":"file","file":"clay.kza"}])");
    const std::string m = what([&] { parseScript(headerLine(plain) + "\n" + line + "\n", "mask.jsonl"); });
    EXPECT_NE(m.find("mask.jsonl: line 2"), std::string::npos) << m;
    EXPECT_NE(m.find("start only"), std::string::npos) << m;
    Stroke masked = carveAcross(0.5);
    masked.constraints.masks.push_back(mScript.start);
    EXPECT_THROW(validate(masked), std::invalid_argument);

    Script noFile = mScript;
    noFile.start.file.clear();
    const std::string header = headerLine(noFile);
    EXPECT_NE(what([&] { parseScript(header + "\n", "empty.jsonl"); }).find("needs a \"file\""), std::string::npos);
}

TEST_F(FileStartTest, ASessionFromClayReopensBitForBit) {
    const std::string dir = (mDir / "session").string();
    adf::AdfPtr live;
    {
        auto s = Session::createFromClay(dir, mClay);
        EXPECT_TRUE(fs::exists(fs::path(dir) / "start.kza"));
        EXPECT_EQ(s->journal().start.kind, Shape::Kind::File);
        EXPECT_EQ(s->journal().start.file, "start.kza");
        EXPECT_EQ(s->sculptor().current(), mClay);
        s->record({Step::Kind::Stroke, carveAcross(0.45), 0});
        s->record({Step::Kind::Stroke, carveAcross(0.55, 0.01), 0});
        live = s->sculptor().current();
        EXPECT_NE(live, mClay);
    }
    EXPECT_THROW(Session::createFromClay(dir, mClay), FileError) << "a directory with a session is not overwritten";
    EXPECT_TRUE(adf::encodeAdf(*adf::loadAdf((fs::path(dir) / "start.kza").string())) == adf::encodeAdf(*mClay));
    {
        auto s = Session::open(dir);
        EXPECT_TRUE(adf::encodeAdf(*s->sculptor().current()) == adf::encodeAdf(*live));
        // From a checkpoint, an undo that reaches before it rebuilds the history from start.kza.
        s->checkpoint();
        live = s->sculptor().current();  // with the corrections the checkpoint made (journaled)
    }
    auto s = Session::open(dir);
    EXPECT_TRUE(adf::encodeAdf(*s->sculptor().current()) == adf::encodeAdf(*live));
    s->record(Step::undo());
    s->record(Step::undo());
    EXPECT_TRUE(adf::encodeAdf(*s->sculptor().current()) == adf::encodeAdf(*mClay));
    // create() from a script that starts from a file copies the file into the session.
    const std::string copy = (mDir / "copy").string();
    auto c = Session::create(copy, mScript, 0);
    EXPECT_TRUE(fs::exists(fs::path(copy) / "start.kza"));
    EXPECT_EQ(c->journal().start.file, "start.kza");
    EXPECT_THROW(Session::create((mDir / "copy6").string(), mScript, 6), std::invalid_argument);
}

TEST_F(FileStartTest, ASessionFromClayInMemoryWritesNothing) {
    auto s = Session::createFromClay({}, mClay);
    EXPECT_TRUE(s->dir().empty());
    EXPECT_EQ(s->sculptor().current(), mClay);
    s->record({Step::Kind::Stroke, carveAcross(0.5, 0.01), 0});
    const adf::AdfPtr live = s->sculptor().current();
    EXPECT_NE(live, mClay);
    // Replaying its journal from the same clay gives the same bits.
    Script j = s->journal();
    auto again = makeSculptor(j, 0);
    for (const Step& st : j.steps) again->replay(st);
    EXPECT_TRUE(adf::encodeAdf(*again->current()) == adf::encodeAdf(*live));
    s->record(Step::undo());
    EXPECT_EQ(s->sculptor().current(), mClay);
}

}  // namespace
}  // namespace kizamu
