// SPDX-License-Identifier: Apache-2.0
/// @file fuzz_import_reply.cpp
/// @brief libFuzzer harness for the parent's side of the assimp helper process: the decoder of
/// kizamu-import's reply (src/mesh/mesh_import_reply.h). Whatever the child writes is either a
/// one-line FileError or a valid mesh (indices in range, finite positions, at least one
/// triangle) with one-line warnings, and that mesh encodes and decodes to itself.
#include "mesh/mesh_import_reply.h"
#include "util/file_error.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
    const std::string_view bytes(reinterpret_cast<const char*>(data), size);
    std::vector<std::string> warnings;
    kizamu::mesh::MeshBuffers m;
    try {
        m = kizamu::mesh::decodeImportReply(bytes, "fuzz", &warnings);
    } catch (const kizamu::FileError& e) {
        if (std::string_view(e.what()).find('\n') != std::string_view::npos) std::abort();
        return 0;
    }
    if (!m.valid() || m.triangleCount() == 0 || !m.normals.empty() || !m.colours.empty())
        std::abort();
    for (const auto& p : m.positions)
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) std::abort();
    if (warnings.size() > kizamu::mesh::kMaxReplyWarnings) std::abort();
    for (const std::string& w : warnings)
        if (w.find('\n') != std::string::npos || w.rfind("fuzz: ", 0) != 0) std::abort();
    const kizamu::mesh::MeshBuffers again =
        kizamu::mesh::decodeImportReply(kizamu::mesh::encodeImportReply(m, {}), "fuzz");
    if (again.positions != m.positions || again.indices != m.indices) std::abort();
    return 0;
}
