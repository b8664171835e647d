// SPDX-License-Identifier: Apache-2.0
/// @file atomic_file.cpp
/// @brief POSIX implementation: open/write/fsync/rename/fsync(dir).
#include "util/atomic_file.h"

#include "util/file_error.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <fcntl.h>
#include <unistd.h>

namespace kizamu::util {

namespace {
/// `error` is errno captured right after the failing call, before cleanup can change it.
[[noreturn]] void fail(const std::string& path, const std::string& step, int error) {
    throw FileError(path, step + ": " + std::strerror(error));
}
}  // namespace

void writeFileAtomically(const std::string& path, std::span<const std::byte> bytes) {
    const std::string tmp = path + ".tmp";
    const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0) fail(path, "cannot create " + tmp, errno);
    std::size_t done = 0;
    while (done < bytes.size()) {
        const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
        if (n < 0) {
            if (errno == EINTR) continue;
            const int error = errno;
            ::close(fd);
            ::unlink(tmp.c_str());
            fail(path, "cannot write", error);
        }
        done += std::size_t(n);
    }
    if (::fsync(fd) != 0) {
        const int error = errno;
        ::close(fd);
        ::unlink(tmp.c_str());
        fail(path, "cannot flush to disk", error);
    }
    ::close(fd);
    if (::rename(tmp.c_str(), path.c_str()) != 0) {
        const int error = errno;
        ::unlink(tmp.c_str());
        fail(path, "cannot replace", error);
    }
    std::string dir = std::filesystem::path(path).parent_path().string();
    fsyncDirectory(dir.empty() ? "." : dir);
}

void fsyncDirectory(const std::string& dir) {
    const int dfd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dfd >= 0) {
        ::fsync(dfd);  // best effort: some filesystems refuse directory fsync
        ::close(dfd);
    }
}

std::string readWholeFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw FileError(path, std::string("cannot open: ") + std::strerror(errno));
    std::ostringstream ss;
    ss << in.rdbuf();
    if (in.bad()) throw FileError(path, "read error");
    return std::move(ss).str();
}

}  // namespace kizamu::util
