// SPDX-License-Identifier: Apache-2.0
/// @file mesh_import_assimp.cpp
/// @brief Runs `kizamu-import` (assimp) as a child process and decodes its reply; recognises
/// the formats only assimp reads.
///
/// The child is started with posix_spawn (glibc: clone + exec, no fork of this process's
/// threads and locks) in a process group of its own, so that a timeout kills it and whatever
/// it started. Its standard output is the reply, its standard error is kept (the last line
/// explains a failed start), its standard input is /dev/null, and no other descriptor of ours
/// reaches it. One thread polls both pipes until they close or the deadline passes. Its
/// environment is ours plus mimalloc's huge-page options (unless set already): a fresh process
/// faults in every page of the scene assimp builds, and the helper's allocator reads these
/// before main() (docs/decisions/0028-assimp-in-a-child-process.md); without mimalloc they
/// are ignored.
#include "mesh/mesh_import_assimp.h"

#include "mesh/mesh_import_reply.h"
#include "util/file_error.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <thread>
#include <vector>

extern char** environ;

namespace kizamu::mesh {

namespace {

constexpr double kDefaultTimeoutS = 120.0;
/// More than any mesh with 32-bit indices that fits in memory needs (about 180 million
/// triangles): a child that writes more is broken.
constexpr std::size_t kMaxReplyBytes = std::size_t(4) << 30;
constexpr std::size_t kStderrTailBytes = 4096;

using Clock = std::chrono::steady_clock;

std::string lowerExtension(const std::string& path) {
    const std::string file = std::filesystem::path(path).filename().string();
    const auto dot = file.rfind('.');
    std::string ext = dot == std::string::npos ? "" : file.substr(dot + 1);
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    return ext;
}

std::string helperPath(const AssimpImportSettings& s) {
    if (!s.helper.empty()) return s.helper;
    if (const char* env = std::getenv("KIZAMU_IMPORT_HELPER"); env != nullptr && *env != '\0')
        return env;
    std::error_code ec;
    const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (!ec) {
        const std::filesystem::path beside = self.parent_path() / "kizamu-import";
        if (std::filesystem::exists(beside, ec)) return beside.string();
    }
    return "kizamu-import";  // posix_spawnp looks on the PATH
}

double timeoutOf(const AssimpImportSettings& s) {
    if (s.timeoutS > 0.0) return s.timeoutS;
    if (const char* env = std::getenv("KIZAMU_IMPORT_TIMEOUT_S"); env != nullptr) {
        char* end = nullptr;
        const double v = std::strtod(env, &end);
        if (end != env && *end == '\0' && std::isfinite(v) && v > 0.0) return v;
    }
    return kDefaultTimeoutS;
}

/// A file descriptor closed when it goes.
struct Fd {
    int fd = -1;
    Fd() = default;
    Fd(const Fd&) = delete;
    Fd& operator=(const Fd&) = delete;
    ~Fd() { reset(); }
    void reset() {
        if (fd >= 0) ::close(fd);
        fd = -1;
    }
};

void makePipe(Fd& readEnd, Fd& writeEnd, const std::string& path) {
    int fds[2];
    if (::pipe2(fds, O_CLOEXEC) != 0)
        throw FileError(
            path, std::string("cannot start the import helper: pipe: ") + std::strerror(errno));
    readEnd.fd = fds[0];
    writeEnd.fd = fds[1];
}

/// The child: killed with its process group and reaped if the import is abandoned (timeout,
/// an exception on our side), so no zombie and no stray assimp outlive the call.
class Child {
public:
    explicit Child(pid_t pid) : mPid(pid) {}
    Child(const Child&) = delete;
    Child& operator=(const Child&) = delete;
    ~Child() {
        if (mPid > 0) {
            kill();
            reap();
        }
    }
    void kill() const {
        ::kill(-mPid, SIGKILL);  // the group: the helper and anything it started
        ::kill(mPid, SIGKILL);   // in case it left the group
    }
    /// Waits for the exit; false when the status is unknown (SIGCHLD ignored: reaped already).
    bool reap(int* status = nullptr) {
        int st = 0;
        pid_t r;
        do {
            r = ::waitpid(mPid, &st, 0);
        } while (r < 0 && errno == EINTR);
        mPid = -1;
        if (status != nullptr) *status = st;
        return r > 0;
    }
    /// Waits for the exit until `deadline`; false when it has not exited by then.
    bool reapBy(Clock::time_point deadline, int& status, bool& known) {
        for (;;) {
            const pid_t r = ::waitpid(mPid, &status, WNOHANG);
            if (r == mPid || (r < 0 && errno != EINTR)) {
                known = r == mPid;
                mPid = -1;
                return true;
            }
            if (Clock::now() >= deadline) return false;
            std::this_thread::sleep_for(std::chrono::milliseconds(2));
        }
    }

private:
    pid_t mPid;
};

/// The last non-empty line of the child's standard error, for a message.
std::string lastLine(const std::string& text) {
    std::size_t end = text.size();
    while (end > 0 && std::isspace(static_cast<unsigned char>(text[end - 1]))) --end;
    const std::size_t start = text.rfind('\n', end == 0 ? 0 : end - 1);
    const std::string line = text.substr(start == std::string::npos ? 0 : start + 1,
                                         end - (start == std::string::npos ? 0 : start + 1));
    return line.empty() ? "" : replyLine(line.substr(0, 300));
}

std::string secondsText(double s) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", s);
    return buf;
}

}  // namespace

