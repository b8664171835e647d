// SPDX-License-Identifier: Apache-2.0
/// @file kizamu_import.cpp
/// @brief `kizamu-import [--as EXT] FILE`: reads FILE with assimp (assimp_read.h) and writes its
/// triangles to standard output in the reply format of src/mesh/mesh_import_reply.h.
///
/// Started by importWithAssimp (src/mesh/mesh_import_assimp.h) as a child process, so that a
/// crash or a hang in assimp ends this process and not a sculpting session
/// (docs/decisions/0028-assimp-in-a-child-process.md). `--as EXT` reads FILE as if its
/// extension were EXT: its content is that format while its name says otherwise (assimp picks
/// its reader by the extension first).
///
/// Where it is built with mimalloc (KIZAMU_MIMALLOC), the parent starts it with mimalloc's
/// huge-page options in its environment: options set in main() would come after the first
/// segment, which holds a whole mid-size import, was mapped in 4 KiB pages
/// (docs/decisions/0028-assimp-in-a-child-process.md).
///
/// Exit status: 0 with a reply (a mesh, or the error assimp gave); 2 for a bad command line; 3
/// when the reply cannot be written. Messages meant for a person go to standard error; assimp's
/// own printing to standard output is sent there too, so standard output holds only the reply.
#include "import/assimp_read.h"
#include "mesh/mesh_import_reply.h"

#include <signal.h>
#include <sys/prctl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

namespace {

/// Writes all of `bytes` to `fd`; false on an error (the parent has gone).
bool writeAll(int fd, std::string_view bytes) {
    while (!bytes.empty()) {
        const ssize_t n = ::write(fd, bytes.data(), bytes.size());
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return false;
        bytes.remove_prefix(std::size_t(n));
    }
    return true;
}

}  // namespace

int main(int argc, char** argv) {
    std::string as;
    if (argc == 4 && std::string_view(argv[1]) == "--as") {
        as = argv[2];
        argv += 2;
        argc -= 2;
    }
    if (argc != 2 || argv[1][0] == '\0' || as.find_first_of("/.") != std::string::npos) {
        std::fprintf(stderr,
                     "usage: kizamu-import [--as EXT] FILE\n"
                     "Reads FILE with assimp and writes its triangles to standard output in "
                     "Kizamu's import reply format (src/mesh/mesh_import_reply.h).\n");
        return 2;
    }
    // Gone with the parent: an import nobody waits for is not finished.
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    // The reply gets its own descriptor; whatever assimp prints to standard output goes to
    // standard error.
    const int reply = ::dup(1);
    if (reply < 0 || ::dup2(2, 1) < 0) {
        std::perror("kizamu-import: dup");
        return 3;
    }
    kizamu::mesh::MeshBuffers mesh;
    std::vector<std::string> warnings;
    const std::string problem = kizamu::import::readWithAssimp(argv[1], as, mesh, warnings);
    const std::string out = problem.empty() ? kizamu::mesh::encodeImportReply(mesh, warnings)
                                            : kizamu::mesh::encodeImportError(problem);
    if (!writeAll(reply, out)) {
        std::perror("kizamu-import: writing the reply");
        return 3;
    }
    return 0;
}
