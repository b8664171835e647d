// SPDX-License-Identifier: Apache-2.0
/// @file sculpt_app.cpp
/// @brief The sculpting window's frame loop: input, navigation, the tool, the engine's mesh
/// deltas, drawing, the panel.
#include "app/sculpt_app.h"

#include "app/cell_view.h"
#include "app/commands.h"
#include "app/device_open.h"
#include "app/headset_mode.h"
#include "engine/engine.h"
#include "haptics/engine_client.h"
#include "haptics/haptic_trace.h"
#include "haptics/servo_loop.h"
#include "interact/input_script.h"
#include "interact/input_state.h"
#include "interact/mouse_tool.h"
#include "mesh/mesh_colours.h"
#include "mesh/mesh_delta.h"
#include "mesh/mesh_export.h"
#include "mesh/mesh_import_assimp.h"
#include "render/clay_renderer.h"
#include "render/image.h"
#include "render/shader_program.h"
#include "sculpt/session.h"
#include "sculpt/session_lock.h"
#include "ui/file_browser.h"
#include "ui/glfw_window.h"
#include "ui/imgui_layer.h"
#include "util/cpu_set.h"
#include "util/file_error.h"
#include "xr/stylus_workspace.h"

#include <epoxy/gl.h>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <imgui.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <deque>
#include <filesystem>
#include <future>
#include <memory>
#include <optional>
#include <thread>

#include <unistd.h>

namespace kizamu::app {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

int64_t nowNs() { return std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now().time_since_epoch()).count(); }

/// A new block of clay: a 12 cm cube in a 20 cm domain centred on the origin.
sculpt::Script defaultBlock(int level) {
    sculpt::Script s;
    s.domain.originWorld = glm::dvec3(-0.1);
    s.domain.sizeWorld = 0.2;
    s.domain.maxLevel = level > 0 ? level : 9;
    s.start.kind = sculpt::Shape::Kind::Box;
    s.start.centre = glm::dvec3(0.0);
    s.start.halfSize = glm::dvec3(0.06);
    return s;
}

std::string defaultSessionRoot() {
    if (const char* x = std::getenv("XDG_DATA_HOME"); x && *x) return (fs::path(x) / "kizamu" / "sessions").string();
    if (const char* h = std::getenv("HOME"); h && *h) return (fs::path(h) / ".local" / "share" / "kizamu" / "sessions").string();
    return (fs::temp_directory_path() / "kizamu-sessions").string();
}

/// A fresh "untitled-YYYYMMDD-HHMMSS[-N]" directory name under `root`.
std::string untitledDir(const std::string& root) {
    const std::time_t t = std::time(nullptr);
    std::tm tm{};
    localtime_r(&t, &tm);
    char stamp[32];
    std::strftime(stamp, sizeof stamp, "%Y%m%d-%H%M%S", &tm);
    std::string dir = (fs::path(root) / (std::string("untitled-") + stamp)).string();
    for (int n = 2; fs::exists(dir); ++n) dir = (fs::path(root) / (std::string("untitled-") + stamp + "-" + std::to_string(n))).string();
    return dir;
}

/// Sessions under `root` a crash left open, newest first.
std::vector<std::string> interruptedSessions(const std::string& root) {
    std::vector<std::pair<fs::file_time_type, std::string>> found;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(root, ec)) {
        if (!e.is_directory() || !sculpt::isSessionDir(e.path().string())) continue;
        if (sculpt::SessionLock::interrupted(e.path().string())) found.emplace_back(fs::last_write_time(e.path(), ec), e.path().string());
    }
    std::sort(found.begin(), found.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
    std::vector<std::string> out;
    for (auto& f : found) out.push_back(std::move(f.second));
    return out;
}

const char* const kOpNames[] = {"Carve", "Add", "Build", "Heat gun", "Smooth", "Flatten", "Paint"};
const char* const kShapeNames[] = {"Sphere", "Cube", "Cylinder"};
const char* const kShadeNames[] = {"Lit", "Matcap", "Points"};  ///< render::ShadeMode's, in order
const char* const kUnits[] = {"mm", "cm", "m"};  ///< an export's coordinates

/// The median of `values` (0 when empty). Complexity: O(n log n).
double median(std::vector<double> values) {
    if (values.empty()) return 0.0;
    std::sort(values.begin(), values.end());
    return values[values.size() / 2];
}

/// The process's resident memory, MiB (Linux /proc/self/statm; 0 where it cannot be read).
double residentMiB() {
    std::FILE* f = std::fopen("/proc/self/statm", "r");
    if (!f) return 0.0;
    unsigned long pages = 0, resident = 0;
    const int n = std::fscanf(f, "%lu %lu", &pages, &resident);
    std::fclose(f);
    return n == 2 ? double(resident) * double(sysconf(_SC_PAGESIZE)) / (1024.0 * 1024.0) : 0.0;
}

/// The haptic side when a device is chosen: the device, its servo loop and the client that
/// feels the engine's clay; the mouse moves the simulated stylus's live hand.
struct Haptics {
    sim::LiveHand hand;
    OpenedDevice device;
    std::unique_ptr<haptics::ProxyRenderer> renderer;
    std::unique_ptr<haptics::EngineHapticClient> client;
    std::unique_ptr<haptics::ServoLoop> loop;
    haptics::HapticToolSettings tool;
    /// The servo thread's ticks (single producer, the UI thread consumes): where the stylus is.
    std::unique_ptr<haptics::TraceRing> ticks = std::make_unique<haptics::TraceRing>(1024);
    haptics::TraceRecord latest;  ///< the newest tick the UI thread took
    bool ticked = false;
};

/// Touches of the stylus's tip to the controller's, collected until there are enough to register.
struct StylusTouches {
    static constexpr std::size_t kNeeded = 4;
    static constexpr double kStillSpeed = 0.005;  ///< m/s on the device: the tips are held together
    std::vector<glm::dvec3> device, space;
    bool triggerWas = false, pending = false;
};

