// SPDX-License-Identifier: Apache-2.0
/// @file session.cpp
/// @brief Session: journal appends with fsync, atomic checkpoints, recovery.
#include "sculpt/session.h"

#include "adf/adf_file.h"
#include "sculpt/script_start.h"
#include "util/atomic_file.h"
#include "util/file_error.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <algorithm>
#include <filesystem>
#include <span>
#include <stdexcept>
#include <system_error>

namespace kizamu::sculpt {

namespace fs = std::filesystem;

namespace {

constexpr const char* kJournal = "journal.jsonl";
constexpr const char* kStartFile = "start.kza";

std::string journalPath(const std::string& dir) { return (fs::path(dir) / kJournal).string(); }

std::string checkpointName(std::size_t steps) {
    char name[64];
    std::snprintf(name, sizeof name, "checkpoint-%08zu.kza", steps);
    return name;
}

/// Step counts of the checkpoints in `dir`, newest first.
std::vector<std::size_t> checkpoints(const std::string& dir) {
    std::vector<std::size_t> out;
    std::error_code ec;
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
        const std::string n = it->path().filename().string();
        unsigned long long steps = 0;
        char tail[8] = {};
        if (n.size() == 23 && std::sscanf(n.c_str(), "checkpoint-%8llu%4s", &steps, tail) == 2 && std::string(tail) == ".kza")
            out.push_back(std::size_t(steps));
    }
    if (ec) throw FileError(dir, "cannot list the session directory: " + ec.message());
    std::sort(out.rbegin(), out.rend());
    return out;
}

/// Writes all of `text` at the end of the journal and fsyncs it. @throw FileError.
void writeAll(int fd, const std::string& text, const std::string& path) {
    std::size_t done = 0;
    while (done < text.size()) {
        const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
        if (n < 0) {
            if (errno == EINTR) continue;
            throw FileError(path, std::string("cannot append: ") + std::strerror(errno));
        }
        done += std::size_t(n);
    }
    if (::fsync(fd) != 0) throw FileError(path, std::string("cannot fsync: ") + std::strerror(errno));
}

/// True when replaying steps [from, end) from a state without history would undo or redo
/// something before `from` (the undo stack would run dry).
bool undoReachesBefore(const Script& journal, std::size_t from) {
    std::size_t undo = 0, redo = 0;
    for (std::size_t i = from; i < journal.steps.size(); ++i) {
        switch (journal.steps[i].kind) {
        case Step::Kind::Stroke:
            ++undo;
            redo = 0;
            break;
        case Step::Kind::Undo:
            if (undo == 0) return true;
            --undo;
            ++redo;
            break;
        case Step::Kind::Redo:
            if (redo == 0) return true;
            --redo;
            ++undo;
            break;
        case Step::Kind::Correct: break;  // not an edit: nothing to undo
        }
    }
    return false;
}

}  // namespace

bool isSessionDir(const std::string& path) {
    std::error_code ec;
    return fs::is_directory(path, ec) && fs::exists(journalPath(path), ec);
}

Session::~Session() {
    if (mFd >= 0) ::close(mFd);
}

void Session::openJournalForAppend() {
    const std::string path = journalPath(mDir);
    mFd = ::open(path.c_str(), O_WRONLY | O_APPEND | O_CLOEXEC);
    if (mFd < 0) throw FileError(path, std::string("cannot open for appending: ") + std::strerror(errno));
}

namespace {

/// Creates `dir` (and its parents) and makes a new directory durable.
void makeSessionDirectory(const std::string& dir) {
    std::error_code ec;
    const bool made = fs::create_directories(dir, ec);
    if (ec) throw FileError(dir, "cannot create the session directory: " + ec.message());
    if (made) {
        const std::string parent = fs::absolute(fs::path(dir), ec).parent_path().string();
        util::fsyncDirectory(parent.empty() ? "." : parent);  // the new directory itself is durable
    }
}

}  // namespace

