// SPDX-License-Identifier: Apache-2.0
/// @file session_lock.h
/// @brief One writer per journal directory, and a trace of a writer that died: DIR/lock, held
/// with an advisory lock (flock) while DIR is open for writing, removed on close.
///
/// Two processes appending to one journal would interleave records; the second writer to open
/// DIR gets a clear error instead ("open in another Kizamu, pid N"). The kernel drops a flock
/// when its process dies however it dies, so a lock file that exists but is not held was left by
/// a process that never closed DIR: a crash or a kill. The application offers to reopen such a
/// directory (every finished stroke is in its journal). Cold path; Linux flock(2).
#pragma once

#include <optional>
#include <string>
#include <sys/types.h>

namespace kizamu::sculpt {

class SessionLock {
public:
    /// Takes DIR/lock (creating it, writing this process's id into it).
    /// @throw kizamu::FileError "DIR: open in another Kizamu (pid N)" when another writer
    ///        holds it, or when the lock file cannot be created
    explicit SessionLock(const std::string& dir);
    /// Removes the lock file, then releases the lock (DIR closed cleanly).
    ~SessionLock();
    SessionLock(const SessionLock&) = delete;
    SessionLock& operator=(const SessionLock&) = delete;

    /// Whether `dir` was left open by a process that is gone: its lock file exists and nobody
    /// holds it.
    static bool interrupted(const std::string& dir);
    /// The process that holds `dir` open now, if any (the id it wrote, -1 if unreadable).
    static std::optional<pid_t> holder(const std::string& dir);

private:
    std::string mPath;
    int mFd = -1;
};

}  // namespace kizamu::sculpt