class SculptApp {
public:
    /// `cpus`: how the servo thread and the rest share the CPUs (runSculptApp has already
    /// restricted the calling thread to cpus.otherCpus).
    SculptApp(const SculptOptions& o, util::CpuSplit cpus);
    ~SculptApp();
    int run();

private:
    void startEngine();
    void startHaptics();
    void startHeadset();
    /// The headset's frame: the hands' intent acted on (tool changes, undo, the tool's samples,
    /// the contact cue), after HeadsetMode::beginFrame.
    void sculptInHeadset();
    /// Draws the eyes, the panel into its quad, submits, and mirrors the left eye to the window.
    void drawHeadset();
    /// Ends the OpenXR session the way the runtime expects (request, frames until it stops).
    void endHeadset();
    void frameEvents(int64_t frame);
    void handleKeys();
    void handleDrops();
    /// Opens `path` as a drop does: a session directory is reopened, anything else imported.
    void openPath(const std::string& path);
    void openBrowser(ui::FileBrowserMode mode);
    /// The browser's keys (Enter, Backspace, Escape) and scripted typing, while it is open and
    /// its path field does not hold a person's keyboard.
    void browserInput();
    /// What the browser chose: opened, saved as, or exported.
    void fileChosen();
    void navigate();
    void sculpt();
    void updateMesh();
    /// After a framing: the model moves into the area right of the panel and fits it.
    void frameRightOfPanel();
    /// The cells view's boxes from the published snapshot, while the view is on and the mesh
    /// changed since they were read (four times a second at most: O(leaf cells)).
    void updateCellBoxes();
    void draw();
    void panel();
    void setTitle();
    void screenshot(const std::string& path);
    /// The ray under the cursor (world): origin and direction.
    std::pair<glm::dvec3, glm::dvec3> cursorRay() const;
    void report(const engine::CommandResult& r, const char* what);
    void selectTool();
    /// A long command (open, import, export) runs while frames go on; its result is reported when
    /// it arrives, and `sessionDir`, if set, becomes the session in use when it succeeded.
    void launch(std::future<engine::CommandResult> f, std::string what, std::string sessionDir = {});
    void pollLaunched();
    /// Before the swap: whether the mesh about to be shown holds a newer tool sample's effect.
    void noteShownSample();
    /// After the swap: that sample's sample-to-visible latency, if there was one.
    void measureSampleToVisible();

    struct Launched {
        std::future<engine::CommandResult> result;
        std::string what, sessionDir;
        Clock::time_point started = Clock::now();
    };
    std::vector<Launched> mLaunched;
    std::future<engine::CommandResult> mStrokeTool;  ///< the tool change a stroke's press waits for
    std::optional<render::ToolMark> mToolMark;        ///< where the tool is drawn; none off the clay

    SculptOptions mOptions;
    util::CpuSplit mCpus;
    std::optional<interact::InputScript> mScript;
    std::size_t mScriptNext = 0;
    ui::GlfwWindow mWindow;
    ui::ImGuiLayer mImGui;
    render::ShaderLibrary mShaders;
    render::ClayRenderer mRenderer;
    render::OrbitCamera mCamera;
    render::RenderSettings mLook;
    std::unique_ptr<engine::Engine> mEngine;
    std::unique_ptr<adf::SnapshotStore::Reader> mReader;
    std::unique_ptr<Haptics> mHaptics;
    std::unique_ptr<HeadsetMode> mHeadset;
    bool mHeadsetResizing = false;  ///< the thumbstick is changing the tool's size
    bool mHeadsetGrabWas = false;
    std::optional<xr::StylusRegistration> mStylusRegistration;  ///< the stylus's workspace in the headset's space
    std::optional<StylusTouches> mRegistering;                  ///< a registration in progress
    /// The stylus in the headset: its ticks drained, registration touches taken, its tool shown.
    void stylusInHeadset(const xr::SculptIntent& in);
    bool mScriptNeedsHeadsetWarned = false;
    /// The colour layer the drawn mesh's colours were read from (null: unpainted).
    std::shared_ptr<const adf::ColourLayer> mColoursShown;
    std::size_t mTriangles = 0;
    std::size_t mCells = 0;
    std::vector<render::CellBox> mCellBoxes;
    std::size_t mBoundaryCells = 0;  ///< of the snapshot the boxes were read from
    bool mCellBoxesStale = true;
    Clock::time_point mCellBoxesRead{};
    Clock::time_point mCellsCounted{};
    int mExportUnit = 0;
    bool mFramed = false;
    float mPanelRight = 340.0f;  ///< the panel's right edge, pixels (its last frame's; where it starts before)
    interact::InputState mInput;
    std::vector<interact::InputEvent> mEvents;
    interact::MouseTool mMouse;
    engine::ToolSettings mTool;
    glm::dvec2 mLastCursor{0.0};
    std::string mSessionDir;
    std::string mStatus;           ///< the last message (errors, what a command did)
    std::vector<std::string> mInterrupted;
    std::deque<double> mFrameMs;
    /// Sample-to-visible latency (ms): the recent ones for the panel, every one for the summary.
    std::deque<double> mRecentLatencyMs;
    std::vector<double> mLatencyMs;
    int64_t mAppliedSampleNs = 0;  ///< the newest sample time in the mesh deltas applied
    int64_t mShownSampleNs = 0;    ///< the newest sample time drawn so far
    int64_t mUnswappedSampleNs = 0;  ///< a newer one drawn this frame, not yet swapped; 0: none
    bool mDecimate = false;
    int mDecimatePercent = 25;
    ui::FileBrowser mBrowser;
};

SculptApp::SculptApp(const SculptOptions& o, util::CpuSplit cpus)
    : mOptions(o), mCpus(std::move(cpus)), mWindow([&] {
          ui::WindowSettings ws;
          ws.width = o.width;
          ws.height = o.height;
          // The headset's mirror is a blit of the left eye, which a multisampled window refuses.
          if (o.xr) ws.samples = 0;
          return ws;
      }()),
      mImGui(mWindow.handle()), mRenderer(mShaders) {
    if (!o.input.empty()) mScript = interact::readInputScript(o.input);
    mTool.tool.radius = 0.008;
    mTool.tool.strength = 1.0;
    mMouse.setTool(mTool.tool);
    mLook.ground = true;
    startEngine();
    if (o.xr) startHeadset();  // first: a registered stylus is mapped through the headset's space
    startHaptics();
    if (o.registerStylus && mHeadset) mRegistering.emplace();
    setTitle();
}

void SculptApp::startHeadset() {
    HeadsetModeOptions ho;
    ho.dominant = mOptions.hand == "left" ? xr::Hand::Left : xr::Hand::Right;
    ho.validation = mOptions.xrValidation;
    {
        const auto guard = mReader->acquire();
        const adf::Domain& d = guard.adf().domain();
        ho.clayCentre = d.originWorld + glm::dvec3(0.5 * d.sizeWorld);
        ho.domainSize = d.sizeWorld;
    }
    try {
        mHeadset = std::make_unique<HeadsetMode>(ho);
        std::printf("xr: %s\n", mHeadset->describe().c_str());
        try {
            mStylusRegistration = xr::loadStylusRegistration(xr::defaultRegistrationPath());
        } catch (const FileError& e) {
            mStatus = std::string(e.what()) + " (registering the stylus again replaces it)";
        }
    } catch (const std::exception& e) {
        // No runtime, no headset, no OpenGL binding: the desktop window is the way to sculpt.
        std::fprintf(stderr, "xr: no headset (%s); sculpting in the desktop window\n", e.what());
        mStatus = std::string("no headset: ") + e.what();
    }
}

SculptApp::~SculptApp() {
    if (mHaptics && mHaptics->loop) mHaptics->loop->stop();
    mHaptics.reset();  // its client's reader goes before the engine's store
    mReader.reset();
}