void copySession(const std::string& fromDir, const std::string& toDir) {
    if (!isSessionDir(fromDir)) throw FileError(fromDir, "not a Kizamu session (no journal.jsonl)");
    if (isSessionDir(toDir)) throw FileError(toDir, "already holds a session (journal.jsonl); open it instead");
    makeSessionDirectory(toDir);
    auto copyAtomically = [&](const char* name) {
        const std::string bytes = util::readWholeFile((fs::path(fromDir) / name).string());
        util::writeFileAtomically((fs::path(toDir) / name).string(), std::as_bytes(std::span(bytes.data(), bytes.size())));
    };
    std::error_code ec;
    if (fs::exists(fs::path(fromDir) / kStartFile, ec)) copyAtomically(kStartFile);
    copyAtomically(kJournal);
}

std::unique_ptr<Session> Session::create(const std::string& dir, const Script& script, int level, util::ThreadPool* pool) {
    // A file start is copied into the session, which then stands alone.
    if (script.start.kind == Shape::Kind::File) return createFromClay(dir, startAdf(script, level, pool), pool);
    Script header = script;
    header.steps.clear();
    header.version = kScriptVersion;  // the journal may hold records newer than the script's
    if (level > 0) header.domain.maxLevel = level;
    makeSessionDirectory(dir);
    auto lock = std::make_unique<SessionLock>(dir);
    return createWithJournal(dir, std::move(header), pool, std::move(lock));
}

std::unique_ptr<Session> Session::createFromClay(const std::string& dir, adf::AdfPtr clay, util::ThreadPool* pool) {
    if (!clay) throw std::invalid_argument("createFromClay needs clay");
    Script header;
    header.domain = clay->domain();
    header.start.kind = Shape::Kind::File;
    header.start.file = kStartFile;
    header.start.clay = std::move(clay);
    header.baseDir = dir;
    if (dir.empty()) return createInMemory(header, 0, pool);
    // Checked before start.kza is written: never clobber another session's start.
    if (isSessionDir(dir)) throw FileError(dir, "already holds a session (journal.jsonl); open it instead");
    makeSessionDirectory(dir);
    auto lock = std::make_unique<SessionLock>(dir);
    adf::saveAdf(*header.start.clay, (fs::path(dir) / kStartFile).string());  // temporary file, fsync, rename
    return createWithJournal(dir, std::move(header), pool, std::move(lock));
}

std::unique_ptr<Session> Session::createWithJournal(const std::string& dir, Script header, util::ThreadPool* pool,
                                                    std::unique_ptr<SessionLock> lock) {
    std::unique_ptr<Session> s(new Session());
    s->mLock = std::move(lock);
    s->mDir = dir;
    s->mPool = pool;
    s->mJournal = std::move(header);
    s->mSculptor = makeSculptor(s->mJournal, 0, pool);
    // O_EXCL: never clobber another session, even one created at the same moment.
    const std::string path = journalPath(dir);
    s->mFd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_APPEND | O_CLOEXEC, 0644);
    if (s->mFd < 0) {
        if (errno == EEXIST) throw FileError(dir, "already holds a session (journal.jsonl); open it instead");
        throw FileError(path, std::string("cannot create: ") + std::strerror(errno));
    }
    writeAll(s->mFd, headerLine(s->mJournal) + "\n", path);
    util::fsyncDirectory(dir);
    return s;
}

