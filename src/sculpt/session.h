// SPDX-License-Identifier: Apache-2.0
/// @file Session.h
/// @brief A sculpting Session on disk: its stroke journal plus checkpoints. Never loses a
/// finished stroke.
///
/// DIR/journal.jsonl is the Session's stroke script (docs/STROKE-SCRIPT.md): the header, then
/// one record per step, each appended and fsynced when the step finishes (the directory is
/// fsynced when the journal is created). A Session started from clay (createFromClay: an
/// imported mesh) keeps that clay in DIR/start.kza, which its header names. DIR/checkpoint-NNNNNNNN.kza holds the ADF after the
/// first NNNNNNNN journal records: written to a temporary file, fsynced, renamed, directory
/// fsynced (util::writeFileAtomically); older checkpoints are removed only after that. Opening
/// loads the newest checkpoint that reads back cleanly and replays the journal after it; a last
/// record cut short (a killed process mid-write) is dropped with a warning and cut from the
/// file, so the Session continues from every finished step. Replay is deterministic, so
/// reopening gives the same ADF bit for bit as the live Session had.
///
/// A live stroke (beginStroke ... endStroke) is journaled as one record when it ends, with its
/// live record (where the segments were cut, their dwells, the producer's time stamps and
/// strengths: script version 3), before the sculptor commits it; replay repeats the segments, so
/// reopening reaches the live bits too. A journal of version 1 or 2 gets a version 3 header
/// (rewritten atomically, records kept byte for byte) before its first live record.
/// Checkpoints can be written off the edit thread: prepareCheckpoint, writeCheckpoint (any
/// thread; it reads only an immutable snapshot), checkpointWritten.
/// A Session made by createInMemory has the same journal and sculptor and writes nothing.
/// One writer per directory: a Session that writes holds DIR/lock (session_lock.h) from before it
/// reads or writes anything until it is destroyed; opening one another Session (in any process)
/// holds is an error, and a lock file nobody holds marks a session a crash left open.
/// Owned by the edit thread; not thread-safe. Errors: kizamu::FileError, one line.
#pragma once

#include "sculpt/sculptor.h"
#include "sculpt/session_lock.h"
#include "sculpt/stroke_script.h"

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace kizamu::util {
class ThreadPool;
}

namespace kizamu::sculpt {

class Session {
public:
    /// Starts a Session in `dir` (created; must not hold a journal yet) from the header of
    /// `script` (domain, level, start shape); `level` 0 keeps the script's. A script that
    /// starts from a file gives createFromClay of that file's clay (startAdf's rules).
    static std::unique_ptr<Session> create(const std::string& dir, const Script& script, int level,
                                           util::ThreadPool* pool = nullptr);
    /// Starts a Session in `dir` from `clay` (not null; an imported mesh's ADF, say): writes
    /// DIR/start.kza atomically, then the journal, whose header starts from that file
    /// ({"shape": "file", "file": "start.kza"}) in the clay's domain. Reopening (open) reads
    /// start.kza again. `dir` empty: in memory (the start kept as `clay`, nothing written).
    /// @throw FileError when `dir` already holds a Session (nothing written) or a write fails.
    /// Complexity: one .kza write and the journal header. Cold path.
    static std::unique_ptr<Session> createFromClay(const std::string& dir, adf::AdfPtr clay,
                                                   util::ThreadPool* pool = nullptr);
    /// Reopens `dir`. Problems that lose nothing (a cut-off last record, an unreadable newer
    /// checkpoint) are appended to `warnings`. `readOnly` changes nothing on disk and refuses
    /// record() (what `kizamu info` and `convert` use).
    static std::unique_ptr<Session> open(const std::string& dir, util::ThreadPool* pool = nullptr,
                                         std::vector<std::string>* warnings = nullptr, bool readOnly = false);
    /// A Session kept in memory only: the same journal and sculptor, nothing written (dir() empty;
    /// checkpoint() and the checkpoint functions do nothing). What the live engine uses without a journal directory.
    /// A file start is read once (or taken from Shape::clay).
    static std::unique_ptr<Session> createInMemory(const Script& script, int level, util::ThreadPool* pool = nullptr);

    /// Makes a step durable (journal append + fsync), then applies it. A stroke that fails
    /// validation is not journaled. @throw FileError if the journal cannot be written (the
    /// Session then refuses further steps); std::invalid_argument for a bad stroke;
    /// std::logic_error while a live stroke is open (nothing journaled).
    void record(const Step& step);
    /// Writes a checkpoint of the current state (atomic, fsynced) and removes older ones. Pending
    /// remote-field corrections are made (and journaled as a correct step) first: the three
    /// checkpoint functions below in a row. @throw FileError; std::logic_error while a live
    /// stroke is open.
    void checkpoint();