void SculptApp::startEngine() {
    const std::string root = mOptions.sessionRoot.empty() ? defaultSessionRoot() : mOptions.sessionRoot;
    engine::EngineSettings es;
    es.producers = 2;  // 0: the mouse, 1: the servo thread
    es.start = defaultBlock(mOptions.level);
    const bool openDir = !mOptions.open.empty() && sculpt::isSessionDir(mOptions.open);
    if (openDir) {
        es.sessionDir = mOptions.open;
    } else if (mOptions.open.empty() && mOptions.session.empty()) {
        mInterrupted = interruptedSessions(root);
        if (!mInterrupted.empty() && mOptions.restore == "yes") {
            es.sessionDir = mInterrupted.front();
            mStatus = "restored " + mInterrupted.front();
            mInterrupted.clear();
        } else {
            if (mOptions.restore == "no") mInterrupted.clear();
            es.sessionDir = untitledDir(root);
        }
    } else {
        es.sessionDir = mOptions.session.empty() ? untitledDir(root) : mOptions.session;
    }
    mSessionDir = es.sessionDir;
    mEngine = std::make_unique<engine::Engine>(es);
    mReader = std::make_unique<adf::SnapshotStore::Reader>(mEngine->snapshots());
    report(mEngine->setTool(mTool).get(), "tool");
    if (!mOptions.open.empty() && !openDir) {
        const std::string dir = untitledDir(root);
        launch(mEngine->importMesh(mOptions.open, dir, mOptions.level), "import " + mOptions.open, dir);
    }
}

void SculptApp::launch(std::future<engine::CommandResult> f, std::string what, std::string sessionDir) {
    mStatus = what + " ...";
    mLaunched.push_back({std::move(f), std::move(what), std::move(sessionDir)});
}

void SculptApp::noteShownSample() {
    if (mAppliedSampleNs <= mShownSampleNs) return;
    mShownSampleNs = mAppliedSampleNs;
    mUnswappedSampleNs = mShownSampleNs;
}

void SculptApp::measureSampleToVisible() {
    if (mUnswappedSampleNs == 0) return;
    const double ms = double(nowNs() - mUnswappedSampleNs) * 1e-6;
    mUnswappedSampleNs = 0;
    mLatencyMs.push_back(ms);
    mRecentLatencyMs.push_back(ms);
    if (mRecentLatencyMs.size() > 120) mRecentLatencyMs.pop_front();
}

void SculptApp::pollLaunched() {
    for (auto it = mLaunched.begin(); it != mLaunched.end();) {
        if (it->result.wait_for(std::chrono::seconds(0)) != std::future_status::ready) {
            ++it;
            continue;
        }
        const engine::CommandResult r = it->result.get();
        report(r, it->what.c_str());
        if (r.ok && r.message.empty()) mStatus = it->what + ": done";
        if (r.ok && !it->sessionDir.empty()) {
            mSessionDir = it->sessionDir;
            mRenderer.requireFullMesh();
            mFramed = false;
            setTitle();
        }
        it = mLaunched.erase(it);
    }
}

void SculptApp::startHaptics() {
    if (mOptions.device == "none") return;
    auto h = std::make_unique<Haptics>();
    adf::Domain d;
    {
        const auto guard = mReader->acquire();
        d = guard.adf().domain();
    }
    // The stylus waits at the top of its workspace, above the clay, until the mouse moves it.
    const haptics::DeviceSpec simSpec = sim::SimulatedStylus(sim::Hand{}).spec();
    const glm::dvec3 rest(0.0, 0.0, 0.9 * simSpec.workspaceMax.z);
    h->hand.set(rest, 0, haptics::ServoLoop::clockNs());
    DeviceOpenOptions open;
    open.firmware = mOptions.firmware;
    open.liveHand = &h->hand;
    open.liveStart = rest;
    try {
        h->device = openDevice(mOptions.device, open, true);
    } catch (const std::exception& e) {
        mStatus = std::string(e.what()) + " (sculpting with the mouse alone)";
        return;
    }
    const haptics::DeviceSpec& spec = h->device.device().spec();
    h->tool.mapping = haptics::WorkspaceMapping::fit(spec, d.originWorld, d.originWorld + glm::dvec3(d.sizeWorld));
    // In the headset, a registered stylus feels the clay where the headset shows it.
    if (mHeadset && mStylusRegistration) h->tool.mapping = xr::stylusMapping(mStylusRegistration->deviceToSpace, mHeadset->placement());
    h->tool.planar = h->device.planar;
    haptics::ProxySettings ps;
    ps.toolRadius = mTool.tool.radius;
    h->renderer = std::make_unique<haptics::ProxyRenderer>(h->tool.mapping.worldSpec(spec), 1e-3, ps);
    h->client = std::make_unique<haptics::EngineHapticClient>(mEngine->snapshots(), mEngine->samples(1), *h->renderer, h->tool);
    h->client->setTrace(h->ticks.get());
    haptics::ServoSettings servo;
    servo.cpu = mCpus.servoCpu;
    h->loop = std::make_unique<haptics::ServoLoop>(h->device.device(), *h->client, servo);
    const haptics::ServoStartReport r = h->loop->start();
    if (!r.realtime && !r.warnings.empty()) mStatus = "haptics without real-time priority: " + r.warnings.front();
    mHaptics = std::move(h);
}

void SculptApp::report(const engine::CommandResult& r, const char* what) {
    if (!r.ok) mStatus = std::string(what) + ": " + r.message;
    else if (!r.message.empty()) mStatus = r.message;
}

void SculptApp::setTitle() {
    const std::string name = fs::path(mSessionDir).filename().string();
    mWindow.setTitle("Kizamu - " + (name.empty() ? std::string("in memory") : name));
}

void SculptApp::frameEvents(int64_t frame) {
    mEvents.clear();
    mWindow.poll(mEvents, frame);
    if (mScript) {
        const glm::ivec2 size = mWindow.windowSize();
        const double sx = double(size.x) / mScript->width, sy = double(size.y) / mScript->height;
        while (mScriptNext < mScript->events.size() && mScript->events[mScriptNext].frame <= frame) {
            interact::InputEvent e = mScript->events[mScriptNext++];
            e.x *= sx;
            e.y *= sy;
            if (e.kind == interact::InputEventKind::Drop && fs::path(e.path).is_relative())
                e.path = (fs::path(mScript->baseDir) / e.path).string();
            if (e.kind == interact::InputEventKind::Controller) {
                if ((!mHeadset || !mHeadset->play(e.controller)) && !mScriptNeedsHeadsetWarned) {
                    std::fprintf(stderr, "sculpt: the input script moves controllers, which needs a headset whose runtime "
                                         "can be driven (XR_EXT_conformance_automation); they are ignored\n");
                    mScriptNeedsHeadsetWarned = true;
                }
                continue;
            }
            mEvents.push_back(std::move(e));
        }
    }
    mInput.beginFrame();
    for (const interact::InputEvent& e : mEvents) mInput.apply(e);
}

void SculptApp::selectTool() {
    mMouse.setTool(mTool.tool);
    launch(mEngine->setTool(mTool), "tool");
}

