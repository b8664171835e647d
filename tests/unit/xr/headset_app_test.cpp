// SPDX-License-Identifier: Apache-2.0
// Sculpting in a headset end to end, under a display (Xvfb from scripts/test): the real `kizamu
// sculpt --xr` on Debian's OpenXR loader with the project's simulated runtime (XR_RUNTIME_JSON;
// sim/openxr/), its controllers scripted through XR_EXT_conformance_automation (docs/INPUT.md),
// the eyes' last images and the runtime's events read from its capture directory
// (KIZAMU_XRSIM_CAPTURE; docs/XR-SIM.md). The session reaches FOCUSED and ends cleanly; a
// scripted controller carves a groove seen in both eyes and vibrates on contact; two hands move
// and scale the clay; the panel's pointer clicks Undo; the eyes are sRGB; a registered stylus
// carves where the clay is seen; all of it with Khronos' core validation layer enabled and
// silent.
#include "render/image.h"

#include <glm/vec3.hpp>
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace kizamu {
namespace {

namespace fs = std::filesystem;

constexpr int kFrames = 80;
/// Every script ends with the hands out of sight (behind the headset), so the last images show
/// the clay alone.
constexpr const char* kHandsAway = "{\"frame\": 70, \"controller\": \"right\", \"position\": [0.0, 0.0, 1.0], \"trigger\": 0.0, \"squeeze\": 0.0}\n"
                                   "{\"frame\": 70, \"controller\": \"left\", \"position\": [-0.1, 0.0, 1.0], \"trigger\": 0.0, \"squeeze\": 0.0}\n";

bool haveDisplay() {
    if (std::getenv("DISPLAY")) return true;
    if (std::getenv("KIZAMU_REQUIRE_DISPLAY")) ADD_FAILURE() << "no DISPLAY, and KIZAMU_REQUIRE_DISPLAY is set";
    return false;
}

std::string slurp(const fs::path& p) {
    std::ifstream in(p);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

std::string controller(int frame, const char* hand, const std::string& fields) {
    return "{\"frame\": " + std::to_string(frame) + ", \"controller\": \"" + hand + "\", " + fields + "}\n";
}

std::string position(double x, double y, double z) {
    std::ostringstream s;
    s << "\"position\": [" << x << ", " << y << ", " << z << "]";
    return s.str();
}

/// The right hand carves across the clay's front face (which faces the headset at z = -0.29 m:
/// the 12 cm block appears 0.35 m ahead and 0.15 m down) with the trigger held.
std::string carve() {
    std::string e = controller(2, "right", position(-0.04, -0.15, -0.284)) + controller(6, "right", "\"trigger\": 1.0");
    for (int i = 0; i <= 30; ++i) e += controller(7 + i, "right", position(-0.04 + 0.08 * i / 30.0, -0.15, -0.284));
    return e + controller(40, "right", "\"trigger\": 0.0") + controller(41, "right", position(0.0, 0.0, 1.0));
}

/// The same groove, with the tool held still at its start for a quarter of a second or more
/// first: a stylus carves at its proxy's removal rate, so its dent there is deep at any frame rate.
std::string carveHoldingFirst() {
    std::string e = controller(2, "right", position(-0.04, -0.15, -0.284)) + controller(6, "right", "\"trigger\": 1.0");
    for (int i = 0; i <= 30; ++i) e += controller(22 + i, "right", position(-0.04 + 0.08 * i / 30.0, -0.15, -0.284));
    return e + controller(54, "right", "\"trigger\": 0.0") + controller(55, "right", position(0.0, 0.0, 1.0));
}

struct XrRun {
    int status = -1;
    std::string output, events;
    render::Image left, right;
};

class HeadsetAppTest : public ::testing::Test {
protected:
    void SetUp() override {
        mDir = fs::temp_directory_path() / ("kizamu_xr_" + std::to_string(::getpid()) + "_" +
                                            ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(mDir);
        fs::create_directories(mDir);
    }
    void TearDown() override {
        if (!std::getenv("KIZAMU_KEEP")) fs::remove_all(mDir);
    }

    /// Runs kizamu sculpt --xr for kFrames frames with the controller events `events` (plus the
    /// hands put away) and reads what the runtime captured.
    XrRun sculpt(const std::string& name, const std::string& events, const std::string& args = "", const std::string& env = "") {
        const fs::path capture = mDir / name;
        fs::create_directories(capture);
        const fs::path script = mDir / (name + ".input.jsonl");
        std::ofstream(script) << "{\"kizamu_input\": 1}\n" << events << kHandsAway;
        const fs::path log = capture / "log.txt";
        // Every run with Khronos' core validation layer, which writes its report only when it
        // has something to say.
        const fs::path report = capture / "validation.txt";
        const std::string cmd = "XR_RUNTIME_JSON=" KIZAMU_XRSIM_MANIFEST " KIZAMU_XRSIM_CAPTURE=" + capture.string() +
                                " XR_CORE_VALIDATION_EXPORT_TYPE=text XR_CORE_VALIDATION_FILE_NAME=" + report.string() + " " + env +
                                " " KIZAMU_EXECUTABLE " sculpt --xr " + (args.find("--device") == std::string::npos ? "--device none " : "") +
                                "--width 640 --height 480 --session-root " +
                                (mDir / "sessions").string() + " --frames " + std::to_string(kFrames) + " --input " +
                                script.string() + " --screenshot " + (capture / "mirror.png").string() + " --xr-validation " + args + " >" +
                                log.string() + " 2>&1";
        XrRun r;
        const int status = std::system(cmd.c_str());
        r.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
        r.output = slurp(log);
        r.events = slurp(capture / "events.jsonl");
        if (fs::exists(capture / "left.png")) r.left = render::readPng((capture / "left.png").string());
        if (fs::exists(capture / "right.png")) r.right = render::readPng((capture / "right.png").string());
        EXPECT_NE(r.output.find("Core Validation"), std::string::npos) << name << ": the validation layer did not load\n" << r.output;
        if (fs::exists(report)) ADD_FAILURE() << name << ": the core validation layer reported\n" << slurp(report);
        return r;
    }
    fs::path mDir;
};

/// Pixels differing by more than `tolerance` in any channel, and their bounding box.
struct Difference {
    int count = 0;
    int x0 = 1 << 30, y0 = 1 << 30, x1 = -1, y1 = -1;
};
Difference difference(const render::Image& a, const render::Image& b, int tolerance = 24) {
    Difference d;
    for (int y = 0; y < std::min(a.height, b.height); ++y)
        for (int x = 0; x < std::min(a.width, b.width); ++x) {
            const auto p = a.at(x, y), q = b.at(x, y);
            if (std::max({std::abs(p.r - q.r), std::abs(p.g - q.g), std::abs(p.b - q.b)}) <= tolerance) continue;
            ++d.count;
            d.x0 = std::min(d.x0, x), d.y0 = std::min(d.y0, y), d.x1 = std::max(d.x1, x), d.y1 = std::max(d.y1, y);
        }
    return d;
}

/// The clay's bounding box in an eye's image: the pixels that are not the background's colour.
Difference clayBox(const render::Image& eye) {
    render::Image background = eye;
    const auto corner = eye.at(0, 0);
    for (int y = 0; y < eye.height; ++y)
        for (int x = 0; x < eye.width; ++x) {
            auto* p = &background.pixels[(std::size_t(y) * std::size_t(eye.width) + std::size_t(x)) * 4];
            p[0] = corner.r, p[1] = corner.g, p[2] = corner.b;
        }
    return difference(eye, background, 12);
}

int count(const std::string& text, const std::string& what) {
    int n = 0;
    for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
    return n;
}

TEST_F(HeadsetAppTest, TheSessionReachesFocusedAndEndsCleanly) {
    if (!haveDisplay()) GTEST_SKIP() << "no display";
    const XrRun r = sculpt("lifecycle", "");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("xr: OpenXR: Kizamu simulated runtime"), std::string::npos) << r.output;
    // The specification's order, through to the end the app asked for.
    std::size_t at = 0;
    for (const char* state : {"\"READY\"", "\"SYNCHRONIZED\"", "\"VISIBLE\"", "\"FOCUSED\"", "\"STOPPING\"", "\"IDLE\"", "\"EXITING\""}) {
        at = r.events.find(state, at);
        ASSERT_NE(at, std::string::npos) << state << " missing or out of order in\n" << r.events;
    }
    ASSERT_GT(r.left.width, 0);
    EXPECT_GT(clayBox(r.left).count, 1000) << "the clay is not in the left eye";
    EXPECT_GT(clayBox(r.right).count, 1000) << "the clay is not in the right eye";
    // Two eyes, two viewpoints: the clay sits further left in the right eye.
    EXPECT_LT(clayBox(r.right).x0, clayBox(r.left).x0);
}

TEST_F(HeadsetAppTest, AScriptedControllerCarvesAGrooveSeenInBothEyesAndVibratesOnContact) {
    if (!haveDisplay()) GTEST_SKIP() << "no display";
    const XrRun untouched = sculpt("untouched", "");
    const XrRun carved = sculpt("carved", carve());
    ASSERT_EQ(carved.status, 0) << carved.output;
    EXPECT_NE(carved.output.find("1 strokes"), std::string::npos) << carved.output;
    for (const auto& [name, a, b] : {std::tuple{"left", &untouched.left, &carved.left}, std::tuple{"right", &untouched.right, &carved.right}}) {
        const Difference d = difference(*a, *b);
        const Difference clay = clayBox(*a);
        EXPECT_GT(d.count, 200) << name << " eye: no groove";
        // A groove: wider than tall, inside the clay's outline.
        EXPECT_GT(d.x1 - d.x0, 3 * (d.y1 - d.y0)) << name;
        EXPECT_GE(d.x0, clay.x0) << name;
        EXPECT_LE(d.x1, clay.x1) << name;
    }
    EXPECT_GT(count(carved.events, "\"haptic\""), 10) << "no vibration on contact";
    EXPECT_NE(carved.events.find("/user/hand/right"), std::string::npos);
    EXPECT_EQ(count(untouched.events, "\"haptic\""), 0) << "vibration with nothing touched";
}

TEST_F(HeadsetAppTest, TwoHandsMoveAndScaleTheClay) {
    if (!haveDisplay()) GTEST_SKIP() << "no display";
    // Both hands take hold 20 cm apart, then part to 30 cm with their midpoint 3 cm to the right.
    std::string grab = controller(2, "left", position(-0.1, -0.15, -0.25)) + controller(2, "right", position(0.1, -0.15, -0.25)) +
                       controller(6, "left", "\"squeeze\": 1.0") + controller(6, "right", "\"squeeze\": 1.0");
    for (int i = 1; i <= 10; ++i) {
        const double half = 0.1 + 0.05 * i / 10.0, shift = 0.03 * i / 10.0;
        grab += controller(8 + i, "left", position(shift - half, -0.15, -0.25)) + controller(8 + i, "right", position(shift + half, -0.15, -0.25));
    }
    grab += controller(22, "left", "\"squeeze\": 0.0") + controller(22, "right", "\"squeeze\": 0.0");
    const XrRun still = sculpt("still", "");
    const XrRun moved = sculpt("moved", grab);
    ASSERT_EQ(moved.status, 0) << moved.output;
    const Difference before = clayBox(still.left), after = clayBox(moved.left);
    const double widthRatio = double(after.x1 - after.x0) / double(before.x1 - before.x0);
    EXPECT_GT(widthRatio, 1.3) << "the clay was not scaled up";
    EXPECT_LT(widthRatio, 1.7);
    EXPECT_GT(0.5 * (after.x0 + after.x1), 0.5 * (before.x0 + before.x1) + 5) << "the clay did not move right";
    EXPECT_NE(moved.output.find("0 strokes"), std::string::npos) << "a grab sculpted\n" << moved.output;
}

TEST_F(HeadsetAppTest, ThePanelsPointerClicksUndo) {
    if (!haveDisplay()) GTEST_SKIP() << "no display";
    // The left hand 20 cm in front of the panel (HeadsetSession::panelPose: 0.6 rad about Y at
    // (-0.32, -0.05, -0.42)), aiming straight at its Undo button (pixels 18..54 x 225..244 of
    // 480 x 560, the panel's fixed layout), clicks with the trigger after the carve.
    const std::string aim = "\"orientation\": [0.0, 0.29552, 0.0, 0.95534]";
    const std::string click = controller(45, "left", position(-0.3123, -0.0216, -0.1829) + ", " + aim) +
                              controller(48, "left", "\"trigger\": 1.0") + controller(52, "left", "\"trigger\": 0.0") +
                              controller(56, "left", position(-0.1, 0.0, 1.0));
    const XrRun untouched = sculpt("untouched", "");
    const XrRun carvedOnly = sculpt("carved", carve());
    const XrRun undone = sculpt("undone", carve() + click);
    ASSERT_EQ(undone.status, 0) << undone.output;
    EXPECT_GT(difference(untouched.left, carvedOnly.left).count, 200) << "the carve did nothing to undo";
    EXPECT_LT(difference(untouched.left, undone.left).count, 20) << "the panel's Undo did not restore the clay";
    EXPECT_LT(difference(untouched.right, undone.right).count, 20);
}

TEST_F(HeadsetAppTest, TheRuntimeEndingOrLosingTheSessionEndsTheAppCleanly) {
    if (!haveDisplay()) GTEST_SKIP() << "no display";
    const XrRun stopped = sculpt("stopped", carve(), "", "KIZAMU_XRSIM_STOP_AT_FRAME=20");
    ASSERT_EQ(stopped.status, 0) << stopped.output;
    EXPECT_NE(stopped.output.find("xr: the runtime ended the session"), std::string::npos) << stopped.output;
    std::size_t at = stopped.events.find("\"FOCUSED\"");
    for (const char* state : {"\"STOPPING\"", "\"IDLE\"", "\"EXITING\""}) {
        at = stopped.events.find(state, at);
        ASSERT_NE(at, std::string::npos) << state << " missing or out of order in\n" << stopped.events;
    }
    EXPECT_NE(stopped.output.find("sculpt: session"), std::string::npos) << "no summary: not a clean exit\n" << stopped.output;

    const XrRun lost = sculpt("lost", carve(), "", "KIZAMU_XRSIM_LOSE_AT_FRAME=20");
    ASSERT_EQ(lost.status, 0) << lost.output;
    EXPECT_NE(lost.output.find("xr: the runtime lost the session"), std::string::npos) << lost.output;
    EXPECT_NE(lost.events.find("\"LOSS_PENDING\""), std::string::npos) << lost.events;
    EXPECT_NE(lost.output.find("sculpt: session"), std::string::npos) << lost.output;
}

TEST_F(HeadsetAppTest, TheEyesAreSrgbAsTheDesktopIs) {
    if (!haveDisplay()) GTEST_SKIP() << "no display";
    // The background is RenderSettings' sRGB (0.235, 0.240, 0.255): the swapchain is sRGB and the
    // shaders write encoded values, so the stored bytes are those values, not encoded twice.
    const XrRun r = sculpt("srgb", "");
    ASSERT_EQ(r.status, 0) << r.output;
    for (const render::Image* eye : {&r.left, &r.right}) {
        ASSERT_GT(eye->width, 0);
        const auto corner = eye->at(2, 2);
        EXPECT_NEAR(corner.r, 60, 1);
        EXPECT_NEAR(corner.g, 61, 1);
        EXPECT_NEAR(corner.b, 65, 1);
    }
}

TEST_F(HeadsetAppTest, WithoutARuntimeItSaysSoInOneLineAndSculptsOnTheDesktop) {
    if (!haveDisplay()) GTEST_SKIP() << "no display";
    const fs::path log = mDir / "log.txt";
    const std::string cmd = "env -u XR_RUNTIME_JSON XDG_CONFIG_HOME=" + (mDir / "config").string() + " XDG_CONFIG_DIRS=" +
                            (mDir / "etc").string() + " " KIZAMU_EXECUTABLE " sculpt --xr --device none --frames 3 --session-root " +
                            (mDir / "sessions").string() + " >" + log.string() + " 2>&1";
    const int status = std::system(cmd.c_str());
    const std::string out = slurp(log);
    ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << out;
    if (fs::exists("/etc/openxr/1/active_runtime.json")) GTEST_SKIP() << "this machine has an OpenXR runtime installed";
    EXPECT_EQ(count(out, "xr: "), 1) << out;
    EXPECT_NE(out.find("no OpenXR runtime is installed"), std::string::npos) << out;
    EXPECT_NE(out.find("sculpt: session"), std::string::npos) << out;
}

TEST_F(HeadsetAppTest, AStylusRegisteredInTheHeadsetCarvesWhereTheClayIsSeen) {
    if (!haveDisplay()) GTEST_SKIP() << "no display";
    // The simulated stylus's hand is the controller: four touches in the air around the block
    // (inside its domain, not on one plane), the trigger pulled at each.
    std::string touches;
    int frame = 2;
    for (const auto& p : {glm::dvec3(0.08, -0.07, -0.27), glm::dvec3(-0.08, -0.07, -0.27), glm::dvec3(0.08, -0.07, -0.43),
                          glm::dvec3(-0.08, -0.23, -0.27)}) {
        touches += controller(frame, "right", position(p.x, p.y, p.z)) + controller(frame + 6, "right", "\"trigger\": 1.0") +
                   controller(frame + 13, "right", "\"trigger\": 0.0");
        frame += 15;
    }
    const std::string config = "XDG_CONFIG_HOME=" + (mDir / "config").string();
    const XrRun registering = sculpt("registering", touches, "--device sim --register-stylus", config);
    ASSERT_EQ(registering.status, 0) << registering.output;
    const std::size_t at = registering.output.find("stylus registered: ");
    ASSERT_NE(at, std::string::npos) << registering.output;
    EXPECT_LT(std::strtod(registering.output.c_str() + at + 19, nullptr), 2.0) << "rms (mm) too large: " << registering.output;
    ASSERT_TRUE(fs::exists(mDir / "config" / "kizamu" / "stylus-registration.json"));

    // With the registration kept, the stylus (its hand still the controller) starts its groove
    // where the controller alone starts it (it carves at the proxy's removal rate, so its
    // groove is shorter than the controller's sweep).
    const XrRun untouched = sculpt("untouched", "");
    const XrRun alone = sculpt("alone", carveHoldingFirst());
    const XrRun stylus = sculpt("stylus", carveHoldingFirst(), "--device sim", config);
    ASSERT_EQ(stylus.status, 0) << stylus.output;
    const Difference a = difference(untouched.left, alone.left), b = difference(untouched.left, stylus.left);
    ASSERT_GT(b.count, 100) << "the stylus carved nothing\n" << stylus.output;
    EXPECT_NEAR(a.x0, b.x0, 12.0);
    EXPECT_NEAR(0.5 * (a.y0 + a.y1), 0.5 * (b.y0 + b.y1), 12.0);
    EXPECT_EQ(count(stylus.events, "\"haptic\""), 0) << "the controller vibrated while the stylus carries the forces";
}

TEST_F(HeadsetAppTest, TheBenchmarkReportsItsFigures) {
    if (!haveDisplay()) GTEST_SKIP() << "no display";
    const fs::path log = mDir / "bench.jsonl";
    const std::string cmd = "XR_RUNTIME_JSON=" KIZAMU_XRSIM_MANIFEST " " KIZAMU_EXECUTABLE " bench xr --json --frames 5 --edits 2 >" +
                            log.string() + " 2>/dev/null";
    const int status = std::system(cmd.c_str());
    const std::string out = slurp(log);
    ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << out;
    for (const char* figure : {"\"xr.frame_ms\"", "\"xr.edit_to_visible_frames\""}) {
        const std::size_t at = out.find(figure);
        ASSERT_NE(at, std::string::npos) << figure << " missing:\n" << out;
        const std::size_t value = out.find("\"value\":", at);
        ASSERT_NE(value, std::string::npos) << out;
        const double v = std::strtod(out.c_str() + value + 8, nullptr);
        EXPECT_TRUE(std::isfinite(v) && v >= 0.0) << figure << " = " << v;
    }
}

}  // namespace
}  // namespace kizamu