    /// Live strokes through the Session: forward to the sculptor (same contracts as Sculptor's).
    /// beginStroke also throws FileError when the Session refuses steps (read-only, or after a
    /// failed write).
    void beginStroke(const Stroke& header);
    void extendStroke(std::span<const ToolSample> samples, double dwell = 0.0);
    /// Journals the live stroke (its liveStroke() with `timesNs` and `strengths` added to its live record, appended and fsynced) and only then
    /// ends it in the sculptor: one journal record, one undo record. A stroke that changed nothing is cancelled and not journaled (returns false).
    /// @param timesNs    per sample: the producer's time stamps, ns (non-decreasing), or empty
    /// @param strengths  per sample: 0..1, or empty
    /// @throw FileError if the journal cannot be written: the stroke is then cancelled (the clay returns to the stroke's start, as on disk) and the Session refuses further steps, as record() does.
    ///        std::invalid_argument when `timesNs` or `strengths` break LiveRecord's rules: nothing is journaled and the stroke stays open.
    ///        std::logic_error without an open stroke.
    /// Complexity: O(poses) to format the record, one fsync, then Sculptor::endStroke.
    bool endStroke(std::vector<int64_t> timesNs = {}, std::vector<float> strengths = {});
    void cancelStroke();
    bool stroking() const { return mSculptor->stroking(); }

    /// Background checkpoints: prepareCheckpoint (edit thread) makes pending corrections (journaled, as checkpoint() does) and returns what to write; writeCheckpoint (any thread, touches no Session state) writes it atomically; checkpointWritten (edit thread) removes older checkpoints and records it. checkpoint() = the three in a row.
    /// In memory, prepareCheckpoint returns an empty job (no path) and the other two do nothing.
    struct CheckpointJob {
        std::size_t steps = 0;  ///< journal records the checkpoint covers
        adf::AdfPtr adf;        ///< the snapshot after them (immutable; safe to read on any thread)
        std::string path;       ///< where it goes; empty: nothing to write
    };
    /// @throw FileError (journaling the correction); std::logic_error while a live stroke is open.
    CheckpointJob prepareCheckpoint();
    /// @throw FileError. Threading: any thread; reads only `job`.
    static void writeCheckpoint(const CheckpointJob& job);
    /// Removes the checkpoints older than `job.steps` (never a newer one) and records it as the
    /// Session's checkpoint. Call only after writeCheckpoint(job) returned.
    void checkpointWritten(const CheckpointJob& job);

    const Sculptor& sculptor() const { return *mSculptor; }
    const Script& journal() const { return mJournal; }  ///< header and every recorded step
    std::size_t steps() const { return mJournal.steps.size(); }
    std::size_t checkpointSteps() const { return mCheckpointSteps; }
    const std::string& dir() const { return mDir; }

    ~Session();
    // Not copyable or movable: declaring the moves deleted deletes the copies too.
    Session(Session&&) = delete;
    Session& operator=(Session&&) = delete;

private:
    Session() = default;
    /// A Session started in the existing `dir` with the journal header `header`. @throw FileError.
    static std::unique_ptr<Session> createWithJournal(const std::string& dir, Script header, util::ThreadPool* pool,
                                                      std::unique_ptr<SessionLock> lock);
    void openJournalForAppend();
    /// @throw FileError unless the Session takes steps (in memory, or the journal open).
    void requireWritable() const;
    /// Appends `step` to the journal and fsyncs it (nothing in memory). On failure the write is
    /// cut back off and the Session refuses further steps. @throw FileError.
    void append(const Step& step);
    /// Gives a journal older than version 3 a version 3 header before its first live record.
    /// @throw FileError (then the Session refuses further steps).
    void upgradeJournal();

    std::unique_ptr<SessionLock> mLock;  ///< first: released after everything else is closed
    std::string mDir;
    Script mJournal;
    std::unique_ptr<Sculptor> mSculptor;
    util::ThreadPool* mPool = nullptr;
    int mFd = -1;
    std::size_t mCheckpointSteps = 0;
    bool mHistoryFromCheckpoint = false;  ///< opened from a checkpoint: no undo history before it
    bool mInMemory = false;               ///< createInMemory: nothing is written
};

/// True when `path` is a directory holding a Session journal.
bool isSessionDir(const std::string& path);

/// Copies the Session in `fromDir` to `toDir` (created if missing; must not hold a Session): its
/// start clay (DIR/start.kza, where it has one), then its journal, each written atomically, the
/// journal last, so `toDir` becomes a Session only once it is complete. Checkpoints are not
/// copied: opening the copy replays every step, so its undo history reaches back to the start.
/// The caller makes sure nothing appends to `fromDir` meanwhile (the edit thread, between steps).
/// @throw FileError when `fromDir` is no Session, `toDir` already holds one, or a read or write fails.
/// Complexity: O(journal + start clay bytes). Threading: any thread. Memory: one file at a time.
void copySession(const std::string& fromDir, const std::string& toDir);

}  // namespace kizamu::sculpt
