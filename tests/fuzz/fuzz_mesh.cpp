// SPDX-License-Identifier: Apache-2.0
/// @file fuzz_mesh.cpp
/// @brief libFuzzer harness for the mesh readers: the first byte picks the format (or, for 4,
/// recognition by content, ours and assimp's), the rest is the file. Any input is either a one-line
/// FileError or a valid mesh with one-line warnings.
#include "mesh/mesh_import.h"
#include "mesh/mesh_import_assimp.h"
#include "util/file_error.h"

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
    if (size == 0) return 0;
    using kizamu::mesh::MeshFormat;
    constexpr MeshFormat kFormats[4] = {MeshFormat::Obj, MeshFormat::Stl, MeshFormat::Ply,
                                        MeshFormat::Off};
    const std::string_view bytes(reinterpret_cast<const char*>(data) + 1, size - 1);
    std::optional<MeshFormat> format;
    if (data[0] % 5 == 4) {
        format = kizamu::mesh::meshFormatOfContent(bytes);
        if (!format) {
            const auto other = kizamu::mesh::assimpFormatOfContent(bytes);
            if (other && (other->name.empty() || other->extension.empty())) std::abort();
            return 0;
        }
    } else {
        format = kFormats[data[0] % 5];
    }
    std::vector<std::string> warnings;
    try {
        const kizamu::mesh::MeshBuffers m =
            kizamu::mesh::decodeMesh(bytes, *format, "fuzz", &warnings);
        if (!m.valid() || m.triangleCount() == 0) std::abort();
    } catch (const kizamu::FileError& e) {
        if (std::string_view(e.what()).find('\n') != std::string_view::npos) std::abort();
    }
    for (const std::string& w : warnings)
        if (w.find('\n') != std::string::npos) std::abort();
    return 0;
}
