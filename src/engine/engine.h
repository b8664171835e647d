// SPDX-License-Identifier: Apache-2.0
/// @file engine.h
/// @brief The live engine: tool samples and commands in; the published clay (the haptic
/// thread's view) and mesh deltas (the render thread's) out. Read this first.
///
/// One Engine owns a sculpt::Session (journal, checkpoints, sculptor), the snapshot store, the mesher
/// and the edit thread; front ends (haptic loop, desktop window, headset) talk only to it
/// (docs/ARCHITECTURE.md, "The live engine"):
///
///  - **Samples in.** Each producer (stylus servo thread, controller, mouse) owns one
///    SampleQueue (samples(i)): wait-free, never allocates, simplifies rather than drops when
///    the edit thread falls behind. A press of kButtonPrimary starts a stroke with the current
///    tool; while it is held, each pass of the edit thread applies the samples that arrived since
///    the last pass as one segment (Sculptor::extendStroke) and publishes; the release ends the
///    stroke as one undo record and one journal record (stroke script version 3 keeps the cuts,
///    time stamps and strengths, so replay reaches the live bits). One stroke at a time: while
///    one producer strokes, the others' presses are ignored.
///  - **Commands in** (any thread): each returns a std::future that the edit thread fulfils with
///    the result or its one-line error; the caller never waits on the edit thread unless it
///    calls get(). Commands that change the clay end an open stroke first.
///  - **Snapshots out.** snapshots() is the SnapshotStore: every change (segment, undo, redo,
///    correction, open) is published under a growing sequence number; readers
///    (SnapshotStore::Reader, GuardedAccessor) never block. Retired snapshots are reclaimed
///    every EngineSettings::reclaimEvery even when nothing is published.
///  - **Mesh deltas out.** After each publish the mesher re-meshes the tiles the edit replaced
///    (it compares tiles by identity) and the delta goes to a one-slot mailbox; a newer delta is
///    folded into one not yet taken (mesh::coalesce). takeMeshDelta() never waits: it returns
///    nothing when the edit thread holds the mailbox at that instant. A consumer that lost
///    track asks requestFullMesh().
///
/// Determinism: segment cuts depend on timing, and the journal records them. Replaying the
/// journal (Session::open) gives the live clay bit for bit; sync() lets a driver cut segments
/// deterministically (kizamu live --rate 0).
/// Threads: the edit thread makes every call into the sculptor, the mesher and the journal; the pool it owns does
/// their parallel loops. It sleeps on a condition variable between passes (commands wake it at
/// once, samples are seen within EngineSettings::pollEvery); it never spins.
#pragma once

#include "adf/snapshot_store.h"
#include "engine/sample_queue.h"
#include "engine/tool_sample.h"
#include "mesh/mesh_delta.h"
#include "sculpt/stroke.h"
#include "sculpt/stroke_script.h"

#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <future>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <thread>
#include <vector>