std::unique_ptr<Session> Session::open(const std::string& dir, util::ThreadPool* pool, std::vector<std::string>* warnings,
                                       bool readOnly) {
    const std::string path = journalPath(dir);
    if (!isSessionDir(dir)) throw FileError(dir, "not a Kizamu session (no journal.jsonl)");
    // One writer: taken before anything is read, so a record another process is appending is
    // never taken for one cut short.
    std::unique_ptr<SessionLock> lock = readOnly ? nullptr : std::make_unique<SessionLock>(dir);
    std::string text = util::readWholeFile(path);
    // A record is finished when its line ends: cut a last line without its newline (a process
    // killed mid-append) and keep every step before it.
    const std::size_t lastNewline = text.rfind('\n');
    const std::size_t keep = lastNewline == std::string::npos ? 0 : lastNewline + 1;
    if (keep < text.size()) {
        if (warnings)
            warnings->push_back(path + ": the last record was cut short (" + std::to_string(text.size() - keep) +
                                " bytes); the session continues from the steps before it");
        if (!readOnly && ::truncate(path.c_str(), off_t(keep)) != 0)
            throw FileError(path, std::string("cannot cut the unfinished record: ") + std::strerror(errno));
        text.resize(keep);
    }
    std::unique_ptr<Session> s(new Session());
    s->mLock = std::move(lock);
    s->mDir = dir;
    s->mPool = pool;
    s->mJournal = parseScript(text, path);
    s->mJournal.baseDir = dir;
    // A file start is read once: the reference, a replay from the start and an undo that
    // rebuilds the history all use this clay.
    if (s->mJournal.start.kind == Shape::Kind::File) s->mJournal.start.clay = startAdf(s->mJournal, 0, pool);
    const std::size_t total = s->mJournal.steps.size();
    // Newest checkpoint that loads and that the journal covers; otherwise from the start.
    adf::AdfPtr base;
    for (std::size_t steps : checkpoints(dir)) {
        if (steps > total) continue;
        const std::string cp = (fs::path(dir) / checkpointName(steps)).string();
        try {
            base = adf::loadAdf(cp);
            s->mCheckpointSteps = steps;
            break;
        } catch (const FileError& e) {
            if (warnings) warnings->push_back(std::string(e.what()) + " (an older checkpoint or the journal is used)");
        }
    }
    // An undo after the checkpoint may reach back before it; then the history is needed and
    // the journal is replayed from the start.
    if (base && undoReachesBefore(s->mJournal, s->mCheckpointSteps)) base.reset();
    if (!base) {
        base = startAdf(s->mJournal, 0, pool);
        s->mCheckpointSteps = 0;
    }
    s->mSculptor = std::make_unique<Sculptor>(base, pool);
    s->mSculptor->setReference(s->mJournal.start.source(base->domain()));
    s->mHistoryFromCheckpoint = s->mCheckpointSteps > 0;
    for (std::size_t i = s->mCheckpointSteps; i < total; ++i) s->mSculptor->replay(s->mJournal.steps[i]);
    if (!readOnly) s->openJournalForAppend();
    return s;
}

std::unique_ptr<Session> Session::createInMemory(const Script& script, int level, util::ThreadPool* pool) {
    std::unique_ptr<Session> s(new Session());
    s->mInMemory = true;
    s->mPool = pool;
    s->mJournal = script;
    s->mJournal.steps.clear();
    s->mJournal.version = kScriptVersion;
    if (s->mJournal.start.kind == Shape::Kind::File) {
        s->mJournal.start.clay = startAdf(s->mJournal, level, pool);  // read once
    } else if (level > 0) {
        s->mJournal.domain.maxLevel = level;
    }
    s->mSculptor = makeSculptor(s->mJournal, 0, pool);
    return s;
}

void Session::requireWritable() const {
    if (!mInMemory && mFd < 0) throw FileError(mDir, "the session is read-only or a journal write failed earlier");
}

void Session::append(const Step& step) {
    if (mInMemory) return;
    // A failed write is cut back off the journal and the session stops taking steps (the clay
    // on disk is whole).
    const std::string path = journalPath(mDir);
    const off_t before = ::lseek(mFd, 0, SEEK_END);
    try {
        writeAll(mFd, stepLine(step) + "\n", path);
    } catch (...) {
        if (before >= 0 && ::ftruncate(mFd, before) == 0) ::fsync(mFd);
        ::close(mFd);
        mFd = -1;
        throw;
    }
}

void Session::upgradeJournal() {
    if (mInMemory || mJournal.version >= 3) return;
    // The header line is replaced, every byte after it kept; written atomically, so a crash
    // leaves the old journal or the new one, both whole.
    const std::string path = journalPath(mDir);
    try {
        std::string text = util::readWholeFile(path);
        std::size_t at = 0;
        for (;;) {  // the first line that is not blank or a comment is the header
            const std::size_t end = text.find('\n', at);
            if (end == std::string::npos) throw FileError(path, "no header line to upgrade");
            const std::size_t first = text.find_first_not_of(" \t\r", at);
            if (first < end && text[first] != '#') {
                Script header = mJournal;
                header.steps.clear();
                header.version = 3;
                text.replace(at, end - at, headerLine(header));
                break;
            }
            at = end + 1;
        }
        util::writeFileAtomically(path, std::as_bytes(std::span<const char>(text.data(), text.size())));
    } catch (...) {
        ::close(mFd);
        mFd = -1;
        throw;
    }
    ::close(mFd);
    mFd = -1;
    openJournalForAppend();
    mJournal.version = 3;
}

