// SPDX-License-Identifier: Apache-2.0
/// @file edit_pass.h
/// @brief The edit thread's side of the Engine (engine.h): what it owns and what one pass
/// does. Internal to the engine; front ends include engine.h only.
///
/// A pass: take the queued commands; take every sample the producers handed over and turn the
/// runs with kButtonPrimary held into stroke segments (one segment per pass and stroke, so the
/// segments grow when the edit thread falls behind and shrink to one sample when it keeps up);
/// publish each segment; run the commands; re-mesh what the pass changed and post the delta;
/// then the timers (reclaim, background checkpoint, idle corrections). The thread sleeps on the
/// command queue's condition variable between passes for at most EngineSettings::pollEvery,
/// and not at all while samples are waiting.
#pragma once

#include "engine/engine.h"
#include "mesh/surface_nets.h"
#include "sculpt/session.h"
#include "util/thread_pool.h"

#include <chrono>
#include <condition_variable>
#include <deque>
#include <future>
#include <mutex>
#include <optional>
#include <vector>

namespace kizamu::engine::detail {

/// A command from engine.h's functions, with the promise its result goes to.
struct Command {
    enum class Kind : uint8_t { SetTool, Undo, Redo, Cancel, Save, Export, New, Open, SaveAs, Import, Sync } kind = Kind::Sync;
    ToolSettings tool;
    std::string path, unit;
    std::string dir;  ///< Import: the new session's directory (path is the mesh)
    sculpt::Script script;
    int level = 0;
    double decimate = 0.0;  ///< Export: the decimated copy's fraction of the triangles (0: none)
    std::promise<CommandResult> result;
};

/// Commands from any thread to the edit thread: a mutex (never taken by a real-time thread)
/// and the condition variable the edit thread sleeps on.
struct CommandQueue {
    std::mutex mutex;
    std::condition_variable wake;
    std::deque<Command> pending;
    bool stop = false;
};

/// The one-slot mesh delta mailbox and the notices.
struct Mailbox {
    std::mutex mutex;  ///< held by the edit thread only to move a delta in or out, never while coalescing
    std::optional<mesh::MeshDelta> delta;
    std::mutex noticeMutex;
    std::vector<std::string> notices;
};

struct Counters {
    std::atomic<uint64_t> segments{0}, strokes{0}, cancelled{0}, meshUpdates{0}, superseded{0}, checkpoints{0}, corrections{0}, retired{0};
};

/// The edit thread's state. Every function runs on the edit thread, except the constructor and
/// current() (the Engine's constructor, before the thread starts).
class EditPass {
public:
    /// Opens or creates the session and builds the mesh (the first delta, a reset, is posted).
    EditPass(const EngineSettings& settings, const std::vector<std::unique_ptr<SampleQueue>>& queues, Mailbox& mailbox,
             Counters& counters, std::atomic<bool>& stroking, std::atomic<bool>& fullMeshWanted);
    ~EditPass();
    /// The session's current clay (what the store starts from).
    const adf::AdfPtr& current() const;
    /// Binds the store the passes publish to (before run()).
    void start(adf::SnapshotStore& store) { mStore = &store; }
    /// Passes until the queue is stopped, then the shutdown (engine.h, ~Engine).
    void run(CommandQueue& commands);

private:
    using Clock = std::chrono::steady_clock;
    struct Producer {
        uint32_t buttons = 0;
        bool ignorePress = false;  ///< the rest of this press is ignored (cancelled, or the tool changed)
    };

    // Samples and strokes.
    bool samplesWaiting() const;
    /// Takes every handed-over sample; applies segments; true when anything was taken.
    bool takeSamples();
    void onSample(std::size_t producer, const ToolSample& s);
    void applySegment();
    /// Ends the open stroke (journaled). `ignoreRest`: the owner's press, still held, starts nothing.
    void endStroke(bool ignoreRest);
    void cancelStroke();

    // Commands.
    void runCommand(Command& c);
    CommandResult setTool(const ToolSettings& tool);
    CommandResult undoRedo(bool undo);
    /// Start their background job, which answers `c`: true once it holds c.result (else the
    /// caller answers; a throw means nothing was started).
    bool save(Command& c);
    bool exportMesh(Command& c);
    CommandResult replaceSession(Command& c);
    CommandResult saveSessionAs(const std::string& dir);
    CommandResult importMesh(Command& c);
    /// Makes `next` the session: waits for a background checkpoint of the old one, rebuilds the
    /// mesh, publishes and posts a reset delta.
    void installSession(std::unique_ptr<sculpt::Session> next);

    // Publishing and meshing.
    void publish(std::span<const ToolSample> samples, double ms);
    /// Re-meshes when the published clay is not the meshed one; `force` ignores supersedeMesh.
    void meshIfBehind(bool force);
    void post(mesh::MeshDelta delta);
    void notice(std::string text);

    // Timers and background work.
    void housekeeping();
    bool idle() const;
    void startCheckpoint(std::optional<std::promise<CommandResult>> promise);
    /// Finishes a background checkpoint: `wait` blocks until it is written.
    void finishCheckpoint(bool wait);
    void reapBackground(bool wait);
    void shutdown();

    const EngineSettings& mSettings;
    const std::vector<std::unique_ptr<SampleQueue>>& mQueues;
    Mailbox& mMailbox;
    Counters& mCounters;
    std::atomic<bool>& mStroking;
    std::atomic<bool>& mFullMeshWanted;
    adf::SnapshotStore* mStore = nullptr;

    util::ThreadPool mPool;
    std::unique_ptr<sculpt::Session> mSession;
    mesh::SurfaceMesher mMesher;
    ToolSettings mTool;

    std::vector<Producer> mProducers;
    std::vector<ToolSample> mDrained;  ///< one queue's samples of a pass (capacity reserved)
    int mOwner = -1;                   ///< producer whose press holds the open stroke; -1: none
    bool mBegun = false;               ///< the session's live stroke is open
    std::vector<ToolSample> mSegment;  ///< owner's held samples not yet applied
    std::vector<sculpt::ToolSample> mPoses;
    std::vector<int64_t> mStrokeTimes;
    std::vector<float> mStrokeStrengths;
    int64_t mLastHeldNs = 0;
    std::vector<ToolSample> mUnmeshed;  ///< samples published and not yet in a posted delta

    Clock::time_point mLastReclaim, mLastActivity;
    std::optional<sculpt::Session::CheckpointJob> mCheckpoint;
    std::future<void> mCheckpointWriting;
    std::optional<std::promise<CommandResult>> mCheckpointPromise;
    std::vector<std::future<void>> mBackground;  ///< saves and exports
};

}  // namespace kizamu::engine::detail