void SculptApp::handleKeys() {
    using namespace interact;
    for (const KeyPress& k : mInput.keys()) {
        const bool ctrl = k.mods & kModCtrl, shift = k.mods & kModShift;
        if (ctrl && k.key == "z" && !shift) launch(mEngine->undo(), "undo");
        else if ((ctrl && shift && k.key == "z") || (ctrl && k.key == "y")) launch(mEngine->redo(), "redo");
        else if (ctrl && shift && k.key == "s") openBrowser(ui::FileBrowserMode::SaveAs);
        else if (ctrl && k.key == "s") launch(mEngine->save(), "save");
        else if (ctrl && k.key == "o") openBrowser(ui::FileBrowserMode::Open);
        else if (!ctrl && k.key.size() == 1 && k.key[0] >= '1' && k.key[0] <= '7') {
            mTool.tool.op = sculpt::ToolOp(k.key[0] - '1');
            selectTool();
        } else if (k.key == "[" || k.key == "]") {
            mTool.tool.radius = std::clamp(mTool.tool.radius * (k.key == "]" ? 1.25 : 0.8), 0.0005, 0.1);
            selectTool();
        } else if (k.key == "minus" || k.key == "equal") {
            mTool.tool.strength = std::clamp(mTool.tool.strength + (k.key == "equal" ? 0.1 : -0.1), 0.1, 1.0);
            selectTool();
        } else if (k.key == "kp1") mCamera.setView(ctrl ? render::ViewAxis::Back : render::ViewAxis::Front);
        else if (k.key == "kp3") mCamera.setView(ctrl ? render::ViewAxis::Left : render::ViewAxis::Right);
        else if (k.key == "kp7") mCamera.setView(ctrl ? render::ViewAxis::Bottom : render::ViewAxis::Top);
        else if (k.key == "kp5")
            mCamera.projection = mCamera.projection == render::Projection::Perspective ? render::Projection::Orthographic
                                                                                        : render::Projection::Perspective;
        else if (k.key == "kpdecimal" || k.key == "home") mFramed = false;
        else if (k.key == "w" && !ctrl) mLook.wireframe = !mLook.wireframe;
        else if (k.key == "c" && !ctrl) mLook.cells = !mLook.cells;
        else if (k.key == "m" && !ctrl) mLook.shade = render::ShadeMode((int(mLook.shade) + 1) % IM_ARRAYSIZE(kShadeNames));
        else if (k.key == "escape") launch(mEngine->cancelStroke(), "cancel");
    }
}

void SculptApp::handleDrops() {
    for (const std::string& path : mInput.drops()) openPath(path);
}

void SculptApp::openPath(const std::string& path) {
    if (sculpt::isSessionDir(path)) {
        launch(mEngine->openSession(path), "open " + path, path);
    } else {
        const std::string dir = untitledDir(mOptions.sessionRoot.empty() ? defaultSessionRoot() : mOptions.sessionRoot);
        launch(mEngine->importMesh(path, dir, 0), "import " + path, dir);
    }
}

void SculptApp::openBrowser(ui::FileBrowserMode mode) {
    ui::FileBrowserSettings s;
    s.mode = mode;
    s.isSession = [](const std::string& p) { return sculpt::isSessionDir(p); };
    const auto knownFormat = [](auto formatOf) {
        return [formatOf](const std::string& p) {
            try {
                formatOf(p);
                return true;
            } catch (const std::exception&) {
                return false;
            }
        };
    };
    if (mode == ui::FileBrowserMode::Open) {
        const auto ours = knownFormat([](const std::string& p) { mesh::meshFormatOf(p); });
        s.accepts = [ours](const std::string& p) { return ours(p) || mesh::assimpReadsExtension(p); };
    } else if (mode == ui::FileBrowserMode::Export) {
        s.accepts = knownFormat([](const std::string& p) { mesh::exportFormatOf(p); });
    } else {
        s.accepts = [](const std::string&) { return false; };  // Save As names a directory
        if (!mSessionDir.empty()) s.directory = fs::path(mSessionDir).parent_path().string();
    }
    mBrowser.open(std::move(s));
}

void SculptApp::browserInput() {
    if (!mInput.text().empty()) mBrowser.typeText(mInput.text());
    for (const interact::KeyPress& k : mInput.keys()) {
        if (k.key == "enter") mBrowser.accept();
        else if (k.key == "backspace") mBrowser.eraseLast();
        else if (k.key == "escape") mBrowser.close();
    }
}

void SculptApp::fileChosen() {
    const std::optional<std::string> path = mBrowser.takeChosen();
    if (!path) return;
    switch (mBrowser.mode()) {
    case ui::FileBrowserMode::Open: openPath(*path); break;
    case ui::FileBrowserMode::SaveAs: launch(mEngine->saveSessionAs(*path), "save as " + *path, *path); break;
    case ui::FileBrowserMode::Export:
        launch(mEngine->exportMesh(*path, kUnits[mExportUnit], mDecimate ? mDecimatePercent / 100.0 : 0.0), "export " + *path);
        break;
    }
}

void SculptApp::navigate() {
    const glm::dvec2 c = mInput.cursor();
    const glm::dvec2 delta = c - mLastCursor;
    mLastCursor = c;
    const bool orbit = mInput.held(interact::MouseButton::Middle) || mInput.held(interact::MouseButton::Right);
    if (orbit && !(mInput.mods() & interact::kModShift)) {
        mCamera.orbit(float(-delta.x * 0.008), float(delta.y * 0.008));
    } else if (orbit) {  // Shift + middle: pan in the view plane
        const glm::ivec2 size = mWindow.windowSize();
        const float perPixel = 2.0f * mCamera.distance * std::tan(mCamera.fovYRad * 0.5f) / float(std::max(1, size.y));
        const glm::vec3 right = glm::normalize(glm::cross(mCamera.forward(), mCamera.up()));
        mCamera.target += (-float(delta.x) * right + float(delta.y) * mCamera.up()) * perPixel;
    }
    if (mInput.wheel() != 0.0 && !(mInput.mods() & interact::kModAlt)) mCamera.zoom(float(std::pow(0.85, mInput.wheel())));
}

std::pair<glm::dvec3, glm::dvec3> SculptApp::cursorRay() const {
    const glm::ivec2 size = mWindow.windowSize();
    const float aspect = float(size.x) / float(std::max(1, size.y));
    const glm::mat4 inv = glm::inverse(mCamera.projectionMatrix(aspect) * mCamera.viewMatrix());
    const glm::dvec2 c = mInput.cursor();
    const float nx = float(2.0 * c.x / size.x - 1.0), ny = float(1.0 - 2.0 * c.y / size.y);
    glm::vec4 a = inv * glm::vec4(nx, ny, -1.0f, 1.0f), b = inv * glm::vec4(nx, ny, 1.0f, 1.0f);
    a /= a.w;
    b /= b.w;
    return {glm::dvec3(a), glm::dvec3(b - a)};
}