void Session::beginStroke(const Stroke& header) {
    requireWritable();
    mSculptor->beginStroke(header);
}

void Session::extendStroke(std::span<const ToolSample> samples, double dwell) { mSculptor->extendStroke(samples, dwell); }

bool Session::endStroke(std::vector<int64_t> timesNs, std::vector<float> strengths) {
    if (!mSculptor->liveChanged()) {  // throws without an open stroke
        mSculptor->cancelStroke();
        return false;
    }
    Step step{Step::Kind::Stroke, mSculptor->liveStroke(), 0};
    step.stroke.live->timesNs = std::move(timesNs);
    step.stroke.live->strengths = std::move(strengths);
    validate(step.stroke);  // never journal a stroke that cannot replay; the stroke stays open
    try {
        requireWritable();
        upgradeJournal();
        append(step);
    } catch (...) {
        mSculptor->cancelStroke();  // the clay as on disk: the stroke's start
        throw;
    }
    mSculptor->endStroke();
    mJournal.steps.push_back(std::move(step));
    return true;
}

void Session::cancelStroke() { mSculptor->cancelStroke(); }

void Session::record(const Step& step) {
    requireWritable();
    if (mSculptor->stroking()) throw std::logic_error("a session step while a live stroke is open (endStroke or cancelStroke first)");
    if (step.kind == Step::Kind::Stroke) validate(step.stroke);  // never journal a stroke that cannot replay
    // Opened from a checkpoint, the sculptor has no history before it: an undo reaching there
    // first rebuilds it from the journal, so the live session matches any later replay.
    if (step.kind == Step::Kind::Undo && mSculptor->undoDepth() == 0 && mHistoryFromCheckpoint) {
        mSculptor = makeSculptor(mJournal, 0, mPool);
        for (const Step& s : mJournal.steps) mSculptor->replay(s);
        mHistoryFromCheckpoint = false;
    }
    // Journal first: a step is applied only once it is durable.
    if (step.kind == Step::Kind::Stroke && step.stroke.live) upgradeJournal();
    append(step);
    mSculptor->replay(step);
    mJournal.steps.push_back(step);
}

void Session::checkpoint() {
    const CheckpointJob job = prepareCheckpoint();
    writeCheckpoint(job);
    checkpointWritten(job);
}

Session::CheckpointJob Session::prepareCheckpoint() {
    if (mInMemory) return {};
    if (mSculptor->stroking()) throw std::logic_error("a checkpoint while a live stroke is open (endStroke or cancelStroke first)");
    // A checkpoint holds no pending corrections: correct first, and journal that, so that a
    // replay of the journal corrects at the same point and reaches the same bits.
    if (!mSculptor->pendingCorrections().empty()) record(Step::correct());
    const std::size_t steps = mJournal.steps.size();
    return {steps, mSculptor->current(), (fs::path(mDir) / checkpointName(steps)).string()};
}

void Session::writeCheckpoint(const CheckpointJob& job) {
    if (job.path.empty()) return;
    adf::saveAdf(*job.adf, job.path);  // temporary file, fsync, rename, directory fsync
}

void Session::checkpointWritten(const CheckpointJob& job) {
    if (job.path.empty()) return;
    // Only older ones: a newer checkpoint (a later job finished first) stays.
    for (std::size_t old : checkpoints(mDir))
        if (old < job.steps) {
            std::error_code ec;
            fs::remove(fs::path(mDir) / checkpointName(old), ec);
        }
    mCheckpointSteps = std::max(mCheckpointSteps, job.steps);
}

}  // namespace kizamu::sculpt