MeshBuffers importWithAssimp(const std::string& path, const AssimpImportSettings& settings,
                             std::vector<std::string>* warnings) {
    const std::string helper = helperPath(settings);
    const double timeoutS = timeoutOf(settings);
    Fd replyRead, replyWrite, errRead, errWrite;
    makePipe(replyRead, replyWrite, path);
    makePipe(errRead, errWrite, path);

    posix_spawn_file_actions_t actions;
    posix_spawnattr_t attr;
    posix_spawn_file_actions_init(&actions);
    posix_spawnattr_init(&attr);
    posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_adddup2(&actions, replyWrite.fd, 1);
    posix_spawn_file_actions_adddup2(&actions, errWrite.fd, 2);
    posix_spawn_file_actions_addclosefrom_np(&actions, 3);
    // Its own process group (a timeout kills the group), no blocked signals, and the default
    // action for the signals a host application may ignore (ignoring is inherited across exec).
    sigset_t none, defaults;
    sigemptyset(&none);
    sigemptyset(&defaults);
    for (const int sig : {SIGPIPE, SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGCHLD})
        sigaddset(&defaults, sig);
    posix_spawnattr_setflags(
        &attr, POSIX_SPAWN_SETPGROUP | POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF);
    posix_spawnattr_setpgroup(&attr, 0);
    posix_spawnattr_setsigmask(&attr, &none);
    posix_spawnattr_setsigdefault(&attr, &defaults);
    std::vector<char*> env;
    for (char** e = environ; *e != nullptr; ++e) env.push_back(*e);
    static char kLargePages[] = "MIMALLOC_LARGE_OS_PAGES=1";
    static char kEagerCommit[] = "MIMALLOC_EAGER_COMMIT_DELAY=0";
    for (char* option : {kLargePages, kEagerCommit})
        if (std::getenv(std::string(option, std::strchr(option, '=')).c_str()) == nullptr)
            env.push_back(option);
    env.push_back(nullptr);
    std::string arg0 = helper, as = "--as", ext = settings.asExtension, file = path;
    char* argv[] = {arg0.data(), as.data(), ext.data(), file.data(), nullptr};
    if (ext.empty()) {
        argv[1] = file.data();
        argv[2] = nullptr;
    }
    pid_t pid = -1;
    const int spawned = ::posix_spawnp(&pid, helper.c_str(), &actions, &attr, argv, env.data());
    posix_spawn_file_actions_destroy(&actions);
    posix_spawnattr_destroy(&attr);
    if (spawned != 0)
        throw FileError(path,
                        "cannot start the import helper " + helper + ": " + std::strerror(spawned));
    Child child(pid);
    replyWrite.reset();
    errWrite.reset();

    const auto deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                             std::chrono::duration<double>(timeoutS));
    const std::string timedOut = "assimp took longer than " + secondsText(timeoutS) +
                                 " s and was stopped (KIZAMU_IMPORT_TIMEOUT_S sets the limit)";
    std::string reply, err;
    char buf[1 << 16];
    pollfd fds[2] = {{replyRead.fd, POLLIN, 0}, {errRead.fd, POLLIN, 0}};
    while (fds[0].fd >= 0 || fds[1].fd >= 0) {
        const auto left =
            std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
        if (left <= 0) throw FileError(path, timedOut);  // ~Child kills and reaps
        const int n = ::poll(fds, 2, int(std::min<long long>(left + 1, INT_MAX)));
        if (n < 0) {
            if (errno == EINTR) continue;
            throw FileError(
                path, std::string("waiting for the import helper: poll: ") + std::strerror(errno));
        }
        for (int k = 0; k < 2; ++k) {
            if (fds[k].fd < 0 || fds[k].revents == 0) continue;
            const ssize_t got = ::read(fds[k].fd, buf, sizeof buf);
            if (got < 0 && (errno == EINTR || errno == EAGAIN)) continue;
            if (got <= 0) {
                fds[k].fd = -1;  // end of file (or a broken pipe): poll skips it
                continue;
            }
            if (k == 0) {
                if (reply.size() + std::size_t(got) > kMaxReplyBytes)
                    throw FileError(path, "the import helper's reply is malformed: more than " +
                                              std::to_string(kMaxReplyBytes >> 30) + " GiB");
                reply.append(buf, std::size_t(got));
            } else {
                err.append(buf, std::size_t(got));
                if (err.size() > 2 * kStderrTailBytes) err.erase(0, err.size() - kStderrTailBytes);
            }
        }
    }
    int status = 0;
    bool known = false;
    if (!child.reapBy(deadline, status, known)) throw FileError(path, timedOut);

    if (known && WIFSIGNALED(status)) {
        const int sig = WTERMSIG(status);
        const char* what = ::strsignal(sig);
        throw FileError(path, "assimp crashed reading it (signal " + std::to_string(sig) +
                                  (what != nullptr ? std::string(", ") + what : "") +
                                  "); the file was not read");
    }
    if (known && WIFEXITED(status) && WEXITSTATUS(status) != 0) {
        const std::string line = lastLine(err);
        throw FileError(path, "the import helper " + helper + " failed (exit status " +
                                  std::to_string(WEXITSTATUS(status)) + ")" +
                                  (line.empty() ? "" : ": " + line));
    }
    return decodeImportReply(reply, path, warnings);
}