void SculptApp::sculpt() {
    interact::MouseInput in;
    in.timeS = double(nowNs()) * 1e-9;
    // A script's cursor is the only one: the panel's hover (from the system's pointer) is ignored.
    const bool panelHasMouse = !mScript && mImGui.wantsMouse();
    in.hasRay = mInput.hasCursor() && !panelHasMouse;
    std::tie(in.rayOrigin, in.rayDirection) = cursorRay();
    in.primary = mInput.held(interact::MouseButton::Left) && !panelHasMouse;
    in.ctrl = mInput.mods() & interact::kModCtrl;
    in.shift = mInput.mods() & interact::kModShift;
    in.wheel = (mInput.mods() & interact::kModAlt) ? mInput.wheel() : 0.0;  // Alt + wheel: the tool's depth
    in.pressure = mInput.pressure();
    interact::MouseToolFrame f;
    {
        const auto guard = mReader->acquire();
        adf::AdfAccessor clay(guard.adf());
        f = mMouse.update(in, clay, guard.adf().domain());
    }
    if (f.strokeBegan) {
        // The stroke's tool first: the edit thread takes samples before commands in a pass, so
        // the press waits (a frame or two, never blocking this thread) until the tool is set.
        engine::ToolSettings ts = mTool;
        ts.tool.op = f.op;
        ts.constraints.followOffset = f.followOffset;
        mStrokeTool = mEngine->setTool(ts);
    }
    if (mStrokeTool.valid()) {
        if (mStrokeTool.wait_for(std::chrono::seconds(0)) != std::future_status::ready) return;  // the ring stays where it was
        report(mStrokeTool.get(), "tool");
    }
    mToolMark.reset();
    if (!f.hasTarget) return;
    render::ToolMark mark;
    mark.centre = glm::vec3(f.target);
    mark.normal = glm::vec3(f.normal);
    mark.radius = float(mTool.tool.radius);
    mToolMark = mark;
    const uint32_t buttons = f.stroking ? uint32_t(engine::kButtonPrimary) : 0u;
    if (mHaptics) {
        // The hand presses the stylus a tool radius into the clay below the cursor: the proxy
        // stays on the surface and, while the button is held, carves in at the removal rate.
        const glm::dvec3 pressed = f.target - f.normal * mTool.tool.radius;
        mHaptics->hand.set(mHaptics->client->mapping().toDevice(pressed), buttons, haptics::ServoLoop::clockNs());
        return;
    }
    engine::ToolSample s;
    s.timeNs = nowNs();
    s.posWorld = f.target;
    s.strength = f.pressure;
    s.buttons = buttons;
    mEngine->samples(0).push(s);  // a refused sample (pending buffer full) is carried by the next
}

void SculptApp::updateMesh() {
    // Paint: the deltas carry shapes only; a vertex's colour is the published layer's at its
    // position (the same lookup every export uses, mesh_colours.h), read for the vertices a
    // delta re-emits, and for every vertex when the layer itself changed (a paint stroke).
    auto paintFrom = [](std::shared_ptr<const adf::ColourLayer> layer) -> render::VertexColourFunction {
        if (!layer) return {};
        return [layer = std::move(layer)](std::span<const glm::vec3> positions, std::span<glm::u8vec4> colours) {
            std::vector<glm::u8vec3> rgb;
            mesh::colourPoints(*layer, positions, rgb);
            for (std::size_t i = 0; i < rgb.size(); ++i) colours[i] = glm::u8vec4(rgb[i], 255);
        };
    };
    std::shared_ptr<const adf::ColourLayer> layer = mReader->acquire().adf().colours();
    if (std::optional<mesh::MeshDelta> delta = mEngine->takeMeshDelta()) {
        const int64_t sampleNs = delta->newestSampleNs;
        if (!mRenderer.applyDelta(std::move(*delta), paintFrom(layer))) {
            mEngine->requestFullMesh();
            return;
        }
        mAppliedSampleNs = std::max(mAppliedSampleNs, sampleNs);
        mTriangles = mRenderer.triangleCount();
        mCellBoxesStale = true;
        if (Clock::now() - mCellsCounted > std::chrono::milliseconds(500)) {  // O(tiles): twice a second at most
            const auto guard = mReader->acquire();
            mCells = guard.adf().computeStats().cells;
            mCellsCounted = Clock::now();
        }
        if (!mFramed && mTriangles > 0) {
            const glm::ivec2 size = mWindow.windowSize();
            if (mCamera.distance == 1.0f && mCamera.yawRad == 0.0f) mCamera.setView(render::ViewAxis::Iso);
            mCamera.frame(mRenderer.boundsMin(), mRenderer.boundsMax(), float(size.x) / float(std::max(1, size.y)), 1.6f);
            mFramed = true;
        }
    }
    if (layer != mColoursShown) {
        if (layer || mColoursShown) mRenderer.recolour(paintFrom(layer));
        mColoursShown = std::move(layer);
    }
}

void SculptApp::updateCellBoxes() {
    /// Boxes beyond this are thinned (cell_view.h): lines enough to read the cells' sizes, few
    /// enough to leave the frame to the clay.
    constexpr std::size_t kMaxCellBoxes = 60000;
    if (!mLook.cells || !mCellBoxesStale || Clock::now() - mCellBoxesRead < std::chrono::milliseconds(250)) return;
    {
        const auto guard = mReader->acquire();
        mBoundaryCells = collectBoundaryCellBoxes(guard.adf(), kMaxCellBoxes, mCellBoxes);
    }
    mRenderer.setCellBoxes(mCellBoxes);
    mCellBoxesStale = false;
    mCellBoxesRead = Clock::now();
}

void SculptApp::sculptInHeadset() {
    const xr::SculptIntent& in = mHeadset->intent();
    if (in.invert && (mTool.tool.op == sculpt::ToolOp::Carve || mTool.tool.op == sculpt::ToolOp::Add)) {
        mTool.tool.op = mTool.tool.op == sculpt::ToolOp::Carve ? sculpt::ToolOp::Add : sculpt::ToolOp::Carve;
        selectTool();
    }
    if (in.toolStep != 0) {
        const int n = int(IM_ARRAYSIZE(kOpNames));
        mTool.tool.op = sculpt::ToolOp((int(mTool.tool.op) + in.toolStep + n) % n);
        selectTool();
    }
    if (in.sizeFactor != 1.0) {
        mTool.tool.radius = std::clamp(mTool.tool.radius * in.sizeFactor, 0.0005, 0.1);
        mHeadsetResizing = true;
    } else if (mHeadsetResizing) {  // the stick let go: the engine gets the new size once
        mHeadsetResizing = false;
        selectTool();
    }
    if (in.undo) launch(mEngine->undo(), "undo");

    mToolMark.reset();
    if (mHaptics) {
        stylusInHeadset(in);
        return;
    }
    if (!in.hasTool) {
        mHeadset->contact(0.0, mTool.tool.radius);
        return;
    }
    adf::Sample under;
    {
        const auto guard = mReader->acquire();
        adf::AdfAccessor clay(guard.adf());
        under = clay.sample(glm::vec3(in.toolClay));
    }
    render::ToolMark mark;
    mark.centre = glm::vec3(in.toolClay);
    const float g = glm::length(under.gradient);
    mark.normal = g > 1e-6f ? under.gradient / g : glm::vec3(0.0f, 0.0f, 1.0f);
    mark.radius = float(mTool.tool.radius);
    mark.body = mTool.tool.shape == sculpt::ToolShape::Cube       ? render::ToolBody::Cube
                : mTool.tool.shape == sculpt::ToolShape::Cylinder ? render::ToolBody::Cylinder
                                                                  : render::ToolBody::Sphere;
    mToolMark = mark;
    // The contact cue: how far the tool's sphere reaches into the clay (the same distance
    // query the stylus's force uses).
    mHeadset->contact(mTool.tool.radius - double(under.distance), mTool.tool.radius);
    engine::ToolSample sample;
    sample.timeNs = nowNs();
    sample.posWorld = in.toolClay;
    sample.strength = std::max(in.strength, 0.05f);
    sample.buttons = in.sculpting ? uint32_t(engine::kButtonPrimary) : 0u;
    mEngine->samples(0).push(sample);
}

