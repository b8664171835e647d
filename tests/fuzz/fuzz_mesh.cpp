// SPDX-License-Identifier: Apache-2.0
/// @file fuzz_mesh.cpp
/// @brief libFuzzer harness for the mesh readers: the first byte picks the format, the rest is
/// the file. Any input is either a FileError or a valid mesh.
#include "mesh/mesh_import.h"
#include "util/file_error.h"

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
    if (size == 0) return 0;
    using kizamu::mesh::MeshFormat;
    constexpr MeshFormat kFormats[4] = {MeshFormat::Obj, MeshFormat::Stl, MeshFormat::Ply, MeshFormat::Off};
    const std::string_view bytes(reinterpret_cast<const char*>(data) + 1, size - 1);
    try {
        const kizamu::mesh::MeshBuffers m = kizamu::mesh::decodeMesh(bytes, kFormats[data[0] % 4], "fuzz");
        if (!m.valid() || m.triangleCount() == 0) std::abort();
    } catch (const kizamu::FileError&) {
    }
    return 0;
}
