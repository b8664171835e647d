// SPDX-License-Identifier: Apache-2.0
// The sculpting window end to end, under a display (Xvfb from scripts/test): the real `kizamu
// sculpt` run with input scripts (docs/INPUT.md), its last frame compared as pixels. A scripted
// drag carves a groove where the cursor went and nowhere else; Ctrl+Z restores the pixels; the
// panel is drawn; a dropped mesh opens; a shader that does not compile is a clear error; a session
// a crash left open is restored; Save As moves the journal to a new directory; Ctrl+O and a typed
// path open a session or a mesh; --level 11 makes a level-11 block; a small window frames the
// block right of the panel; the summary line carries the sample-to-visible latency.
#include "render/image.h"
#include "sculpt/session.h"
#include "sculpt/session_lock.h"

#include <gtest/gtest.h>

#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

namespace kizamu {
namespace {

namespace fs = std::filesystem;

constexpr int kW = 960, kH = 600;
/// The drag: along y = kDragY from kDragX0 to kDragX1 (pixels), over the block right of the panel.
constexpr int kDragX0 = 560, kDragX1 = 740, kDragY = 300;
/// The panel's corner of the window (what it covers at 640 x 480, with room to spare): its
/// figures change from run to run, so comparisons leave it out.
constexpr int kPanelRight = 350, kPanelBottom = 480;

bool haveDisplay() {
    if (std::getenv("DISPLAY")) return true;
    if (std::getenv("KIZAMU_REQUIRE_DISPLAY")) ADD_FAILURE() << "no DISPLAY, and KIZAMU_REQUIRE_DISPLAY is set";
    return false;
}

class SculptAppTest : public ::testing::Test {
protected:
    void SetUp() override {
        mDir = fs::temp_directory_path() / ("kizamu_sculpt_" + std::to_string(::getpid()) + "_" +
                                            ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(mDir);
        fs::create_directories(mDir);
    }
    void TearDown() override {
        if (!std::getenv("KIZAMU_KEEP")) fs::remove_all(mDir);
    }

    /// Runs kizamu sculpt with `args` in a `width` x `height` window; returns its exit status, its
    /// output in `out`.
    int sculpt(const std::string& args, std::string* out = nullptr, const std::string& env = "", int width = kW, int height = kH) {
        const std::string log = (mDir / "log.txt").string();
        const std::string cmd = env + " " KIZAMU_EXECUTABLE " sculpt --device none --width " + std::to_string(width) + " --height " +
                                std::to_string(height) + " --session-root " + (mDir / "sessions").string() + " " + args + " >" +
                                log + " 2>&1";
        const int status = std::system(cmd.c_str());
        if (out) {
            std::ifstream in(log);
            out->assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
        }
        return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    }
    std::string script(const std::string& name, const std::string& events) {
        const std::string path = (mDir / name).string();
        std::ofstream(path) << "{\"kizamu_input\": 1, \"size\": [" << kW << ", " << kH << "]}\n" << events;
        return path;
    }
    /// The groove's drag: from (kDragX0, kDragY) to (kDragX1, kDragY) 10 px a frame, then released.
    static std::string drag() {
        const std::string y = std::to_string(kDragY);
        std::string e = "{\"frame\": 5, \"move\": [" + std::to_string(kDragX0) + ", " + y + "]}\n{\"frame\": 6, \"press\": \"left\"}\n";
        const int steps = (kDragX1 - kDragX0) / 10;
        for (int i = 1; i <= steps; ++i)
            e += "{\"frame\": " + std::to_string(6 + i) + ", \"move\": [" + std::to_string(kDragX0 + 10 * i) + ", " + y + "]}\n";
        return e + "{\"frame\": " + std::to_string(8 + steps) + ", \"release\": \"left\"}\n";
    }
    /// Pixels outside the panel that differ by more than `tolerance` in any channel, and how far
    /// the farthest of them is from the drag's line.
    static int changed(const render::Image& a, const render::Image& b, int tolerance, double* farthest = nullptr) {
        int n = 0;
        double far = 0.0;
        for (int y = 0; y < a.height; ++y)
            for (int x = 0; x < a.width; ++x) {
                if (x < kPanelRight && y < kPanelBottom) continue;
                const auto p = a.at(x, y), q = b.at(x, y);
                const int d = std::max({std::abs(p.r - q.r), std::abs(p.g - q.g), std::abs(p.b - q.b)});
                if (d <= tolerance) continue;
                ++n;
                const double dx = x < kDragX0 ? kDragX0 - x : (x > kDragX1 ? x - kDragX1 : 0), dy = std::abs(y - kDragY);
                far = std::max(far, std::hypot(dx, dy));
            }
        if (farthest) *farthest = far;
        return n;
    }
    fs::path mDir;
};

TEST_F(SculptAppTest, AScriptedDragCarvesWhereTheCursorWentAndUndoRestoresThePixels) {
    if (!haveDisplay()) GTEST_SKIP() << "no display";
    const std::string before = (mDir / "before.png").string(), after = (mDir / "after.png").string(),
                      undone = (mDir / "undone.png").string();
    ASSERT_EQ(sculpt("--frames 40 --screenshot " + before), 0);
    std::string out;
    ASSERT_EQ(sculpt("--frames 40 --input " + script("drag.input.jsonl", drag()) + " --screenshot " + after, &out), 0) << out;
    EXPECT_NE(out.find("1 strokes"), std::string::npos) << out;
    // The summary's sample-to-visible latency: the carve's samples reached the screen.
    const auto latencyAt = out.find("sample to visible median ");
    ASSERT_NE(latencyAt, std::string::npos) << out;
    double latencyMs = 0.0;
    std::size_t latencyFrames = 0;
    ASSERT_EQ(std::sscanf(out.c_str() + latencyAt, "sample to visible median %lf ms over %zu frames", &latencyMs, &latencyFrames), 2) << out;
    std::printf("[ sculpt ] sample to visible: median %.2f ms over %zu frames\n", latencyMs, latencyFrames);
    EXPECT_TRUE(std::isfinite(latencyMs) && latencyMs > 0.0) << out;
    EXPECT_GT(latencyFrames, 0u) << out;
    ASSERT_EQ(sculpt("--frames 40 --input " +
                     script("undo.input.jsonl", drag() + "{\"frame\": 32, \"key\": \"z\", \"mods\": [\"ctrl\"]}\n"
                                                   "{\"frame\": 33, \"move\": [" + std::to_string(kW - 10) + ", 10]}\n") +  // off the clay: no tool ring
                     " --screenshot " + undone),
              0);
    const render::Image a = render::readPng(before), b = render::readPng(after), c = render::readPng(undone);
    ASSERT_EQ(a.width, kW);
    ASSERT_EQ(a.height, kH);
    double farthest = 0.0;
    const int groove = changed(a, b, 24, &farthest);
    std::printf("[ sculpt ] the drag changed %d pixels, the farthest %.0f px from its line; after undo %d differ\n", groove, farthest,
                changed(a, c, 24));
    EXPECT_GT(groove, 500) << "a groove is visible";
    EXPECT_LT(farthest, 60.0) << "nothing changed away from where the cursor went";
    EXPECT_LT(changed(a, c, 24), 20) << "Ctrl+Z restored the pixels";
    // The panel is drawn: its title bar, in the window's top left corner, is not the background.
    const auto bg = a.at(kW - 5, 5), title = a.at(200, 18);
    EXPECT_GT(std::abs(int(title.b) - int(bg.b)) + std::abs(int(title.r) - int(bg.r)), 30);
}

TEST_F(SculptAppTest, ADroppedMeshOpensAsASessionAndAnInterruptedSessionIsRestored) {
    if (!haveDisplay()) GTEST_SKIP() << "no display";
    // An octahedron, 8 cm across, in millimetres (OBJ's default unit here).
    const std::string obj = (mDir / "octahedron.obj").string();
    std::ofstream(obj) << "v 40 0 0\nv -40 0 0\nv 0 40 0\nv 0 -40 0\nv 0 0 40\nv 0 0 -40\n"
                          "f 1 3 5\nf 3 2 5\nf 2 4 5\nf 4 1 5\nf 3 1 6\nf 2 3 6\nf 4 2 6\nf 1 4 6\n";
    std::string out;
    ASSERT_EQ(sculpt("--frames 30 --input " + script("drop.input.jsonl", "{\"frame\": 3, \"drop\": \"octahedron.obj\"}\n"), &out), 0)
        << out;
    const auto at = out.find("sculpt: session ");
    ASSERT_NE(at, std::string::npos) << out;
    const std::string session = out.substr(at + 16, out.find(',', at) - at - 16);
    EXPECT_TRUE(fs::exists(fs::path(session) / "start.kza")) << "the dropped mesh became the session's clay: " << out;

    // A session left open by a process that died: its lock file remains, held by nobody.
    const fs::path crashed = mDir / "sessions" / "untitled-crashed";
    ASSERT_EQ(sculpt("--frames 2 --session " + crashed.string()), 0);
    std::ofstream(crashed / "lock") << "999999\n";
    ASSERT_TRUE(sculpt::SessionLock::interrupted(crashed.string()));
    ASSERT_EQ(sculpt("--frames 2 --restore yes", &out), 0) << out;
    EXPECT_NE(out.find("sculpt: session " + crashed.string()), std::string::npos) << out;
    EXPECT_FALSE(sculpt::SessionLock::interrupted(crashed.string())) << "closed cleanly this time";
}

/// The session the run's summary line names ("sculpt: session DIR, N strokes").
std::string summarySession(const std::string& out) {
    const auto at = out.find("sculpt: session ");
    if (at == std::string::npos) return {};
    return out.substr(at + 16, out.find(',', at) - at - 16);
}

TEST_F(SculptAppTest, SaveAsJournalsTheSessionToTheNewDirectoryAndCtrlOOpensSessionsAndMeshes) {
    if (!haveDisplay()) GTEST_SKIP() << "no display";
    // A stroke, then Ctrl+Shift+S, a directory typed into the browser's path field, Enter; then
    // a second stroke, which goes to the new directory's journal.
    const std::string named = (mDir / "named-session").string();
    std::string second = drag();
    for (std::size_t at = second.find("\"frame\": "); at != std::string::npos; at = second.find("\"frame\": ", at + 1)) {
        const std::size_t from = at + 9, to = second.find(',', from);
        second.replace(from, to - from, std::to_string(std::stoi(second.substr(from, to - from)) + 40));
    }
    const std::string saveAs = drag() + "{\"frame\": 32, \"key\": \"s\", \"mods\": [\"ctrl\", \"shift\"]}\n"
                               "{\"frame\": 33, \"text\": \"" + named + "\"}\n{\"frame\": 34, \"key\": \"enter\"}\n" + second;
    std::string out;
    ASSERT_EQ(sculpt("--frames 80 --input " + script("saveas.input.jsonl", saveAs), &out), 0) << out;
    EXPECT_EQ(summarySession(out), named) << "the session in use is the new one: " << out;
    EXPECT_EQ(out.find("untitled"), std::string::npos) << out;
    ASSERT_TRUE(sculpt::isSessionDir(named)) << out;
    const auto journal = sculpt::Session::open(named, nullptr, nullptr, true)->journal();
    EXPECT_EQ(std::count_if(journal.steps.begin(), journal.steps.end(), [](const sculpt::Step& st) { return st.kind == sculpt::Step::Kind::Stroke; }), 2)
        << "both strokes are in the new journal";

    // Ctrl+O, a session's path typed, Enter: the session is reopened.
    ASSERT_EQ(sculpt("--frames 12 --input " +
                         script("open.input.jsonl", "{\"frame\": 2, \"key\": \"o\", \"mods\": [\"ctrl\"]}\n"
                                                    "{\"frame\": 3, \"text\": \"" + named + "\"}\n{\"frame\": 4, \"key\": \"enter\"}\n"),
                     &out),
              0)
        << out;
    EXPECT_EQ(summarySession(out), named) << out;
    // Ctrl+O on a mesh: typed in two parts, the first with a wrong last letter erased.
    const std::string obj = (mDir / "octahedron.obj").string();
    std::ofstream(obj) << "v 40 0 0\nv -40 0 0\nv 0 40 0\nv 0 -40 0\nv 0 0 40\nv 0 0 -40\n"
                          "f 1 3 5\nf 3 2 5\nf 2 4 5\nf 4 1 5\nf 3 1 6\nf 2 3 6\nf 4 2 6\nf 1 4 6\n";
    const std::string half = obj.substr(0, obj.size() / 2), rest = obj.substr(obj.size() / 2);
    ASSERT_EQ(sculpt("--frames 30 --input " +
                         script("import.input.jsonl", "{\"frame\": 2, \"key\": \"o\", \"mods\": [\"ctrl\"]}\n"
                                                      "{\"frame\": 3, \"text\": \"" + half + "Q\"}\n{\"frame\": 4, \"key\": \"backspace\"}\n"
                                                      "{\"frame\": 5, \"text\": \"" + rest + "\"}\n{\"frame\": 6, \"key\": \"enter\"}\n"),
                     &out),
              0)
        << out;
    EXPECT_TRUE(fs::exists(fs::path(summarySession(out)) / "start.kza")) << "the mesh became the session's clay: " << out;
}

TEST_F(SculptAppTest, LevelElevenMakesALevelElevenBlock) {
    if (!haveDisplay()) GTEST_SKIP() << "no display";
    const std::string dir = (mDir / "fine").string();
    std::string out;
    ASSERT_EQ(sculpt("--frames 3 --level 11 --session " + dir, &out), 0) << out;
    ASSERT_TRUE(sculpt::isSessionDir(dir)) << out;
    EXPECT_EQ(sculpt::Session::open(dir, nullptr, nullptr, true)->journal().domain.maxLevel, 11);
}

TEST_F(SculptAppTest, ASmallWindowFramesTheBlockRightOfThePanel) {
    if (!haveDisplay()) GTEST_SKIP() << "no display";
    const std::string png = (mDir / "small.png").string();
    std::string out;
    ASSERT_EQ(sculpt("--frames 20 --screenshot " + png, &out, "", 640, 480), 0) << out;
    const render::Image img = render::readPng(png);
    ASSERT_EQ(img.width, 640);
    // The clay is light (the background and the floor are darker): its pixels outside the
    // panel, and where their middle lies.
    long count = 0;
    double sumX = 0.0;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            if (x < kPanelRight && y < kPanelBottom) continue;
            const auto p = img.at(x, y);
            if (std::min({p.r, p.g, p.b}) < 150) continue;
            ++count;
            sumX += x;
        }
    ASSERT_GT(count, 5000) << "the block is in view";
    std::printf("[ sculpt ] at 640 x 480: %ld clay pixels, their middle at x = %.0f\n", count, sumX / double(count));
    EXPECT_GT(sumX / double(count), kPanelRight + 100.0) << "the block is framed right of the panel, not under it";
}

TEST_F(SculptAppTest, AShaderThatDoesNotCompileIsAClearError) {
    if (!haveDisplay()) GTEST_SKIP() << "no display";
    const fs::path shaders = mDir / "shaders";
    fs::create_directories(shaders);
    for (const auto& e : fs::directory_iterator(KIZAMU_SOURCE_SHADER_DIR)) fs::copy_file(e.path(), shaders / e.path().filename());
    std::ofstream(shaders / "clay.frag", std::ios::app) << "\nthis is not GLSL;\n";
    std::string out;
    EXPECT_NE(sculpt("--frames 2", &out, "KIZAMU_SHADER_DIR=" + shaders.string()), 0);
    EXPECT_NE(out.find("clay.frag:"), std::string::npos) << out;
    EXPECT_NE(out.find("error"), std::string::npos) << out;
}

}  // namespace
}  // namespace kizamu
