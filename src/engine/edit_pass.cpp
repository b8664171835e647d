// SPDX-License-Identifier: Apache-2.0
/// @file edit_pass.cpp
/// @brief The edit thread's passes (edit_pass.h): samples into stroke segments, commands,
/// publishing, meshing, and the background work that must not stall it.
#include "engine/edit_pass.h"

#include "adf/adf_file.h"
#include "adf/generate.h"
#include "mesh/mesh_decimate.h"
#include "mesh/mesh_export.h"
#include "mesh/mesh_import.h"
#include "mesh/mesh_source.h"
#include "util/cpu_set.h"
#include "util/file_error.h"

#include <algorithm>
#include <exception>
#include <utility>

namespace kizamu::engine::detail {

namespace {

int64_t nowNs() {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

double msSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

/// The session of `dir`: reopened when it holds a journal, else created from `start` (whose
/// steps are then recorded); in memory when `dir` is empty.
std::unique_ptr<sculpt::Session> openOrCreate(const std::string& dir, const sculpt::Script& start, int level,
                                              util::ThreadPool* pool, std::vector<std::string>* warnings) {
    if (!dir.empty() && sculpt::isSessionDir(dir)) return sculpt::Session::open(dir, pool, warnings);
    std::unique_ptr<sculpt::Session> s = dir.empty() ? sculpt::Session::createInMemory(start, level, pool)
                                                     : sculpt::Session::create(dir, start, level, pool);
    for (const sculpt::Step& step : start.steps) s->record(step);
    return s;
}

/// What a result says about an exception: its one line.
CommandResult failure(const std::exception& e) { return {false, e.what()}; }

}  // namespace

EditPass::EditPass(const EngineSettings& settings, const std::vector<std::unique_ptr<SampleQueue>>& queues, Mailbox& mailbox,
                   Counters& counters, std::atomic<bool>& stroking, std::atomic<bool>& fullMeshWanted)
    : mSettings(settings), mQueues(queues), mMailbox(mailbox), mCounters(counters), mStroking(stroking),
      mFullMeshWanted(fullMeshWanted), mPool(settings.threads, settings.poolCpus), mMesher(&mPool), mProducers(queues.size()) {
    std::vector<std::string> warnings;
    mSession = openOrCreate(settings.sessionDir, settings.start, settings.level, &mPool, &warnings);
    for (std::string& w : warnings) notice(std::move(w));
    mMesher.build(mSession->sculptor().current());
    post(mMesher.takeDelta());
    std::size_t most = 0;
    for (const auto& q : queues) most = std::max(most, q->capacity());
    mDrained.reserve(most);
    mLastReclaim = mLastActivity = Clock::now();
}

EditPass::~EditPass() = default;

const adf::AdfPtr& EditPass::current() const { return mSession->sculptor().current(); }

void EditPass::run(CommandQueue& commands) {
    // The edit thread runs pool items as thread 0: it keeps to the pool's CPUs.
    if (!mSettings.poolCpus.empty()) {
        std::string why;
        if (!util::pinCurrentThread(mSettings.poolCpus, &why)) notice("edit thread: " + why);
    }
    for (;;) {
        std::deque<Command> taken;
        bool stop = false;
        {
            std::unique_lock lock(commands.mutex);
            if (commands.pending.empty() && !commands.stop && !samplesWaiting())
                commands.wake.wait_for(lock, mSettings.pollEvery);
            taken.swap(commands.pending);
            stop = commands.stop;
        }
        // Commands are taken before samples: every sample handed over before a command was
        // queued is applied before it runs (sync() relies on this).
        const bool sampled = takeSamples();
        std::vector<std::promise<CommandResult>> syncs;
        for (Command& c : taken) {
            if (c.kind == Command::Kind::Sync) {
                syncs.push_back(std::move(c.result));
                continue;
            }
            runCommand(c);
        }
        if (sampled || !taken.empty()) mLastActivity = Clock::now();
        meshIfBehind(!syncs.empty());
        for (auto& p : syncs) p.set_value({});
        if (stop) break;
        housekeeping();
    }
    shutdown();
}

// ---- samples and strokes ----

bool EditPass::samplesWaiting() const {
    return std::any_of(mQueues.begin(), mQueues.end(), [](const auto& q) { return q->sizeApprox() > 0; });
}

bool EditPass::takeSamples() {
    bool any = false;
    for (std::size_t i = 0; i < mQueues.size(); ++i) {
        mDrained.clear();
        // The reserve covers a whole ring, so these push_backs never allocate.
        mQueues[i]->popAll([this](const ToolSample& s) { mDrained.push_back(s); });
        any = any || !mDrained.empty();
        for (const ToolSample& s : mDrained) onSample(i, s);
    }
    if (mOwner >= 0) applySegment();
    return any;
}

void EditPass::onSample(std::size_t producer, const ToolSample& s) {
    Producer& p = mProducers[producer];
    const bool down = (s.buttons & kButtonPrimary) != 0;
    const bool was = (p.buttons & kButtonPrimary) != 0;
    p.buttons = s.buttons;
    if (!down) {
        p.ignorePress = false;
        if (was && mOwner == int(producer)) endStroke(false);
        return;
    }
    if (!was && mOwner < 0 && !p.ignorePress) {
        mOwner = int(producer);
        mLastHeldNs = s.timeNs;
    }
    if (mOwner == int(producer)) mSegment.push_back(s);
}

void EditPass::applySegment() {
    if (mSegment.empty()) return;
    const auto t0 = Clock::now();
    // The heat gun dwells for the time between held samples, weighted by each one's strength
    // (pressure is heat); the other tools take the tool's strength and ignore the samples'.
    const bool heat = mTool.tool.op == sculpt::ToolOp::HeatGun;
    double dwell = 0.0;
    mPoses.clear();
    for (const ToolSample& s : mSegment) {
        mPoses.push_back({s.posWorld, glm::dquat(s.orientation)});
        if (heat) dwell += double(std::max<int64_t>(0, s.timeNs - mLastHeldNs)) * 1e-9 * double(s.strength);
        mLastHeldNs = s.timeNs;
    }
    try {
        if (!mBegun) {
            sculpt::Stroke header;
            header.tool = mTool.tool;
            header.samples = mPoses;
            header.constraints = mTool.constraints;
            header.mirror = mTool.mirror;
            header.dwell = dwell;
            mSession->beginStroke(header);
            mBegun = true;
            mStroking.store(true, std::memory_order_release);
        } else {
            mSession->extendStroke(mPoses, dwell);
        }
    } catch (const std::exception& e) {
        notice(std::string("stroke segment skipped: ") + e.what());
        mSegment.clear();
        return;
    }
    for (const ToolSample& s : mSegment) {
        mStrokeTimes.push_back(s.timeNs);
        mStrokeStrengths.push_back(s.strength);
    }
    mCounters.segments.fetch_add(1, std::memory_order_relaxed);
    publish(mSegment, msSince(t0));
    mSegment.clear();
}

void EditPass::endStroke(bool ignoreRest) {
    applySegment();
    if (mOwner >= 0 && ignoreRest) mProducers[std::size_t(mOwner)].ignorePress = true;
    mOwner = -1;
    mSegment.clear();
    if (!mBegun) return;
    mBegun = false;
    mStroking.store(false, std::memory_order_release);
    try {
        if (mSession->endStroke(std::exchange(mStrokeTimes, {}), std::exchange(mStrokeStrengths, {})))
            mCounters.strokes.fetch_add(1, std::memory_order_relaxed);
    } catch (const std::exception& e) {
        notice(std::string("the stroke could not be journaled and was undone: ") + e.what());
    }
    mStrokeTimes.clear();
    mStrokeStrengths.clear();
    publish({}, 0.0);  // a stroke that changed nothing, or failed to journal, returns to its start
}

void EditPass::cancelStroke() {
    mSegment.clear();
    if (mOwner >= 0) mProducers[std::size_t(mOwner)].ignorePress = true;
    mOwner = -1;
    if (!mBegun) return;
    mBegun = false;
    mStroking.store(false, std::memory_order_release);
    mSession->cancelStroke();
    mStrokeTimes.clear();
    mStrokeStrengths.clear();
    mCounters.cancelled.fetch_add(1, std::memory_order_relaxed);
    publish({}, 0.0);
}

// ---- commands ----

void EditPass::runCommand(Command& c) {
    CommandResult r;
    bool deferred = false;  // save() and exportMesh() answer from their background job
    try {
        switch (c.kind) {
        case Command::Kind::SetTool: r = setTool(c.tool); break;
        case Command::Kind::Undo: r = undoRedo(true); break;
        case Command::Kind::Redo: r = undoRedo(false); break;
        case Command::Kind::Cancel:
            if (!mBegun) r.message = "no stroke to cancel";
            cancelStroke();
            break;
        case Command::Kind::Save: deferred = save(c); break;
        case Command::Kind::Export: deferred = exportMesh(c); break;
        case Command::Kind::New:
        case Command::Kind::Open: r = replaceSession(c); break;
        case Command::Kind::SaveAs: r = saveSessionAs(c.path); break;
        case Command::Kind::Import: r = importMesh(c); break;
        case Command::Kind::Sync: break;
        }
    } catch (const std::exception& e) {
        r = failure(e);
    }
    if (!deferred) c.result.set_value(std::move(r));
}

CommandResult EditPass::setTool(const ToolSettings& tool) {
    sculpt::Stroke check;
    check.tool = tool.tool;
    check.samples.push_back({});
    check.constraints = tool.constraints;
    check.mirror = tool.mirror;
    sculpt::validate(check);  // throws before anything changes
    if (tool.mirror > 7) throw std::invalid_argument("mirror takes the bits x 1, y 2, z 4");
    endStroke(true);
    mTool = tool;
    return {};
}

CommandResult EditPass::undoRedo(bool undo) {
    endStroke(true);
    const adf::AdfPtr before = mSession->sculptor().current();
    mSession->record(undo ? sculpt::Step::undo() : sculpt::Step::redo());
    publish({}, 0.0);
    if (mSession->sculptor().current() == before) return {true, undo ? "nothing to undo" : "nothing to redo"};
    return {};
}

bool EditPass::save(Command& c) {
    endStroke(true);
    if (c.path.empty()) {
        if (mSession->dir().empty()) throw std::invalid_argument("this session is kept in memory: save to a .kza file instead");
        finishCheckpoint(true);
        startCheckpoint(std::move(c.result));
        return true;
    }
    adf::AdfPtr clay = mSession->sculptor().settled();
    auto job = [clay = std::move(clay), path = c.path, promise = std::move(c.result)]() mutable {
        try {
            adf::saveAdf(*clay, path);
            promise.set_value({true, "saved " + path});
        } catch (const std::exception& e) {
            promise.set_value(failure(e));
        }
    };
    mBackground.push_back(std::async(std::launch::async, std::move(job)));
    return true;
}

bool EditPass::exportMesh(Command& c) {
    mesh::ExportOptions options;
    if (!c.unit.empty()) {
        options.unit = mesh::lengthUnitOf(c.unit);
        if (!options.unit) throw std::invalid_argument("unknown unit '" + c.unit + "' (mm, cm or m)");
    }
    mesh::exportUnit(c.path, options);  // refuses a bad extension or unit before any work
    if (c.decimate < 0.0 || c.decimate >= 1.0) throw std::invalid_argument("decimate: the ratio must be in (0, 1), or 0 for no copy");
    options.untangle = true;
    adf::AdfPtr clay = mSession->sculptor().settled();
    // Meshed and written on its own thread, serially: the pool is the edit thread's.
    auto job = [clay = std::move(clay), path = c.path, options, ratio = c.decimate, promise = std::move(c.result)]() mutable {
        try {
            const mesh::MeshBuffers m = mesh::meshAdf(clay);
            mesh::exportMesh(m, path, options);
            std::string message = "wrote " + path;
            if (ratio > 0.0) {
                const mesh::MeshBuffers d = mesh::decimateMesh(m, {ratio, 1.0});
                mesh::exportMesh(d, mesh::decimatedPath(path), options);
                message += " and " + mesh::decimatedPath(path) + " (" + std::to_string(d.triangleCount()) + " of " +
                           std::to_string(m.triangleCount()) + " triangles)";
            }
            promise.set_value({true, std::move(message)});
        } catch (const std::exception& e) {
            promise.set_value(failure(e));
        }
    };
    mBackground.push_back(std::async(std::launch::async, std::move(job)));
    return true;
}

CommandResult EditPass::replaceSession(Command& c) {
    endStroke(true);
    std::vector<std::string> warnings;
    // Built first: a session that cannot be opened leaves the current one in place.
    std::unique_ptr<sculpt::Session> next;
    if (c.kind == Command::Kind::Open) {
        if (!sculpt::isSessionDir(c.path)) throw FileError(c.path, "no session journal here");
        next = sculpt::Session::open(c.path, &mPool, &warnings);
    } else {
        if (!c.path.empty() && sculpt::isSessionDir(c.path)) throw FileError(c.path, "already holds a session (open it instead)");
        next = openOrCreate(c.path, c.script, c.level, &mPool, &warnings);
    }
    installSession(std::move(next));
    CommandResult r;
    for (const std::string& w : warnings) r.message += (r.message.empty() ? "" : "; ") + w;
    return r;
}

CommandResult EditPass::saveSessionAs(const std::string& dir) {
    endStroke(true);
    if (mSession->dir().empty()) throw std::invalid_argument("this session is kept in memory: save to a .kza file instead");
    if (dir.empty()) throw std::invalid_argument("save as: no directory given");
    finishCheckpoint(true);
    sculpt::copySession(mSession->dir(), dir);
    std::vector<std::string> warnings;
    installSession(sculpt::Session::open(dir, &mPool, &warnings));
    CommandResult r{true, "saved as " + dir};
    for (const std::string& w : warnings) r.message += "; " + w;
    return r;
}

CommandResult EditPass::importMesh(Command& c) {
    endStroke(true);
    // Everything that can be refused cheaply is, before the mesh is read.
    mesh::LengthUnit unit = mesh::LengthUnit::Millimetre;
    if (!c.unit.empty()) {
        const std::optional<mesh::LengthUnit> u = mesh::lengthUnitOf(c.unit);
        if (!u) throw std::invalid_argument("unknown unit '" + c.unit + "' (mm, cm or m)");
        unit = *u;
    }
    const int level = c.level > 0 ? c.level : mSession->sculptor().current()->domain().maxLevel;
    if (level < 1 || level > adf::kMaxSupportedLevel)
        throw std::invalid_argument("level " + std::to_string(level) + " is out of range (1.." +
                                    std::to_string(adf::kMaxSupportedLevel) + ")");
    if (!c.dir.empty() && sculpt::isSessionDir(c.dir)) throw FileError(c.dir, "already holds a session (open it instead)");
    std::vector<std::string> warnings;
    bool inMetres = false;  // a format that declares its unit (glTF, FBX, COLLADA)
    mesh::MeshBuffers m = mesh::importMesh(c.path, &warnings, &inMetres);
    if (!inMetres) mesh::scaleToMetres(m, unit);
    // The domain and generation `kizamu convert` uses, so both give the same clay.
    adf::AdfPtr clay;
    {
        // The source first: it refuses a mesh without triangles, which has no domain.
        const adf::SourcePtr source = mesh::makeMeshSource(m, &warnings);  // closed parts oriented by nesting
        const adf::GenerationSettings settings;
        const adf::Domain d = mesh::domainAround(m, level, settings.bandCells + 2.0);
        clay = adf::generate(*source, d, settings, &mPool);
    }
    installSession(sculpt::Session::createFromClay(c.dir, std::move(clay), &mPool));
    CommandResult r{true, "imported " + c.path + ": " + std::to_string(m.triangleCount()) + " triangles, level " +
                              std::to_string(level)};
    for (const std::string& w : warnings) r.message += "; " + w;
    return r;
}

void EditPass::installSession(std::unique_ptr<sculpt::Session> next) {
    finishCheckpoint(true);
    mSession = std::move(next);
    mMesher.build(mSession->sculptor().current());
    publish({}, 0.0);
    mUnmeshed.clear();
    post(mMesher.takeDelta());
}

// ---- publishing and meshing ----

void EditPass::publish(std::span<const ToolSample> samples, double ms) {
    const adf::AdfPtr& clay = mSession->sculptor().current();
    if (clay == mStore->current()) return;
    const uint64_t sequence = mStore->publish(clay);
    mCounters.retired.store(mStore->retiredCount(), std::memory_order_relaxed);
    mUnmeshed.insert(mUnmeshed.end(), samples.begin(), samples.end());
    if (mSettings.observer) mSettings.observer({EngineEvent::Kind::Published, sequence, nowNs(), ms, samples});
}

void EditPass::meshIfBehind(bool force) {
    const adf::AdfPtr& clay = mStore->current();
    if (clay != mMesher.snapshot()) {
        // Superseding: newer samples are waiting, and the next pass's mesh shows them with these.
        if (!force && mSettings.supersedeMesh && mBegun && samplesWaiting()) {
            mCounters.superseded.fetch_add(1, std::memory_order_relaxed);
            return;
        }
        const auto t0 = Clock::now();
        const bool sameGrid = mMesher.snapshot() && mMesher.snapshot()->domain() == clay->domain();
        if (sameGrid)
            mMesher.update(clay);
        else
            mMesher.build(clay);
        mesh::MeshDelta delta = mMesher.takeDelta();
        for (const ToolSample& sample : mUnmeshed) delta.newestSampleNs = std::max(delta.newestSampleNs, sample.timeNs);
        post(std::move(delta));
        mCounters.meshUpdates.fetch_add(1, std::memory_order_relaxed);
        if (mSettings.observer)
            mSettings.observer({EngineEvent::Kind::Meshed, mStore->currentSequence(), nowNs(), msSince(t0), mUnmeshed});
        mUnmeshed.clear();
    }
    if (mFullMeshWanted.exchange(false, std::memory_order_acq_rel)) post(mMesher.fullDelta());
}

void EditPass::post(mesh::MeshDelta delta) {
    std::optional<mesh::MeshDelta> older;
    {
        std::lock_guard lock(mMailbox.mutex);
        if (!mMailbox.delta) {
            mMailbox.delta = std::move(delta);
            return;
        }
        older = std::move(mMailbox.delta);
        mMailbox.delta.reset();
    }
    // Folded outside the lock: meanwhile the consumer finds the box empty and tries next frame.
    mesh::coalesce(*older, std::move(delta));
    std::lock_guard lock(mMailbox.mutex);
    mMailbox.delta = std::move(older);
}

void EditPass::notice(std::string text) {
    std::lock_guard lock(mMailbox.noticeMutex);
    mMailbox.notices.push_back(std::move(text));
}

// ---- timers and background work ----

bool EditPass::idle() const {
    return !mBegun && mOwner < 0 && Clock::now() - mLastActivity >= mSettings.correctAfterIdle;
}

void EditPass::housekeeping() {
    const auto now = Clock::now();
    if (now - mLastReclaim >= mSettings.reclaimEvery) {
        mCounters.retired.store(mStore->reclaim(), std::memory_order_relaxed);
        mLastReclaim = now;
    }
    finishCheckpoint(false);
    reapBackground(false);
    if (!idle() || mSettings.correctAfterIdle.count() == 0) return;
    try {
        // Idle: one pending correction per pass (journaled, so replay corrects at the same
        // point), then a due checkpoint, which then has nothing left to correct.
        if (!mSession->sculptor().pendingCorrections().empty()) {
            mSession->record(sculpt::Step::correct(1));
            mCounters.corrections.fetch_add(1, std::memory_order_relaxed);
            publish({}, 0.0);
            meshIfBehind(true);
            return;
        }
        const bool due = mSettings.checkpointEvery > 0 && !mSession->dir().empty() && !mCheckpoint &&
                         mSession->steps() >= mSession->checkpointSteps() + mSettings.checkpointEvery;
        if (due) startCheckpoint(std::nullopt);
    } catch (const std::exception& e) {
        notice(e.what());
        mLastActivity = now;  // not again at once
    }
}

void EditPass::startCheckpoint(std::optional<std::promise<CommandResult>> promise) {
    mCheckpoint = mSession->prepareCheckpoint();
    publish({}, 0.0);  // the corrections it made
    mCheckpointPromise = std::move(promise);
    mCheckpointWriting = std::async(std::launch::async, [job = *mCheckpoint] { sculpt::Session::writeCheckpoint(job); });
}

void EditPass::finishCheckpoint(bool wait) {
    if (!mCheckpoint) return;
    if (!wait && mCheckpointWriting.wait_for(std::chrono::seconds(0)) != std::future_status::ready) return;
    CommandResult r{true, "checkpoint written"};
    try {
        mCheckpointWriting.get();
        mSession->checkpointWritten(*mCheckpoint);
        mCounters.checkpoints.fetch_add(1, std::memory_order_relaxed);
    } catch (const std::exception& e) {
        r = failure(e);
        if (!mCheckpointPromise) notice(std::string("background checkpoint failed: ") + e.what());
    }
    if (mCheckpointPromise) mCheckpointPromise->set_value(std::move(r));
    mCheckpoint.reset();
    mCheckpointPromise.reset();
}

void EditPass::reapBackground(bool wait) {
    std::erase_if(mBackground, [wait](std::future<void>& f) {
        if (!wait && f.wait_for(std::chrono::seconds(0)) != std::future_status::ready) return false;
        f.wait();
        return true;
    });
}

void EditPass::shutdown() {
    // Every sample already handed over is applied, and the open stroke ends as a finished one.
    takeSamples();
    endStroke(true);
    finishCheckpoint(true);
    reapBackground(true);
}

}  // namespace kizamu::engine::detail