namespace kizamu::engine {

namespace detail {
struct Command;
struct CommandQueue;
struct Mailbox;
struct Counters;
class EditPass;
}  // namespace detail

/// What a stroke started by a press uses: the stroke script's tool, symmetry and constraints.
struct ToolSettings {
    sculpt::Tool tool;
    uint8_t mirror = 0;  ///< sculpt::Stroke::mirror bits (x 1, y 2, z 4)
    sculpt::StrokeConstraints constraints;
};

/// Something the edit thread did, for observers (benchmarks, tests, a status line).
struct EngineEvent {
    enum class Kind : uint8_t {
        Published,  ///< a new snapshot: `samples` are the stroke samples it first contains
        Meshed,     ///< a mesh delta was posted: `samples` are those it first shows
    } kind = Kind::Published;
    uint64_t sequence = 0;              ///< the snapshot's (Meshed: the snapshot meshed)
    int64_t atNs = 0;                   ///< steady_clock, ns: when it happened
    double ms = 0.0;                    ///< the edit's (Published) or the mesh update's (Meshed) wall time
    std::span<const ToolSample> samples;  ///< valid during the call only
};

struct EngineSettings {
    /// The journal directory (sculpt::Session): reopened when it holds a journal, else created from `start`.
    /// Empty: kept in memory (nothing written; save() and exportMesh() still write files).
    std::string sessionDir;
    sculpt::Script start;  ///< domain, level and start shape when none exists yet (its steps are replayed too)
    int level = 0;         ///< finest level when created; 0 keeps the script's
    unsigned threads = 0;  ///< edit pool size; 0: the CPUs in the process's affinity mask
    std::vector<int> poolCpus;  ///< CPUs the pool's workers may run on; empty: all allowed
    std::size_t producers = 1;  ///< sample queues (samples(0) .. samples(producers - 1))
    SampleQueueSettings queue;
    /// Finished steps between background checkpoints (0: none but on save()).
    std::size_t checkpointEvery = 64;
    std::chrono::milliseconds reclaimEvery{10};
    std::chrono::microseconds pollEvery{500};  ///< the edit thread's sleep between looks at the queues
    /// Idle time after which pending remote-field corrections are made, one zone per pass
    /// (journaled); 0 disables them.
    std::chrono::milliseconds correctAfterIdle{250};
    /// Skip the mesh update of a segment when newer samples are already waiting (the next
    /// segment's mesh shows both): docs/decisions/0030-live-engine-threads.md.
    bool supersedeMesh = false;
    /// Called on the edit thread after each publish and each posted mesh delta; must be quick.
    std::function<void(const EngineEvent&)> observer;
};

/// A command's outcome: ok, or the one-line error.
struct CommandResult {
    bool ok = true;
    std::string message;  ///< the error, or what happened ("nothing to undo", warnings)
};

/// Counters the edit thread keeps; readable from any thread.
struct EngineStats {
    uint64_t segments = 0;     ///< live segments applied
    uint64_t strokes = 0;      ///< strokes ended (journaled)
    uint64_t cancelled = 0;    ///< strokes cancelled
    uint64_t meshUpdates = 0;  ///< mesh deltas posted
    uint64_t superseded = 0;   ///< mesh updates skipped for newer samples
    uint64_t checkpoints = 0;  ///< background checkpoints written
    uint64_t corrections = 0;  ///< idle remote-field corrections
    uint64_t retired = 0;      ///< published snapshots not yet freed (a reader may still see them)
};

/// The live engine. Owned by the application; one per sculpture in progress. Not copyable.
/// Thread-safe as documented per function; destruction from the thread that created it.
class Engine {
public:
    /// Opens or creates the sculpt::Session, meshes it, and starts the edit thread.
    /// @throw kizamu::FileError when the sculpt::Session cannot be opened or created;
    ///        std::invalid_argument for bad settings (no producers, a bad queue setting)
    /// Complexity: a full generation (new) or replay (open) and a full mesh. Cold path.
    explicit Engine(EngineSettings settings);
    /// Stops the edit thread after it has applied every sample already handed over and ended
    /// an open stroke (journaled: a finished stroke is never lost), waits for a background
    /// checkpoint or save; commands queued before it run, later ones fail ("the engine stopped").
    /// Producers must have stopped pushing and every SnapshotStore::Reader must be gone first.
    ~Engine();
    Engine(const Engine&) = delete;
    Engine& operator=(const Engine&) = delete;

    // ---- producers ----
    /// Producer i's queue (i < EngineSettings::producers): push from that producer's thread only.
    SampleQueue& samples(std::size_t i = 0) { return *mQueues.at(i); }