std::optional<AssimpFormat> assimpFormatOfContent(std::string_view bytes) {
    const std::string_view head = bytes.substr(0, 64 * 1024);
    if (head.substr(0, 4) == "glTF") return AssimpFormat{"glTF binary", "glb"};
    if (head.substr(0, 18) == "Kaydara FBX Binary") return AssimpFormat{"FBX", "fbx"};
    if (head.substr(0, 5) == "; FBX") return AssimpFormat{"FBX", "fbx"};
    // 3DS: the main chunk (0x4D4D) whose length is the file's size.
    if (bytes.size() >= 16 && uint8_t(bytes[0]) == 0x4D && uint8_t(bytes[1]) == 0x4D) {
        uint32_t length;
        std::memcpy(&length, bytes.data() + 2, 4);
        if (length == bytes.size()) return AssimpFormat{"3DS", "3ds"};
    }
    // Text formats: skip a UTF-8 byte-order mark and leading white space.
    std::string_view text = head;
    if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
    while (!text.empty() && std::isspace(static_cast<unsigned char>(text.front())))
        text.remove_prefix(1);
    if (text.substr(0, 1) == "<" && text.find("<COLLADA") != std::string_view::npos)
        return AssimpFormat{"COLLADA", "dae"};
    if (text.substr(0, 1) == "{" && text.find("\"asset\"") != std::string_view::npos &&
        text.find("\"version\"") != std::string_view::npos)
        return AssimpFormat{"glTF", "gltf"};
    return std::nullopt;
}

bool assimpReadsExtension(const std::string& path) {
    // `assimp listext` of Debian's assimp 5.2.5, less ours (obj, stl, ply, off), the files that
    // hold no meshes (animations, cameras, projects) and STEP (its reader takes IFC only).
    // Content that is ours still goes to our readers (importMesh decides).
    static constexpr std::string_view kExtensions[] = {
        "3d",   "3ds",   "3mf", "assbin",  "ac",     "ac3d", "acc",  "amf",     "ase",  "ask",
        "b3d",  "blend", "bsp", "bvh",     "cob",    "csm",  "dae",  "dxf",     "enff", "fbx",
        "glb",  "gltf",  "hmp", "ifc",     "ifczip", "iqm",  "irr",  "irrmesh", "lwo",  "lws",
        "lxo",  "md2",   "md3", "md5mesh", "mdc",    "mdl",  "mesh", "ms3d",    "ndo",  "nff",
        "ogex", "pk3",   "pmx", "q3o",     "q3s",    "raw",  "scn",  "sib",     "smd",  "ter",
        "uc",   "vta",   "x",   "x3d",     "x3db",   "xgl",  "xml",  "zae",     "zgl"};
    const std::string ext = lowerExtension(path);
    return std::find(std::begin(kExtensions), std::end(kExtensions), ext) != std::end(kExtensions);
}

}  // namespace kizamu::mesh