void SculptApp::stylusInHeadset(const xr::SculptIntent& in) {
    Haptics& h = *mHaptics;
    for (haptics::TraceRecord r; h.ticks->pop(r);) {
        h.latest = r;
        h.ticked = true;
    }
    // The simulated stylus's hand is the controller (a real stylus ignores it): the
    // controller's grip, in the stylus's workspace, with the trigger as its button.
    if (in.hasTool) {
        const uint32_t buttons = in.sculpting && !mRegistering ? uint32_t(engine::kButtonPrimary) : 0u;
        h.hand.set(h.tool.mapping.toDevice(in.toolClay), buttons, haptics::ServoLoop::clockNs());
    }
    // A grab moves the clay under the stylus: its map follows when the hands let go.
    if (mHeadsetGrabWas && !in.grabbing && mStylusRegistration) {
        h.loop->stop();
        mHaptics.reset();
        startHaptics();
        mHeadsetGrabWas = false;
        return;
    }
    mHeadsetGrabWas = in.grabbing;
    if (mRegistering && in.hasTool && h.ticked) {
        StylusTouches& t = *mRegistering;
        const bool trigger = in.strength > 0.5f;
        // A touch is taken once the stylus is still (a hand settling the two tips together) while
        // the trigger is held; letting go first takes nothing.
        if (trigger && !t.triggerWas) t.pending = true;
        if (!trigger) t.pending = false;
        const double speed = glm::length(h.latest.velocity) / h.tool.mapping.scale;  // m/s on the device
        if (t.pending && speed < StylusTouches::kStillSpeed) {
            t.pending = false;
            t.device.push_back(h.tool.mapping.toDevice(h.latest.device));
            t.space.push_back(mHeadset->placement().apply(in.toolClay));
            mStatus = "stylus registration: touch " + std::to_string(t.device.size()) + " of " + std::to_string(t.kNeeded);
        }
        t.triggerWas = trigger;
        if (t.device.size() >= t.kNeeded) {
            try {
                const xr::StylusRegistration r = xr::registerStylus(t.device, t.space);
                xr::saveStylusRegistration(xr::defaultRegistrationPath(), r, h.device.device().spec().name);
                mStylusRegistration = r;
                mStatus = "stylus registered: " + std::to_string(r.rmsM * 1000.0).substr(0, 5) + " mm rms, kept in " +
                          xr::defaultRegistrationPath();
                std::printf("xr: %s\n", mStatus.c_str());
                mRegistering.reset();
                h.loop->stop();
                mHaptics.reset();
                startHaptics();  // the new map
                return;
            } catch (const std::exception& e) {
                mStatus = std::string("stylus registration failed: ") + e.what();
                std::printf("xr: %s\n", mStatus.c_str());
                mRegistering.emplace();
            }
        }
    }
    if (!h.ticked) return;
    adf::Sample under;
    {
        const auto guard = mReader->acquire();
        adf::AdfAccessor clay(guard.adf());
        under = clay.sample(glm::vec3(h.latest.proxy));
    }
    render::ToolMark mark;
    mark.centre = glm::vec3(h.latest.proxy);
    const float g = glm::length(under.gradient);
    mark.normal = g > 1e-6f ? under.gradient / g : glm::vec3(0.0f, 0.0f, 1.0f);
    mark.radius = float(mTool.tool.radius);
    mark.body = render::ToolBody::Sphere;
    mToolMark = mark;
}

void SculptApp::drawHeadset() {
    mHeadset->drawEyes(mRenderer, mLook, mToolMark ? &*mToolMark : nullptr);
    mHeadset->beginPanel();
    mImGui.end();
    mHeadset->endPanel();
    mHeadset->endFrame();
    const glm::ivec2 fb = mWindow.framebufferSize();
    mHeadset->mirror(fb.x, fb.y);
}

void SculptApp::endHeadset() {
    if (!mHeadset) return;
    mHeadset->requestExit();
    // The runtime answers with STOPPING (the session ends) and EXITING; frames go on meanwhile,
    // empty, as the specification asks, for at most a few seconds.
    const auto deadline = Clock::now() + std::chrono::seconds(3);
    while (mHeadset->alive() && Clock::now() < deadline) {
        if (mHeadset->running()) {
            mHeadset->beginFrame();
            mHeadset->endFrame();
        } else {
            std::this_thread::sleep_for(std::chrono::milliseconds(2));
        }
    }
    mHeadset.reset();
}

void SculptApp::frameRightOfPanel() {
    const glm::ivec2 size = mWindow.windowSize();
    const float freeWidth = float(size.x) - mPanelRight;
    if (freeWidth < 0.25f * float(size.x) || size.y <= 0) return;  // a panel this wide is the user's choice: frame the whole window
    // Fit the framed sphere (its radius and centre are kept) into the free area's aspect, then
    // pan so its centre is the free area's: half the panel's width to the right on screen.
    const glm::vec3 halfDiagonal(mCamera.sceneRadius / std::sqrt(3.0f));
    mCamera.frame(mCamera.target - halfDiagonal, mCamera.target + halfDiagonal, freeWidth / float(size.y), 1.0f);
    const float perPixel = 2.0f * mCamera.distance * std::tan(mCamera.fovYRad * 0.5f) / float(size.y);
    const glm::vec3 right = glm::normalize(glm::cross(mCamera.forward(), mCamera.up()));
    mCamera.target -= right * (0.5f * mPanelRight * perPixel);
}

void SculptApp::draw() {
    const glm::ivec2 fb = mWindow.framebufferSize();
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(0, 0, fb.x, fb.y);
    mRenderer.draw(mCamera, fb.x, fb.y, mLook, mToolMark ? &*mToolMark : nullptr);
}

