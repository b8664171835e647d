// SPDX-License-Identifier: Apache-2.0
/// @file session.h
/// @brief A sculpting session on disk: its stroke journal plus checkpoints. Never loses a
/// finished stroke.
///
/// DIR/journal.jsonl is the session's stroke script (docs/STROKE-SCRIPT.md): the header, then
/// one record per step, each appended and fsynced when the step finishes (the directory is
/// fsynced when the journal is created). DIR/checkpoint-NNNNNNNN.kza holds the ADF after the
/// first NNNNNNNN journal records: written to a temporary file, fsynced, renamed, directory
/// fsynced (util::writeFileAtomically); older checkpoints are removed only after that. Opening
/// loads the newest checkpoint that reads back cleanly and replays the journal after it; a last
/// record cut short (a killed process mid-write) is dropped with a warning and cut from the
/// file, so the session continues from every finished step. Replay is deterministic, so
/// reopening gives the same ADF bit for bit as the live session had.
/// Owned by the edit thread; not thread-safe. Errors: kizamu::FileError, one line.
#pragma once

#include "sculpt/sculptor.h"
#include "sculpt/stroke_script.h"

#include <memory>
#include <string>
#include <vector>

namespace kizamu::util {
class ThreadPool;
}

namespace kizamu::sculpt {

class Session {
public:
    /// Starts a new session in `dir` (created; must not hold a journal yet) from the header of
    /// `script` (domain, level, start shape); `level` 0 keeps the script's.
    static std::unique_ptr<Session> create(const std::string& dir, const Script& script, int level,
                                           util::ThreadPool* pool = nullptr);
    /// Reopens `dir`. Problems that lose nothing (a cut-off last record, an unreadable newer
    /// checkpoint) are appended to `warnings`. `readOnly` changes nothing on disk and refuses
    /// record() (what `kizamu info` and `convert` use).
    static std::unique_ptr<Session> open(const std::string& dir, util::ThreadPool* pool = nullptr,
                                         std::vector<std::string>* warnings = nullptr, bool readOnly = false);

    /// Makes a step durable (journal append + fsync), then applies it. A stroke that fails
    /// validation is not journaled. @throw FileError if the journal cannot be written (the
    /// session then refuses further steps); std::invalid_argument for a bad stroke.
    void record(const Step& step);
    /// Writes a checkpoint of the current state (atomic, fsynced) and removes older ones. Pending
    /// remote-field corrections are made (and journaled as a correct step) first.
    void checkpoint();

    const Sculptor& sculptor() const { return *mSculptor; }
    const Script& journal() const { return mJournal; }  ///< header and every recorded step
    std::size_t steps() const { return mJournal.steps.size(); }
    std::size_t checkpointSteps() const { return mCheckpointSteps; }
    const std::string& dir() const { return mDir; }

    ~Session();
    Session(const Session&) = delete;
    Session& operator=(const Session&) = delete;

private:
    Session() = default;
    void openJournalForAppend();

    std::string mDir;
    Script mJournal;
    std::unique_ptr<Sculptor> mSculptor;
    util::ThreadPool* mPool = nullptr;
    int mFd = -1;
    std::size_t mCheckpointSteps = 0;
    bool mHistoryFromCheckpoint = false;  ///< opened from a checkpoint: no undo history before it
};

/// True when `path` is a directory holding a session journal.
bool isSessionDir(const std::string& path);

}  // namespace kizamu::sculpt
