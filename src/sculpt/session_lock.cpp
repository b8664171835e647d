// SPDX-License-Identifier: Apache-2.0
/// @file session_lock.cpp
/// @brief SessionLock: flock on DIR/lock.
#include "sculpt/session_lock.h"

#include "util/file_error.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>

namespace kizamu::sculpt {

namespace {

std::string lockPath(const std::string& dir) { return (std::filesystem::path(dir) / "lock").string(); }

/// The process id written in the lock file (-1 when unreadable).
pid_t readPid(int fd) {
    char buf[32] = {};
    const ssize_t n = ::pread(fd, buf, sizeof buf - 1, 0);
    if (n <= 0) return -1;
    char* end = nullptr;
    const long pid = std::strtol(buf, &end, 10);
    return end != buf && pid > 0 ? pid_t(pid) : -1;
}

}  // namespace

SessionLock::SessionLock(const std::string& dir) : mPath(lockPath(dir)) {
    mFd = ::open(mPath.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (mFd < 0) throw FileError(dir, std::string("cannot create its lock file: ") + std::strerror(errno));
    if (::flock(mFd, LOCK_EX | LOCK_NB) != 0) {
        const pid_t other = readPid(mFd);
        ::close(mFd);
        mFd = -1;
        throw FileError(dir, "open in another Kizamu" + (other > 0 ? " (pid " + std::to_string(other) + ")" : std::string()) +
                                 ": close it there first");
    }
    const std::string pid = std::to_string(::getpid()) + "\n";
    if (::ftruncate(mFd, 0) != 0 || ::pwrite(mFd, pid.data(), pid.size(), 0) != ssize_t(pid.size())) {
        const int err = errno;
        ::close(mFd);
        mFd = -1;
        throw FileError(dir, std::string("cannot write its lock file: ") + std::strerror(err));
    }
}

SessionLock::~SessionLock() {
    if (mFd < 0) return;
    ::unlink(mPath.c_str());  // first: between the two, nobody can take a lock on a file about to vanish
    ::close(mFd);
}

bool SessionLock::interrupted(const std::string& dir) {
    const int fd = ::open(lockPath(dir).c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) return false;  // closed cleanly, or never opened by a Session
    const bool free = ::flock(fd, LOCK_SH | LOCK_NB) == 0;
    ::close(fd);
    return free;
}

std::optional<pid_t> SessionLock::holder(const std::string& dir) {
    const int fd = ::open(lockPath(dir).c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) return std::nullopt;
    std::optional<pid_t> out;
    if (::flock(fd, LOCK_SH | LOCK_NB) != 0) out = readPid(fd);
    ::close(fd);
    return out;
}

}  // namespace kizamu::sculpt