void SculptApp::panel() {
    ImGui::SetNextWindowPos(ImVec2(10, 10), ImGuiCond_Once);
    ImGui::SetNextWindowSize(ImVec2(330, 0), ImGuiCond_Once);
    ImGui::Begin("Kizamu");
    mPanelRight = ImGui::GetWindowPos().x + ImGui::GetWindowSize().x;
    bool changed = false;
    int op = int(mTool.tool.op);
    changed |= ImGui::Combo("Tool", &op, kOpNames, IM_ARRAYSIZE(kOpNames));
    int shape = int(mTool.tool.shape);
    changed |= ImGui::Combo("Shape", &shape, kShapeNames, IM_ARRAYSIZE(kShapeNames));
    float sizeMm = float(mTool.tool.radius * 1000.0);
    changed |= ImGui::SliderFloat("Size (mm)", &sizeMm, 0.5f, 50.0f, "%.1f", ImGuiSliderFlags_Logarithmic);
    float strength = float(mTool.tool.strength);
    changed |= ImGui::SliderFloat("Strength", &strength, 0.05f, 1.0f, "%.2f");
    float colour[3] = {mTool.tool.colour.r / 255.0f, mTool.tool.colour.g / 255.0f, mTool.tool.colour.b / 255.0f};
    changed |= ImGui::ColorEdit3("Colour", colour);
    bool mx = mTool.mirror & 1, my = mTool.mirror & 2, mz = mTool.mirror & 4;
    ImGui::Text("Symmetry");
    ImGui::SameLine();
    changed |= ImGui::Checkbox("X", &mx);
    ImGui::SameLine();
    changed |= ImGui::Checkbox("Y", &my);
    ImGui::SameLine();
    changed |= ImGui::Checkbox("Z", &mz);
    float depth = float(mMouse.depth());
    if (ImGui::SliderFloat("Depth (radii)", &depth, -1.0f, 1.0f, "%.2f")) mMouse.setDepth(depth);
    float lazyMm = float(mMouse.lazyRadius() * 1000.0);
    if (ImGui::SliderFloat("Lazy mouse (mm)", &lazyMm, 0.0f, 30.0f, "%.1f")) mMouse.setLazyRadius(lazyMm / 1000.0);
    if (changed) {
        mTool.tool.op = sculpt::ToolOp(op);
        mTool.tool.shape = sculpt::ToolShape(shape);
        mTool.tool.radius = sizeMm / 1000.0;
        mTool.tool.strength = strength;
        mTool.tool.colour = glm::u8vec3(glm::round(glm::vec3(colour[0], colour[1], colour[2]) * 255.0f));
        mTool.mirror = uint8_t((mx ? 1 : 0) | (my ? 2 : 0) | (mz ? 4 : 0));
        selectTool();
    }
    ImGui::Separator();
    if (ImGui::Button("Undo")) launch(mEngine->undo(), "undo");
    ImGui::SameLine();
    if (ImGui::Button("Redo")) launch(mEngine->redo(), "redo");
    ImGui::SameLine();
    if (ImGui::Button("Save")) launch(mEngine->save(), "save");
    ImGui::SameLine();
    if (ImGui::Button("New")) {
        const std::string dir = untitledDir(mOptions.sessionRoot.empty() ? defaultSessionRoot() : mOptions.sessionRoot);
        launch(mEngine->newSession(dir, defaultBlock(mOptions.level)), "new block", dir);
    }
    if (ImGui::Button("Open...")) openBrowser(ui::FileBrowserMode::Open);
    ImGui::SameLine();
    if (ImGui::Button("Save as...")) openBrowser(ui::FileBrowserMode::SaveAs);
    ImGui::SameLine();
    if (ImGui::Button("Export...")) openBrowser(ui::FileBrowserMode::Export);
    ImGui::SameLine();
    ImGui::SetNextItemWidth(50);
    ImGui::Combo("##unit", &mExportUnit, kUnits, IM_ARRAYSIZE(kUnits));
    ImGui::Checkbox("Decimated copy", &mDecimate);
    if (mDecimate) {
        ImGui::SameLine();
        ImGui::SetNextItemWidth(120);
        ImGui::SliderInt("##decimate", &mDecimatePercent, 1, 99, "to %d%%");
    }
    ImGui::Text("session: %s", mSessionDir.empty() ? "in memory" : fs::path(mSessionDir).filename().c_str());
    ImGui::Separator();
    bool ortho = mCamera.projection == render::Projection::Orthographic;
    int shade = int(mLook.shade);
    ImGui::SetNextItemWidth(80);
    if (ImGui::Combo("##shade", &shade, kShadeNames, IM_ARRAYSIZE(kShadeNames))) mLook.shade = render::ShadeMode(shade);
    ImGui::SameLine();
    ImGui::Checkbox("Wire", &mLook.wireframe);
    ImGui::SameLine();
    ImGui::Checkbox("Floor", &mLook.ground);
    ImGui::SameLine();
    if (ImGui::Checkbox("Ortho", &ortho)) mCamera.projection = ortho ? render::Projection::Orthographic : render::Projection::Perspective;
    ImGui::Checkbox("Cells", &mLook.cells);
    if (mLook.cells) {
        ImGui::SameLine();
        ImGui::Text("%zu of %zu surface cells drawn", mRenderer.cellBoxes().boxCount(), mBoundaryCells);
    }
    ImGui::Separator();
    ImGui::Text("frame %.1f ms (median of %zu)", median({mFrameMs.begin(), mFrameMs.end()}), mFrameMs.size());
    ImGui::Text("sample to visible %.1f ms (median of %zu)", median({mRecentLatencyMs.begin(), mRecentLatencyMs.end()}),
                mRecentLatencyMs.size());
    ImGui::Text("%zu triangles, %zu cells, %llu strokes", mTriangles, mCells, (unsigned long long)mEngine->stats().strokes);
    ImGui::Text("memory %.0f MiB", residentMiB());
    if (mHaptics) {
        const haptics::ServoSummary s = mHaptics->loop->stats().summary();
        ImGui::Text("haptics %s: %.0f Hz, period error p99 %.0f us", mHaptics->device.device().spec().name.c_str(), s.rateHz,
                    s.periodErrorUs.p99);
        if (mCpus.servoCpu >= 0)
            ImGui::Text("render threads on CPUs %s, haptics on CPU %d", util::formatCpuList(mCpus.otherCpus).c_str(), mCpus.servoCpu);
        else
            ImGui::Text("render threads and haptics share CPU %s", util::formatCpuList(mCpus.otherCpus).c_str());
        if (!mHaptics->loop->connected()) {
            // The servo loop already holds the force at zero; the window goes on.
            ImGui::TextColored(ImVec4(1.0f, 0.6f, 0.3f, 1.0f), "the device stopped answering: force is off");
            if (ImGui::Button("Reconnect")) {
                mHaptics->loop->stop();
                mHaptics.reset();
                startHaptics();
            }
        }
    } else {
        ImGui::TextUnformatted(mHeadset ? "haptics off: the controller sculpts and vibrates on contact"
                                        : "haptics off: the mouse sculpts alone");
    }
    if (mHeadset && mHaptics) {
        if (mRegistering) {
            ImGui::TextWrapped("Registering the stylus: hold its tip to the controller's and pull the trigger, at %zu places "
                               "not on one line (%zu so far).",
                               StylusTouches::kNeeded, mRegistering->device.size());
            if (ImGui::Button("Cancel registration")) mRegistering.reset();
        } else {
            if (ImGui::Button("Register the stylus")) mRegistering.emplace();
            ImGui::SameLine();
            if (mStylusRegistration) ImGui::Text("registered, %.1f mm rms", mStylusRegistration->rmsM * 1000.0);
            else ImGui::TextUnformatted("not registered: fitted to the clay");
        }
    }
    if (mHeadset)
        ImGui::Text("%s, %s, %.1f ms a frame", mHeadset->describe().c_str(), mHeadset->focused() ? "focused" : "not focused",
                    mHeadset->medianFrameMs());
    for (const Launched& l : mLaunched) {
        // Commands that take a while (open, import, export, save as): what, how long, a spinner.
        const double seconds = std::chrono::duration<double>(Clock::now() - l.started).count();
        if (seconds < 0.25) continue;
        ImGui::Text("%c %s  %.1f s", "|/-\\"[int(seconds * 8.0) % 4], l.what.c_str(), seconds);
    }
    if (!mStatus.empty()) ImGui::TextWrapped("%s", mStatus.c_str());
    ImGui::End();
    mBrowser.draw();

    if (!mInterrupted.empty()) {
        ImGui::OpenPopup("Restore");
        if (ImGui::BeginPopupModal("Restore", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
            ImGui::Text("Kizamu did not close %s.\nEvery finished stroke is in its journal.", mInterrupted.front().c_str());
            if (ImGui::Button("Restore it")) {
                openPath(mInterrupted.front());
                mInterrupted.clear();
                ImGui::CloseCurrentPopup();
            }
            ImGui::SameLine();
            if (ImGui::Button("Not now")) {
                mInterrupted.clear();
                ImGui::CloseCurrentPopup();
            }
            ImGui::EndPopup();
        }
    }
}

void SculptApp::screenshot(const std::string& path) {
    const glm::ivec2 fb = mWindow.framebufferSize();
    render::Image img(fb.x, fb.y);
    std::vector<uint8_t> rows(std::size_t(fb.x) * std::size_t(fb.y) * 4);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    glReadBuffer(GL_BACK);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, fb.x, fb.y, GL_RGBA, GL_UNSIGNED_BYTE, rows.data());
    const std::size_t stride = std::size_t(fb.x) * 4;
    for (int y = 0; y < fb.y; ++y)  // GL's first row is the bottom
        std::copy_n(rows.data() + std::size_t(fb.y - 1 - y) * stride, stride, img.pixels.data() + std::size_t(y) * stride);
    render::writePng(path, img);
}

