// SPDX-License-Identifier: Apache-2.0
// The live engine (engine.h) end to end on small clay: samples become live strokes that change
// the clay before release and end as one undo and one journal record; replaying the journal
// gives the live clay bit for bit; cancel, tool changes, undo and redo; the consumer's mesh
// mirror equals the mesh of the published clay at every barrier; background checkpoints;
// commands' errors; destroying a busy engine; a SIGKILL in the middle of a stroke.
#include "engine/engine.h"
#include "engine/trajectory_player.h"

#include "adf/adf_file.h"
#include "mesh/mesh_export.h"
#include "mesh/mesh_import.h"
#include "mesh/surface_nets.h"
#include "sculpt/script_start.h"
#include "sculpt/session.h"
#include "tests/util/icosphere.h"
#include "tests/util/mesh_check.h"

#include <glm/common.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <string>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>
#include <vector>

namespace kizamu {
namespace {

namespace fs = std::filesystem;
using engine::Engine;
using engine::EngineSettings;
using engine::ToolSample;

sculpt::Script slabScript(int level = 6) {
    sculpt::Script s;
    s.domain.maxLevel = level;
    s.domain.tileSpanLevels = 4;  // several tiles, so segments rebuild some and share the rest
    s.start.kind = sculpt::Shape::Kind::Box;  // top face at z = 0.5
    s.start.centre = {0.5, 0.5, 0.4};
    s.start.halfSize = {0.35, 0.35, 0.1};
    return s;
}

EngineSettings settingsFor(const std::string& dir = {}, int level = 6) {
    EngineSettings s;
    s.sessionDir = dir;
    s.start = slabScript(level);
    s.threads = 2;
    return s;
}

struct TempDir {
    fs::path path;
    explicit TempDir(const std::string& name) : path(fs::temp_directory_path() / ("kizamu-engine-" + name + "-" + std::to_string(::getpid()))) {
        fs::remove_all(path);
    }
    ~TempDir() { fs::remove_all(path); }
    std::string str() const { return path.string(); }
};

/// The published clay's bytes (one guard, cold path).
std::vector<std::byte> publishedBytes(Engine& e) {
    adf::SnapshotStore::Reader reader(e.snapshots());
    const auto guard = reader.acquire();
    return adf::encodeAdf(guard.adf());
}

/// A stroke across the slab's top, `n` samples 1 ms apart from `t0Ms`, then a release.
void addStroke(engine::Trajectory& t, int64_t t0Ms, int n, double y = 0.5, float strength = 1.0f) {
    for (int i = 0; i <= n; ++i) {
        ToolSample s;
        s.timeNs = (t0Ms + i) * 1'000'000;
        const double u = double(std::min(i, n - 1)) / double(n - 1);
        s.posWorld = glm::mix(glm::dvec3(0.3, y, 0.5), glm::dvec3(0.7, y + 0.1, 0.5), u);
        s.strength = strength;
        s.buttons = i < n ? engine::kButtonPrimary : 0u;
        t.add(s);
    }
}

engine::ToolChange toolChange(int64_t atMs, sculpt::ToolOp op, double h) {
    engine::ToolChange c;
    c.timeNs = atMs * 1'000'000;
    c.tool.op = op;
    c.tool.radius = 0.04;
    if (op == sculpt::ToolOp::Build) c.tool.amount = 2.0 * h;
    if (op == sculpt::ToolOp::HeatGun) c.tool.rate = 0.05;
    if (op == sculpt::ToolOp::Paint) {
        c.tool.colour = {200, 40, 10};
        c.tool.strength = 0.6;
    }
    return c;
}

void push(Engine& e, const ToolSample& s) {
    while (!e.samples().push(s)) std::this_thread::yield();
    while (!e.samples().flush()) std::this_thread::yield();
}

ToolSample held(int64_t ms, glm::dvec3 p, bool down = true) {
    ToolSample s;
    s.timeNs = ms * 1'000'000;
    s.posWorld = p;
    s.buttons = down ? engine::kButtonPrimary : 0u;
    return s;
}

TEST(Engine, AStrokeChangesTheClayBeforeReleaseAndIsOneUndoRecord) {
    Engine e(settingsFor());
    const std::vector<std::byte> start = publishedBytes(e);
    const uint64_t seq0 = e.snapshots().currentSequence();
    for (int i = 0; i < 20; ++i) push(e, held(i, {0.3 + 0.01 * i, 0.5, 0.5}));
    ASSERT_TRUE(e.sync().get().ok);
    EXPECT_TRUE(e.stroking());
    EXPECT_TRUE(publishedBytes(e) != start) << "the clay follows the stylus while the button is held";
    EXPECT_GT(e.snapshots().currentSequence(), seq0);
    const auto during = e.stats().segments;
    EXPECT_GE(during, 1u);
    for (int i = 20; i < 40; ++i) push(e, held(i, {0.3 + 0.01 * i, 0.5, 0.5}));
    push(e, held(40, {0.7, 0.5, 0.5}, false));
    ASSERT_TRUE(e.sync().get().ok);
    EXPECT_FALSE(e.stroking());
    EXPECT_EQ(e.stats().strokes, 1u);
    const std::vector<std::byte> carved = publishedBytes(e);
    const engine::CommandResult u = e.undo().get();
    ASSERT_TRUE(u.ok) << u.message;
    EXPECT_TRUE(u.message.empty()) << u.message;
    EXPECT_TRUE(publishedBytes(e) == start) << "one undo takes the whole stroke back";
    EXPECT_EQ(e.undo().get().message, "nothing to undo");
    ASSERT_TRUE(e.redo().get().ok);
    EXPECT_TRUE(publishedBytes(e) == carved);
}

TEST(Engine, JournalReplayEqualsTheLiveClayBitForBitForEveryTool) {
    const TempDir dir("replay");
    const double h = slabScript().domain.finestCellSize();
    engine::Trajectory t;
    int64_t ms = 0;
    int k = 0;
    for (sculpt::ToolOp op : {sculpt::ToolOp::Carve, sculpt::ToolOp::Add, sculpt::ToolOp::Build, sculpt::ToolOp::HeatGun,
                              sculpt::ToolOp::Smooth, sculpt::ToolOp::Flatten, sculpt::ToolOp::Paint}) {
        t.add(toolChange(ms, op, h));
        addStroke(t, ms + 1, 25, 0.2 + 0.1 * k, 0.5f + 0.02f * float(k));
        ++k;
        ms += 40;
    }
    std::vector<std::byte> live;
    {
        Engine e(settingsFor(dir.str()));
        const engine::PlaybackReport r = engine::play(e, t, {0.0, 0});
        EXPECT_TRUE(r.errors.empty());
        EXPECT_EQ(e.stats().strokes, 7u);
        EXPECT_GT(e.stats().segments, 7u * 10u) << "lock step cuts a segment per millisecond";
        live = publishedBytes(e);
    }
    const auto reopened = sculpt::Session::open(dir.str());
    EXPECT_EQ(reopened->steps(), 7u);
    for (const sculpt::Step& s : reopened->journal().steps) {
        ASSERT_TRUE(s.stroke.live.has_value());
        EXPECT_EQ(s.stroke.live->timesNs.size(), s.stroke.samples.size());
    }
    EXPECT_TRUE(adf::encodeAdf(*reopened->sculptor().current()) == live);
}

TEST(Engine, TheSameTrajectoryInLockStepGivesTheSameBits) {
    engine::Trajectory t;
    t.add(toolChange(0, sculpt::ToolOp::Carve, 0.0));
    addStroke(t, 1, 60);
    addStroke(t, 80, 30, 0.3);
    std::vector<std::byte> first;
    for (int run = 0; run < 2; ++run) {
        Engine e(settingsFor());
        engine::play(e, t, {0.0, 0});
        if (run == 0)
            first = publishedBytes(e);
        else
            EXPECT_TRUE(publishedBytes(e) == first);
    }
}

TEST(Engine, RetiredSnapshotsAreFreedWithoutAnotherPublish) {
    EngineSettings settings = settingsFor();
    settings.correctAfterIdle = std::chrono::milliseconds(0);  // no idle corrections: nothing publishes after the stroke
    Engine e(settings);
    adf::SnapshotStore::Reader reader(e.snapshots());
    {
        const auto guard = reader.acquire();  // holds the start snapshot through the stroke
        for (int i = 0; i < 10; ++i) push(e, held(i, {0.3 + 0.02 * i, 0.5, 0.5}));
        push(e, held(10, {0.5, 0.5, 0.5}, false));
        ASSERT_TRUE(e.sync().get().ok);
        EXPECT_GT(e.stats().retired, 0u) << "a guard from before the stroke keeps its snapshot";
        EXPECT_GT(guard.adf().domain().maxLevel, 0);
    }
    // Nothing is published from here on: the edit thread's timer frees them.
    for (int i = 0; i < 400 && e.stats().retired > 0; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    EXPECT_EQ(e.stats().retired, 0u);
}

TEST(Engine, CancelRestoresTheClayAndIgnoresTheRestOfThePress) {
    Engine e(settingsFor());
    const std::vector<std::byte> start = publishedBytes(e);
    for (int i = 0; i < 10; ++i) push(e, held(i, {0.3 + 0.02 * i, 0.5, 0.5}));
    ASSERT_TRUE(e.sync().get().ok);
    ASSERT_TRUE(publishedBytes(e) != start);
    ASSERT_TRUE(e.cancelStroke().get().ok);
    EXPECT_TRUE(publishedBytes(e) == start);
    for (int i = 10; i < 20; ++i) push(e, held(i, {0.3 + 0.02 * i, 0.5, 0.5}));
    ASSERT_TRUE(e.sync().get().ok);
    EXPECT_TRUE(publishedBytes(e) == start) << "the cancelled press carves nothing more";
    push(e, held(20, {0.7, 0.5, 0.5}, false));
    EXPECT_EQ(e.undo().get().message, "nothing to undo");
    EXPECT_EQ(e.stats().cancelled, 1u);
    EXPECT_EQ(e.stats().strokes, 0u);
    push(e, held(30, {0.5, 0.5, 0.5}));  // a new press carves again
    push(e, held(31, {0.5, 0.5, 0.5}, false));
    ASSERT_TRUE(e.sync().get().ok);
    EXPECT_EQ(e.stats().strokes, 1u);
}

TEST(Engine, ChangingTheToolEndsTheHeldStroke) {
    Engine e(settingsFor());
    for (int i = 0; i < 10; ++i) push(e, held(i, {0.3 + 0.02 * i, 0.5, 0.5}));
    ASSERT_TRUE(e.sync().get().ok);
    engine::ToolSettings add;
    add.tool.op = sculpt::ToolOp::Add;
    add.tool.radius = 0.02;
    ASSERT_TRUE(e.setTool(add).get().ok);
    EXPECT_EQ(e.stats().strokes, 1u);
    EXPECT_FALSE(e.stroking());
    for (int i = 10; i < 15; ++i) push(e, held(i, {0.3 + 0.02 * i, 0.5, 0.5}));
    ASSERT_TRUE(e.sync().get().ok);
    EXPECT_FALSE(e.stroking()) << "the rest of the press starts nothing";
    engine::ToolSettings bad = add;
    bad.tool.radius = -1.0;
    const engine::CommandResult r = e.setTool(bad).get();
    EXPECT_FALSE(r.ok);
    EXPECT_FALSE(r.message.empty());
}

TEST(Engine, TheMeshMirrorEqualsTheMeshOfThePublishedClayAtEveryBarrier) {
    Engine e(settingsFor({}, 7));
    mesh::MeshMirror mirror;
    auto check = [&](const char* when) {
        ASSERT_TRUE(e.sync().get().ok);
        for (int tries = 0; tries < 1000; ++tries) {  // the edit thread may hold the mailbox for an instant
            std::optional<mesh::MeshDelta> d = e.takeMeshDelta();
            if (!d) {
                std::this_thread::sleep_for(std::chrono::microseconds(100));
                continue;
            }
            ASSERT_TRUE(mirror.apply(std::move(*d))) << when;
            break;
        }
        const std::vector<std::byte> bytes = publishedBytes(e);
        mesh::MeshBuffers want = mesh::meshAdf(adf::decodeAdf(std::string(reinterpret_cast<const char*>(bytes.data()), bytes.size()), "published"));
        want.colours.clear();
        EXPECT_TRUE(test::canonical(mirror.flatten()) == test::canonical(want)) << when;
    };
    check("start");
    for (int i = 0; i < 30; ++i) push(e, held(i, {0.3 + 0.013 * i, 0.45 + 0.003 * i, 0.5}));
    check("held");
    push(e, held(30, {0.7, 0.5, 0.5}, false));
    check("released");
    ASSERT_TRUE(e.undo().get().ok);
    check("undo");
    ASSERT_TRUE(e.redo().get().ok);
    check("redo");
    e.requestFullMesh();
    mirror = mesh::MeshMirror();
    check("resync");
}

TEST(Engine, CommandsReportTheirErrorsAndSaveAndExportWrite) {
    const TempDir dir("commands");
    fs::create_directories(dir.path);
    EngineSettings settings = settingsFor();
    settings.correctAfterIdle = std::chrono::milliseconds(1);
    Engine e(settings);
    EXPECT_FALSE(e.save().get().ok) << "a session in memory has no checkpoints";
    EXPECT_FALSE(e.exportMesh((dir.path / "x.xyz").string()).get().ok);
    EXPECT_FALSE(e.exportMesh((dir.path / "x.stl").string(), "furlong").get().ok);
    EXPECT_FALSE(e.openSession((dir.path / "none").string()).get().ok);
    for (int i = 0; i < 5; ++i) push(e, held(i, {0.4 + 0.02 * i, 0.5, 0.5}));
    push(e, held(5, {0.5, 0.5, 0.5}, false));
    ASSERT_TRUE(e.sync().get().ok);
    for (int i = 0; i < 400 && e.stats().corrections == 0; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    EXPECT_EQ(e.stats().corrections, 1u) << "the idle edit thread makes the stroke's correction";
    const std::string kza = (dir.path / "clay.kza").string(), stl = (dir.path / "clay.stl").string();
    const engine::CommandResult saved = e.save(kza).get();
    ASSERT_TRUE(saved.ok) << saved.message;
    const engine::CommandResult exported = e.exportMesh(stl, "mm").get();
    ASSERT_TRUE(exported.ok) << exported.message;
    EXPECT_GT(fs::file_size(stl), 1000u);
    EXPECT_TRUE(adf::encodeAdf(*adf::loadAdf(kza)) == publishedBytes(e)) << "saved: the clay with its corrections made";
    // A decimated copy beside the export: about the asked fraction, closed as the full one is.
    const std::string ply = (dir.path / "clay.ply").string();
    EXPECT_FALSE(e.exportMesh(ply, "mm", 1.5).get().ok);
    const engine::CommandResult decimated = e.exportMesh(ply, "mm", 0.25).get();
    ASSERT_TRUE(decimated.ok) << decimated.message;
    const mesh::MeshBuffers full = mesh::importMesh(ply), copy = mesh::importMesh((dir.path / "clay.decimated.ply").string());
    EXPECT_NEAR(double(copy.triangleCount()) / double(full.triangleCount()), 0.25, 0.05) << decimated.message;
    EXPECT_TRUE(test::closedOrientedManifold(full));
    EXPECT_TRUE(test::closedOrientedManifold(copy));
}

TEST(Engine, NewAndOpenReplaceTheSessionAndResetTheMesh) {
    const TempDir a("open-a"), b("open-b");
    std::vector<std::byte> carvedA;
    {
        Engine e(settingsFor(a.str()));
        for (int i = 0; i < 5; ++i) push(e, held(i, {0.4 + 0.02 * i, 0.5, 0.5}));
        push(e, held(5, {0.5, 0.5, 0.5}, false));
        ASSERT_TRUE(e.sync().get().ok);
        carvedA = publishedBytes(e);
    }
    Engine e(settingsFor(b.str()));
    (void)e.takeMeshDelta();
    const engine::CommandResult opened = e.openSession(a.str()).get();
    ASSERT_TRUE(opened.ok) << opened.message;
    EXPECT_TRUE(publishedBytes(e) == carvedA);
    std::optional<mesh::MeshDelta> d = e.takeMeshDelta();
    ASSERT_TRUE(d.has_value());
    EXPECT_TRUE(d->reset);
    sculpt::Script sphere = slabScript(5);
    sphere.start.kind = sculpt::Shape::Kind::Sphere;
    ASSERT_TRUE(e.newSession({}, sphere).get().ok);
    EXPECT_TRUE(publishedBytes(e) == adf::encodeAdf(*sculpt::startAdf(sphere, 0)));
    EXPECT_FALSE(e.newSession(a.str(), sphere).get().ok) << "a directory with a session is opened, not overwritten";
}

/// The journal's steps of `kind` in the session in `dir` (idle corrections come and go with timing).
std::size_t stepsOf(const std::string& dir, sculpt::Step::Kind kind) {
    const sculpt::Script journal = sculpt::Session::open(dir, nullptr, nullptr, true)->journal();
    return std::size_t(std::count_if(journal.steps.begin(), journal.steps.end(), [&](const sculpt::Step& s) { return s.kind == kind; }));
}

TEST(Engine, SaveAsCopiesTheSessionAndLaterStrokesJournalToTheCopy) {
    const TempDir a("saveas-a"), b("saveas-b");
    const std::string copy = (b.path / "named").string();
    std::size_t oldSteps = 0;
    {
        Engine e(settingsFor(a.str()));
        for (int i = 0; i < 5; ++i) push(e, held(i, {0.4 + 0.02 * i, 0.5, 0.5}));
        push(e, held(5, {0.5, 0.5, 0.5}, false));
        const engine::CommandResult saved = e.saveSessionAs(copy).get();
        ASSERT_TRUE(saved.ok) << saved.message;
        EXPECT_TRUE(sculpt::isSessionDir(copy));
        EXPECT_FALSE(e.saveSessionAs(copy).get().ok) << "a directory with a session is never overwritten";
        oldSteps = sculpt::Session::open(a.str(), nullptr, nullptr, true)->steps();
        EXPECT_EQ(stepsOf(a.str(), sculpt::Step::Kind::Stroke), 1u);
        for (int i = 0; i < 5; ++i) push(e, held(10 + i, {0.4 + 0.02 * i, 0.6, 0.5}));
        push(e, held(15, {0.5, 0.6, 0.5}, false));
        ASSERT_TRUE(e.undo().get().ok);
        ASSERT_TRUE(e.undo().get().ok) << "the copy's undo history reaches the stroke made before Save As";
        ASSERT_TRUE(e.sync().get().ok);
        EXPECT_TRUE(publishedBytes(e) == adf::encodeAdf(*sculpt::startAdf(slabScript(), 0)));
    }
    EXPECT_EQ(sculpt::Session::open(a.str(), nullptr, nullptr, true)->steps(), oldSteps) << "the old directory stays as it was";
    EXPECT_EQ(stepsOf(copy, sculpt::Step::Kind::Stroke), 2u) << "the stroke after Save As is journaled in the copy";
    EXPECT_EQ(stepsOf(copy, sculpt::Step::Kind::Undo), 2u);
    Engine inMemory(settingsFor());
    EXPECT_FALSE(inMemory.saveSessionAs((b.path / "other").string()).get().ok);
}

TEST(Engine, AnImportedMeshBecomesASessionThatReopensBitForBit) {
    const TempDir dir("import");
    fs::create_directories(dir.path);
    // A closed sphere of radius 30 mm about the origin, written as OBJ in millimetres.
    const std::string obj = (dir.path / "ball.obj").string();
    mesh::ExportOptions mm;
    mm.unit = mesh::LengthUnit::Millimetre;
    mm.meshUnit = mesh::LengthUnit::Millimetre;  // the numbers as they are: 30 (mm)
    mesh::exportMesh(test::icosphere(30.0f, 3), obj, mm);
    const std::string sessionDir = (dir.path / "session").string();
    std::vector<std::byte> live;
    {
        EngineSettings settings = settingsFor();
        settings.correctAfterIdle = std::chrono::milliseconds(0);  // nothing changes after the barrier
        Engine e(settings);
        const std::vector<std::byte> before = publishedBytes(e);
        EXPECT_FALSE(e.importMesh((dir.path / "none.obj").string(), sessionDir, 6).get().ok);
        EXPECT_FALSE(e.importMesh(obj, sessionDir, 6, "furlong").get().ok);
        EXPECT_FALSE(e.importMesh(obj, sessionDir, 40).get().ok);
        EXPECT_TRUE(publishedBytes(e) == before) << "a failed import leaves the session in place";
        EXPECT_FALSE(fs::exists(sessionDir));
        (void)e.takeMeshDelta();

        const engine::CommandResult imported = e.importMesh(obj, sessionDir, 6).get();
        ASSERT_TRUE(imported.ok) << imported.message;
        EXPECT_NE(imported.message.find("imported"), std::string::npos) << imported.message;
        std::optional<mesh::MeshDelta> d = e.takeMeshDelta();
        ASSERT_TRUE(d.has_value());
        EXPECT_TRUE(d->reset);
        {
            adf::SnapshotStore::Reader reader(e.snapshots());
            const auto guard = reader.acquire();
            const adf::Adf& clay = guard.adf();
            EXPECT_EQ(clay.domain().maxLevel, 6);
            EXPECT_LT(clay.distance({0.0f, 0.0f, 0.0f}), -0.02f) << "the sphere's centre is 30 mm inside";
            EXPECT_NEAR(clay.distance({0.03f, 0.0f, 0.0f}), 0.0f, 0.002f);
            const glm::vec3 far = glm::vec3(clay.domain().originWorld) + glm::vec3(float(clay.domain().sizeWorld) * 0.02f);
            EXPECT_GT(clay.distance(far), 0.005f);
        }
        EXPECT_TRUE(fs::exists(fs::path(sessionDir) / "start.kza"));
        EXPECT_FALSE(e.importMesh(obj, sessionDir, 6).get().ok) << "a directory with a session is not overwritten";

        engine::ToolSettings tool;
        tool.tool.radius = 0.006;
        ASSERT_TRUE(e.setTool(tool).get().ok);
        const std::vector<std::byte> start = publishedBytes(e);
        for (int i = 0; i < 8; ++i) {
            const double a = 0.15 * i;
            push(e, held(i, {0.03 * std::cos(a), 0.03 * std::sin(a), 0.0}));
        }
        push(e, held(8, {0.0, 0.03, 0.0}, false));
        ASSERT_TRUE(e.sync().get().ok);
        live = publishedBytes(e);
        EXPECT_FALSE(live == start) << "the stroke carved the imported clay";
        EXPECT_EQ(e.stats().strokes, 1u);
    }
    auto reopened = sculpt::Session::open(sessionDir);
    EXPECT_EQ(reopened->journal().start.kind, sculpt::Shape::Kind::File);
    EXPECT_TRUE(adf::encodeAdf(*reopened->sculptor().current()) == live) << "replay gives the live clay bit for bit";
    // In memory, at the current session's level.
    Engine e(settingsFor({}, 5));
    const engine::CommandResult inMemory = e.importMesh(obj).get();
    ASSERT_TRUE(inMemory.ok) << inMemory.message;
    adf::SnapshotStore::Reader reader(e.snapshots());
    EXPECT_EQ(reader.acquire().adf().domain().maxLevel, 5);
}

TEST(Engine, CheckpointsAreWrittenInTheBackgroundAndReopen) {
    const TempDir dir("checkpoint");
    EngineSettings s = settingsFor(dir.str());
    s.checkpointEvery = 2;
    s.correctAfterIdle = std::chrono::milliseconds(1);
    std::vector<std::byte> live;
    {
        Engine e(s);
        for (int k = 0; k < 3; ++k) {
            for (int i = 0; i < 5; ++i) push(e, held(10 * k + i, {0.3 + 0.02 * i, 0.3 + 0.1 * k, 0.5}));
            push(e, held(10 * k + 5, {0.4, 0.5, 0.5}, false));
        }
        ASSERT_TRUE(e.sync().get().ok);
        for (int i = 0; i < 2000 && e.stats().checkpoints == 0; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(5));
        EXPECT_GE(e.stats().checkpoints, 1u);
        const engine::CommandResult r = e.save().get();
        EXPECT_TRUE(r.ok) << r.message;
        live = publishedBytes(e);
    }
    bool found = false;
    for (const auto& f : fs::directory_iterator(dir.path)) found = found || f.path().extension() == ".kza";
    EXPECT_TRUE(found);
    const auto reopened = sculpt::Session::open(dir.str());
    EXPECT_GT(reopened->checkpointSteps(), 0u);
    EXPECT_TRUE(adf::encodeAdf(*reopened->sculptor().current()) == live);
}

TEST(Engine, DestroyingABusyEngineJoinsAndKeepsTheStroke) {
    const TempDir dir("busy");
    {
        Engine e(settingsFor(dir.str()));
        for (int i = 0; i < 400; ++i) {
            const double u = double(i) / 400.0;
            while (!e.samples().push(held(i, {0.2 + 0.6 * u, 0.5 + 0.2 * std::sin(20.0 * u), 0.5}))) std::this_thread::yield();
        }
        while (!e.samples().flush()) std::this_thread::yield();
        // Destroyed at once, mid-stroke, with samples still queued and no release.
    }
    const auto reopened = sculpt::Session::open(dir.str());
    ASSERT_EQ(reopened->steps(), 1u) << "the open stroke ends as a finished one";
    EXPECT_EQ(reopened->journal().steps[0].stroke.samples.size(), 400u);
}

TEST(Engine, SigkillInTheMiddleOfAStrokeLosesOnlyThatStroke) {
    const TempDir dir("sigkill");
    std::vector<std::byte> afterTwo;
    int ready[2];
    ASSERT_EQ(::pipe(ready), 0);
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
        ::close(ready[0]);
        {
            Engine e(settingsFor(dir.str()));
            for (int k = 0; k < 2; ++k) {
                for (int i = 0; i < 8; ++i) push(e, held(20 * k + i, {0.3 + 0.03 * i, 0.3 + 0.2 * k, 0.5}));
                push(e, held(20 * k + 8, {0.5, 0.5, 0.5}, false));
            }
            for (int i = 0; i < 8; ++i) push(e, held(50 + i, {0.3 + 0.03 * i, 0.6, 0.5}));
            e.sync().get();  // the third stroke is on the clay, not finished
            const char c = e.stroking() ? 'y' : 'n';
            (void)!::write(ready[1], &c, 1);
            for (;;) ::pause();
        }
    }
    ::close(ready[1]);
    char c = 0;
    ASSERT_EQ(::read(ready[0], &c, 1), 1);
    EXPECT_EQ(c, 'y');
    ::kill(child, SIGKILL);
    int status = 0;
    ::waitpid(child, &status, 0);
    ::close(ready[0]);
    ASSERT_TRUE(WIFSIGNALED(status));
    std::vector<std::string> warnings;
    const auto reopened = sculpt::Session::open(dir.str(), nullptr, &warnings);
    EXPECT_EQ(reopened->steps(), 2u);
}

}  // namespace
}  // namespace kizamu