    // ---- commands (any thread) ----
    /// The tool for strokes started from now on; ends an open stroke.
    /// Errors: an invalid tool or constraints (nothing changes).
    std::future<CommandResult> setTool(ToolSettings tool);
    std::future<CommandResult> undo();
    std::future<CommandResult> redo();
    /// Cancels the open stroke: the clay returns to its start and nothing is recorded; the
    /// rest of that press is ignored.
    std::future<CommandResult> cancelStroke();
    /// Writes a checkpoint now, in the background (kept in memory: an error); with a
    /// `path`, writes the clay (every pending correction made) to that .kza file instead.
    std::future<CommandResult> save(std::string path = {});
    /// Meshes the clay (every pending correction made) in the background and writes it
    /// (mesh::exportMesh, untangled), in `unit` ("mm", "cm", "m"; empty: the format's default).
    /// With `decimate` in (0, 1) it also writes a copy with that fraction of the triangles
    /// (mesh::decimateMesh) to mesh::decimatedPath(path); 0: none.
    std::future<CommandResult> exportMesh(std::string path, std::string unit = {}, double decimate = 0.0);
    /// Closes the sculpt::Session in use (its journal is already durable) and starts another in `dir`
    /// (empty: in memory) from `start`'s header at `level` (0: its own); publishes and resets
    /// the mesh.
    std::future<CommandResult> newSession(std::string dir, sculpt::Script start, int level = 0);
    /// Closes the sculpt::Session in use and reopens the one in `dir`; warnings go into the message.
    std::future<CommandResult> openSession(std::string dir);
    /// Save As: ends an open stroke, copies the sculpt::Session in use to `dir` (sculpt::copySession:
    /// created if missing, must not hold a session) and continues in the copy, so later strokes
    /// are journaled there; the old directory stays as it was. Publishes and resets the mesh, as
    /// openSession() does. Errors (a session kept in memory, `dir` already a session, a failed
    /// copy) leave the sculpt::Session in use in place.
    /// Complexity: a copy of the journal and start clay, and a replay of the journal. Cold path.
    std::future<CommandResult> saveSessionAs(std::string dir);
    /// Ends an open stroke, imports the mesh at `meshPath` (OBJ, STL, PLY, OFF, glTF, ...:
    /// mesh::importMesh) and makes it the clay of another sculpt::Session in `dir` (empty: in memory;
    /// sculpt::Session::createFromClay, so it reopens and replays like any other): its ADF is
    /// generated at `level` (0: the level of the clay in use) in mesh::domainAround with the
    /// margin `kizamu convert` uses, on the edit pool; then published with a mesh reset, as
    /// openSession() publishes. The mesh's unit: metres for a format that declares its unit (glTF, FBX,
    /// COLLADA), else `unit` ("mm", "cm", "m"; empty: mm, as `kizamu convert --in-units`).
    /// Errors (an unreadable mesh, one without triangles, a bad unit or level, a `dir` that
    /// already holds a journal) leave the sculpt::Session in use in place. The message says what was
    /// imported and carries the import's warnings.
    /// Complexity: a mesh read and a full generation on the edit thread: no segments are
    /// applied meanwhile (samples wait in their queues). Cold path.
    std::future<CommandResult> importMesh(std::string meshPath, std::string dir = {}, int level = 0, std::string unit = {});
    /// Fulfilled once every sample handed over before the call has been applied, an open
    /// stroke's segment published, and the mesh delta of the result posted. A driver's barrier.
    std::future<CommandResult> sync();

    // ---- readers ----
    /// The published clay. Readers register a SnapshotStore::Reader (cold path) and acquire
    /// guards per query batch.
    adf::SnapshotStore& snapshots() { return *mStore; }
    /// The newest mesh delta not yet taken, or nothing (also when the edit thread is posting
    /// one at this instant: try again next frame). One consumer thread.
    /// Complexity: O(1) (a try-lock and a move). Never waits.
    std::optional<mesh::MeshDelta> takeMeshDelta();
    /// Asks for a full mesh (a reset delta) with the next pass. Any thread; never waits.
    void requestFullMesh() { mFullMeshWanted.store(true, std::memory_order_release); }
    /// Problems no command can report (a sample with a bad pose, a journal write that failed at
    /// a release), oldest first, each once. Any thread.
    std::vector<std::string> takeNotices();
    EngineStats stats() const;
    /// Whether a stroke is open (as of the edit thread's last pass). Any thread.
    bool stroking() const { return mStroking.load(std::memory_order_acquire); }

private:
    std::future<CommandResult> enqueue(detail::Command command);

    EngineSettings mSettings;
    std::vector<std::unique_ptr<SampleQueue>> mQueues;
    std::unique_ptr<detail::CommandQueue> mCommands;
    std::unique_ptr<detail::Mailbox> mMailbox;
    std::unique_ptr<detail::Counters> mCounters;
    std::atomic<bool> mFullMeshWanted{false};
    std::atomic<bool> mStroking{false};
    std::unique_ptr<detail::EditPass> mEdit;  ///< used by the edit thread only, once it runs
    std::unique_ptr<adf::SnapshotStore> mStore;
    std::thread mThread;
};

}  // namespace kizamu::engine