int SculptApp::run() {
    const auto framePeriod = std::chrono::microseconds(16'667);  // 60 frames a second at most
    for (int64_t frame = 0; !mWindow.shouldClose() && (mOptions.frames == 0 || frame < mOptions.frames); ++frame) {
        const auto start = Clock::now();
        frameEvents(frame);
        if (mHeadset && !mHeadset->alive()) {
            // The runtime ended or lost the session: the app ends as if its window closed
            // (every stroke is already journaled).
            std::printf("xr: the runtime %s the session\n", mHeadset->lost() ? "lost" : "ended");
            break;
        }
        // With a running session the headset paces the loop (xrWaitFrame) and the hands sculpt.
        const bool headset = mHeadset && mHeadset->running();
        if (headset) {
            mHeadset->beginFrame();
            mImGui.begin(mHeadset->panelPointer());
        } else {
            mImGui.begin();
        }
        // A script's keys are the only ones: the panel's keyboard focus (a person's) is ignored.
        if (mScript || !mImGui.wantsKeyboard()) {
            if (mBrowser.isOpen()) browserInput();
            else handleKeys();
        }
        handleDrops();
        pollLaunched();
        if (headset) {
            sculptInHeadset();
        } else {
            navigate();
            sculpt();
        }
        const bool framed = mFramed;
        updateMesh();
        if (!framed && mFramed && !headset) frameRightOfPanel();
        noteShownSample();
        updateCellBoxes();
        if (!headset) draw();
        panel();
        fileChosen();
        if (headset) drawHeadset();
        else mImGui.end();
        const bool last = mOptions.frames > 0 && frame + 1 == mOptions.frames;
        if (last && !mOptions.screenshot.empty()) {
            // The last frame shows everything the script did: wait for the engine, then draw again.
            while (!mEngine->samples(0).flush()) std::this_thread::yield();
            for (Launched& l : mLaunched) l.result.wait();
            pollLaunched();
            mEngine->sync().get();
            updateMesh();
            noteShownSample();
            mCellBoxesRead = {};  // the last frame shows the cells of the last snapshot
            updateCellBoxes();
            if (headset && mHeadset->running()) {
                mHeadset->beginFrame();
                mImGui.begin(mHeadset->panelPointer());
                panel();
                drawHeadset();
            } else {
                draw();
                mImGui.drawAgain();
            }
            screenshot(mOptions.screenshot);
        }
        mWindow.swap();
        measureSampleToVisible();
        for (const std::string& n : mEngine->takeNotices()) mStatus = n;
        const double ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
        mFrameMs.push_back(ms);
        if (mFrameMs.size() > 120) mFrameMs.pop_front();
        if (!headset) std::this_thread::sleep_until(start + framePeriod);
    }
    if (mHeadset)
        std::printf("xr: %llu frames, median %.1f ms from xrWaitFrame to xrEndFrame\n", (unsigned long long)mHeadset->frames(),
                    mHeadset->medianFrameMs());
    endHeadset();
    // The summary names the session in use: commands still running (an open, a Save As) finish first.
    for (Launched& l : mLaunched) l.result.wait();
    pollLaunched();
    if (!mOptions.screenshot.empty()) std::printf("wrote %s\n", mOptions.screenshot.c_str());
    std::printf("sculpt: session %s, %llu strokes, sample to visible median %.2f ms over %zu frames\n", mSessionDir.c_str(),
                (unsigned long long)mEngine->stats().strokes, median(mLatencyMs), mLatencyMs.size());
    return 0;
}

}  // namespace

int runSculptApp(const SculptOptions& options) {
    // With a haptic device the servo thread gets a CPU of its own. Mesa's software renderer
    // (llvmpipe, where there is no GPU) starts one thread per CPU, and its threads inherit the
    // mask of the thread that creates the GL context: so this thread, before the window exists,
    // keeps to the other CPUs, and so does everything it starts (the edit thread and its pool);
    // the servo thread pins itself to its CPU. LP_NUM_THREADS is read when the GL driver loads,
    // ignored by GPU drivers; a value already set wins.
    const std::vector<int> allowed = util::allowedCpus();
    util::CpuSplit cpus = options.device == "none" ? util::CpuSplit{-1, allowed} : util::splitCpusForServo(allowed);
    if (cpus.servoCpu >= 0) {
        std::string why;
        if (!util::pinCurrentThread(cpus.otherCpus, &why)) std::fprintf(stderr, "warning: the UI thread keeps every CPU: %s\n", why.c_str());
        if (!std::getenv("LP_NUM_THREADS")) setenv("LP_NUM_THREADS", std::to_string(cpus.otherCpus.size()).c_str(), 0);
    }
    SculptApp app(options, std::move(cpus));
    return app.run();
}

}  // namespace kizamu::app
