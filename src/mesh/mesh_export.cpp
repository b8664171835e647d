// SPDX-License-Identifier: Apache-2.0
/// @file mesh_export.cpp
/// @brief OBJ, binary STL, binary PLY and GLB writers, units, and the choice of writer (3MF
/// is mesh_export_3mf.cpp).
#include "mesh/mesh_export.h"

#include "mesh/mesh_export_3mf.h"

#include "util/atomic_file.h"
#include "util/byte_writer.h"
#include "util/file_error.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <bit>
#include <cctype>
#include <cstdio>
#include <cmath>
#include <cstring>
#include <limits>
#include <span>
#include <vector>

namespace kizamu::mesh {

namespace {

using util::ByteWriter;

/// The writers read positions from `pos` (the mesh's, in the file's unit) and everything else
/// from `m`.
using Positions = std::span<const glm::vec3>;

glm::vec3 faceNormal(const MeshBuffers& m, Positions pos, std::size_t t) {
    const glm::vec3 a = pos[m.indices[3 * t]], b = pos[m.indices[3 * t + 1]],
                    c = pos[m.indices[3 * t + 2]];
    const glm::vec3 n = glm::cross(b - a, c - a);
    const float len = glm::length(n);
    return len > 0.0f ? n / len : glm::vec3(0.0f);
}

void writeObj(const MeshBuffers& m, Positions pos, LengthUnit unit, ByteWriter& out) {
    char line[160];
    std::snprintf(line, sizeof line, "# Kizamu mesh, coordinates in %s\n", unitSymbol(unit));
    out.text(line);
    for (std::size_t i = 0; i < pos.size(); ++i) {
        const glm::vec3 p = pos[i];
        if (m.colours.empty()) {
            std::snprintf(line, sizeof line, "v %.9g %.9g %.9g\n", p.x, p.y, p.z);
        } else {
            const glm::vec3 c = glm::vec3(m.colours[i]) / 255.0f;
            std::snprintf(line, sizeof line, "v %.9g %.9g %.9g %.6g %.6g %.6g\n", p.x, p.y, p.z, c.x, c.y, c.z);
        }
        out.text(line);
    }
    for (const glm::vec3& n : m.normals) {
        std::snprintf(line, sizeof line, "vn %.7g %.7g %.7g\n", n.x, n.y, n.z);
        out.text(line);
    }
    for (std::size_t t = 0; t < m.triangleCount(); ++t) {
        const uint32_t a = m.indices[3 * t] + 1, b = m.indices[3 * t + 1] + 1, c = m.indices[3 * t + 2] + 1;
        if (m.normals.empty())
            std::snprintf(line, sizeof line, "f %u %u %u\n", a, b, c);
        else
            std::snprintf(line, sizeof line, "f %u//%u %u//%u %u//%u\n", a, a, b, b, c, c);
        out.text(line);
    }
}

void writeStl(const MeshBuffers& m, Positions pos, LengthUnit unit, ByteWriter& out) {
    // The header must not start with "solid" (readers would take the file for ASCII STL).
    char header[80] = {};
    std::snprintf(header, sizeof header, "Kizamu binary STL, units: %s", unitSymbol(unit));
    out.putRaw(header, sizeof header);
    out.put(uint32_t(m.triangleCount()));
    for (std::size_t t = 0; t < m.triangleCount(); ++t) {
        out.put(faceNormal(m, pos, t));
        for (int k = 0; k < 3; ++k) out.put(pos[m.indices[3 * t + k]]);
        out.put(uint16_t(0));
    }
}

void writePly(const MeshBuffers& m, Positions pos, LengthUnit unit, ByteWriter& out) {
    std::string header = "ply\nformat binary_little_endian 1.0\n";
    header += "comment Kizamu mesh, coordinates in " + std::string(unitSymbol(unit)) + "\n";
    header += "element vertex " + std::to_string(m.vertexCount()) +
              "\nproperty float x\nproperty float y\nproperty float z\n";
    if (!m.normals.empty()) header += "property float nx\nproperty float ny\nproperty float nz\n";
    if (!m.colours.empty()) header += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
    header += "element face " + std::to_string(m.triangleCount()) + "\nproperty list uchar int vertex_indices\nend_header\n";
    out.text(header);
    // Readers built on assimp (5.2, Debian's) drop a line feed that starts the binary data, and
    // read every value after it one byte off (assimp issue #5341; older versions skipped any
    // blank): the vertex written first is one whose first byte (x's lowest) is no line end or
    // blank, swapped with vertex 0.
    auto safeFirst = [&](std::size_t i) {
        uint32_t bits;
        std::memcpy(&bits, &pos[i].x, sizeof bits);
        const uint8_t b = uint8_t(bits);
        return b != '\n' && b != '\r' && b != ' ' && b != '\t';
    };
    std::size_t first = 0;
    while (first < m.vertexCount() && !safeFirst(first)) ++first;
    if (first == m.vertexCount()) first = 0;
    auto slot = [&](std::size_t i) { return i == 0 ? first : i == first ? 0 : i; };  // its own inverse
    for (std::size_t k = 0; k < m.vertexCount(); ++k) {
        const std::size_t i = slot(k);
        out.put(pos[i]);
        if (!m.normals.empty()) out.put(m.normals[i]);
        if (!m.colours.empty()) out.put(m.colours[i]);
    }
    for (std::size_t t = 0; t < m.triangleCount(); ++t) {
        out.put(uint8_t(3));
        for (int k = 0; k < 3; ++k) out.put(int32_t(slot(m.indices[3 * t + k])));
    }
}

/// glTF 2.0 binary: one mesh, one primitive (triangles), positions/normals/colours/indices in
/// one buffer, each view 4-byte aligned.
void writeGlb(const MeshBuffers& m, Positions pos, ByteWriter& out) {
    ByteWriter bin;
    nlohmann::ordered_json views = nlohmann::ordered_json::array(), accessors = nlohmann::ordered_json::array();
    auto addView = [&](const void* data, std::size_t bytes, int target) {
        bin.pad(4, std::byte{0});
        const std::size_t offset = bin.size();
        bin.putRaw(data, bytes);
        views.push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", bytes}, {"target", target}});
        return views.size() - 1;
    };
    constexpr int kArrayBuffer = 34962, kElementArrayBuffer = 34963;
    constexpr int kFloat = 5126, kUnsignedInt = 5125;
    glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
    for (const glm::vec3& p : pos) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    nlohmann::ordered_json attributes;
    accessors.push_back({{"bufferView", addView(pos.data(), pos.size() * 12, kArrayBuffer)},
                         {"componentType", kFloat}, {"count", m.vertexCount()}, {"type", "VEC3"},
                         {"min", {lo.x, lo.y, lo.z}}, {"max", {hi.x, hi.y, hi.z}}});
    attributes["POSITION"] = accessors.size() - 1;
    if (!m.normals.empty()) {
        accessors.push_back({{"bufferView", addView(m.normals.data(), m.normals.size() * 12, kArrayBuffer)},
                             {"componentType", kFloat}, {"count", m.vertexCount()}, {"type", "VEC3"}});
        attributes["NORMAL"] = accessors.size() - 1;
    }
    if (!m.colours.empty()) {
        // glTF's COLOR_0 is linear: convert our sRGB bytes, stored as float RGB.
        auto linear = [](uint8_t c) {
            const float v = float(c) / 255.0f;
            return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
        };
        std::vector<glm::vec3> rgb(m.colours.size());
        for (std::size_t i = 0; i < rgb.size(); ++i)
            rgb[i] = {linear(m.colours[i].r), linear(m.colours[i].g), linear(m.colours[i].b)};
        accessors.push_back({{"bufferView", addView(rgb.data(), rgb.size() * 12, kArrayBuffer)},
                             {"componentType", kFloat}, {"count", m.vertexCount()}, {"type", "VEC3"}});
        attributes["COLOR_0"] = accessors.size() - 1;
    }
    accessors.push_back({{"bufferView", addView(m.indices.data(), m.indices.size() * 4, kElementArrayBuffer)},
                         {"componentType", kUnsignedInt}, {"count", m.indices.size()}, {"type", "SCALAR"}});
    const std::size_t indexAccessor = accessors.size() - 1;
    bin.pad(4, std::byte{0});

    nlohmann::ordered_json gltf;
    gltf["asset"] = {{"version", "2.0"}, {"generator", "Kizamu"}};
    gltf["scene"] = 0;
    gltf["scenes"] = {{{"nodes", {0}}}};
    gltf["nodes"] = {{{"mesh", 0}}};
    gltf["meshes"] = {{{"primitives", {{{"attributes", attributes}, {"indices", indexAccessor}, {"mode", 4}}}}}};
    gltf["buffers"] = {{{"byteLength", bin.size()}}};
    gltf["bufferViews"] = views;
    gltf["accessors"] = accessors;
    std::string json = gltf.dump();
    while (json.size() % 4) json.push_back(' ');

    out.put(uint32_t(0x46546C67));  // "glTF"
    out.put(uint32_t(2));
    out.put(uint32_t(12 + 8 + json.size() + 8 + bin.size()));
    out.put(uint32_t(json.size()));
    out.put(uint32_t(0x4E4F534A));  // "JSON"
    out.putRaw(json.data(), json.size());
    out.put(uint32_t(bin.size()));
    out.put(uint32_t(0x004E4942));  // "BIN\0"
    out.putRaw(bin.bytes().data(), bin.size());
}

std::string extensionOf(const std::string& path) {
    const auto dot = path.rfind('.');
    std::string ext = dot == std::string::npos ? "" : path.substr(dot + 1);
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return ext;
}

}  // namespace

MeshFormat meshFormatOf(const std::string& path) {
    const std::string ext = extensionOf(path);
    if (ext == "obj") return MeshFormat::Obj;
    if (ext == "stl") return MeshFormat::Stl;
    if (ext == "ply") return MeshFormat::Ply;
    if (ext == "glb") return MeshFormat::Glb;
    if (ext == "off") return MeshFormat::Off;
    throw FileError(path, "unknown mesh format '." + ext + "' (use .obj, .stl, .ply, .off or .glb)");
}

double metresPer(LengthUnit unit) {
    switch (unit) {
        case LengthUnit::Millimetre: return 0.001;
        case LengthUnit::Centimetre: return 0.01;
        case LengthUnit::Metre: return 1.0;
    }
    return 1.0;
}

void scaleToMetres(MeshBuffers& m, LengthUnit unit) {
    const double factor = metresPer(unit);
    if (factor == 1.0) return;
    for (glm::vec3& p : m.positions) p = glm::vec3(glm::dvec3(p) * factor);
}

const char* unitSymbol(LengthUnit unit) {
    switch (unit) {
        case LengthUnit::Millimetre: return "mm";
        case LengthUnit::Centimetre: return "cm";
        case LengthUnit::Metre: return "m";
    }
    return "?";
}

std::optional<LengthUnit> lengthUnitOf(std::string_view symbol) {
    if (symbol == "mm") return LengthUnit::Millimetre;
    if (symbol == "cm") return LengthUnit::Centimetre;
    if (symbol == "m") return LengthUnit::Metre;
    return std::nullopt;
}

ExportFormat exportFormatOf(const std::string& path) {
    const std::string ext = extensionOf(path);
    if (ext == "obj") return ExportFormat::Obj;
    if (ext == "stl") return ExportFormat::Stl;
    if (ext == "ply") return ExportFormat::Ply;
    if (ext == "glb") return ExportFormat::Glb;
    if (ext == "3mf") return ExportFormat::ThreeMf;
    const std::string formats = "(use .obj, .stl, .ply, .glb or .3mf)";
    if (ext == "off") throw FileError(path, "writing .off is not supported " + formats);
    throw FileError(path, "unknown mesh format '." + ext + "' to write " + formats);
}

LengthUnit defaultUnit(ExportFormat format) {
    return format == ExportFormat::Glb ? LengthUnit::Metre : LengthUnit::Millimetre;
}

LengthUnit exportUnit(const std::string& path, const ExportOptions& options) {
    const ExportFormat format = exportFormatOf(path);
    const LengthUnit unit = options.unit.value_or(defaultUnit(format));
    if (format == ExportFormat::Glb && unit != LengthUnit::Metre)
        throw FileError(path, std::string("glTF is in metres by its specification: it cannot be "
                                          "written in ") +
                                  unitSymbol(unit) + " (scale it in the importing tool)");
    return unit;
}

void exportMesh(const MeshBuffers& mesh, const std::string& path, const ExportOptions& options) {
    const ExportFormat format = exportFormatOf(path);
    const LengthUnit unit = exportUnit(path, options);
    if (!mesh.valid()) throw FileError(path, "refusing to write an invalid mesh (sizes or indices out of range)");
    if (mesh.triangleCount() == 0) throw FileError(path, "refusing to write a mesh with no triangles");
    for (const glm::vec3& p : mesh.positions)
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
            throw FileError(path, "refusing to write a mesh with non-finite positions");
    // Scaled in double and rounded once, so that a unit's export is the nearest float to the
    // metre value times the factor.
    std::vector<glm::vec3> scaled;
    Positions pos = mesh.positions;
    if (unit != options.meshUnit) {
        const double factor = metresPer(options.meshUnit) / metresPer(unit);
        scaled.resize(mesh.positions.size());
        for (std::size_t i = 0; i < scaled.size(); ++i) {
            const glm::vec3 p = glm::vec3(glm::dvec3(mesh.positions[i]) * factor);
            if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
                throw FileError(path, std::string("positions overflow a float in ") +
                                          unitSymbol(unit));
            scaled[i] = p;
        }
        pos = scaled;
    }
    // Last, on the coordinates as they will be written: scaling rounds, and could bring two
    // vertices onto one float or a vertex onto another triangle's plane.
    MeshBuffers untangled;
    if (options.untangle) {
        untangled.positions.assign(pos.begin(), pos.end());
        untangled.indices = mesh.indices;
        const UntangleReport r = untangle(untangled, options.pool, 64,
                                          format == ExportFormat::ThreeMf ? detail::threeMfWritten : nullptr);
        if (options.untangled != nullptr) *options.untangled = r;  // (the caller reports r.remaining)
        pos = Positions(untangled.positions.data(), untangled.positions.size());
    }
    ByteWriter out;
    switch (format) {
        case ExportFormat::Obj: writeObj(mesh, pos, unit, out); break;
        case ExportFormat::Stl: writeStl(mesh, pos, unit, out); break;
        case ExportFormat::Ply: writePly(mesh, pos, unit, out); break;
        case ExportFormat::Glb: writeGlb(mesh, pos, out); break;
        case ExportFormat::ThreeMf: detail::writeThreeMf(mesh, pos, unit, path, out.bytes()); break;
    }
    util::writeFileAtomically(path, out.bytes());
}

}  // namespace kizamu::mesh
