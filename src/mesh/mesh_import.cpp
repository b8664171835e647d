// SPDX-License-Identifier: Apache-2.0
/// @file mesh_import.cpp
/// @brief OBJ, STL and OFF readers (PLY: mesh_import_ply.cpp), and recognition of a format by
/// content.
///
/// Leniency follows what assimp, MeshLab and tinyobjloader accept: unknown statements and
/// header lines are stepped over with a warning; a count, an index or a coordinate that cannot
/// be read is an error naming its line (or, in binary data, its entry and byte).
#include "mesh/mesh_import.h"

#include "mesh/mesh_import_assimp.h"
#include "mesh/mesh_import_text.h"
#include "util/atomic_file.h"
#include "util/file_error.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iterator>
#include <unordered_map>
#include <vector>

namespace kizamu::mesh {

using namespace detail;

namespace {

// ---- OBJ ----

/// OBJ statements that hold nothing a triangle mesh needs (texture coordinates, normals, groups,
/// materials, lines, points, free-form geometry, display attributes).
bool isOtherObjStatement(std::string_view k) {
    static constexpr std::string_view kKnown[] = {
        "vt",        "vn",    "vp",       "g",        "o",    "s",      "usemtl", "mtllib",
        "l",         "p",     "cstype",   "deg",      "bmat", "step",   "curv",   "curv2",
        "surf",      "parm",  "trim",     "hole",     "scrv", "sp",     "end",    "con",
        "mg",        "bevel", "c_interp", "d_interp", "lod",  "usemap", "maplib", "shadow_obj",
        "trace_obj", "ctech", "stech",    "call",     "csh",  "res"};
    return std::find(std::begin(kKnown), std::end(kKnown), k) != std::end(kKnown);
}

MeshBuffers readObj(std::string_view text, const std::string& name, WarningLog& log) {
    TextReader r(text, name, log);
    MeshBuffers m;
    std::string_view line;
    std::vector<std::string_view> tok;
    std::vector<uint32_t> face;
    bool colours = true;
    while (r.nextLine(line)) {
        const std::size_t n = split(line, tok);
        if (n == 0) continue;
        if (tok[0] == "v") {
            if (n < 4) r.fail("a vertex needs 3 coordinates");
            glm::vec3 p, c(0.0f);
            for (int a = 0; a < 3; ++a)
                if (!parseFloat(tok[1 + a], p[a]))
                    r.fail("bad vertex coordinate " + quoted(tok[1 + a]));
            bool hasColour = n >= 7;
            for (int a = 0; a < 3 && hasColour; ++a)
                if (!parseFloat(tok[4 + a], c[a])) {
                    hasColour = false;
                    r.warn("obj-colour",
                           [&] { return "a vertex colour that is not a number is ignored"; });
                }
            // x y z, x y z w (w ignored, as every reader does) or x y z r g b; more are ignored.
            if (n == 6 || n > 7)
                r.warn("obj-values", [&] {
                    return "a vertex with " + std::to_string(n - 1) +
                           " values: the extra ones are ignored";
                });
            colours = colours && hasColour;
            m.positions.push_back(p);
            m.colours.push_back(glm::u8vec3(glm::clamp(c, 0.0f, 1.0f) * 255.0f + 0.5f));
        } else if (tok[0] == "f" || tok[0] == "fo") {  // fo: the old name of f
            if (n < 4) {
                r.warn("obj-face", [] { return "a face with fewer than 3 corners is skipped"; });
                continue;
            }
            face.clear();
            for (std::size_t k = 1; k < n; ++k) {
                const std::string_view idx = tok[k].substr(0, tok[k].find('/'));
                long long i;
                if (!parseNumber(idx, i) || i == 0) r.fail("bad face index " + quoted(tok[k]));
                const long long count = (long long)m.positions.size();
                const long long zeroBased =
                    i > 0 ? i - 1 : count + i;  // negative: relative to the end
                if (zeroBased < 0 || zeroBased >= count)
                    r.fail("face index " + std::to_string(i) + " out of range");
                face.push_back(uint32_t(zeroBased));
            }
            addPolygon(m, face.data(), face.size());
        } else if (!isOtherObjStatement(tok[0])) {
            r.warn("obj-statement " + std::string(tok[0].substr(0, 40)),
                   [&] { return "unknown statement " + quoted(tok[0]) + " skipped"; });
        }
    }
    if (!colours) m.colours.clear();
    return m;
}

// ---- STL ----

/// Welds exactly equal positions (STL stores three per facet).
struct Welder {
    MeshBuffers& m;
    std::unordered_map<uint64_t, std::vector<uint32_t>> buckets;
    uint32_t add(glm::vec3 p) {
        p += glm::vec3(0.0f);  // -0 becomes +0, so equal positions hash equally
        uint32_t bits[3];
        std::memcpy(bits, &p, 12);
        const uint64_t key =
            (uint64_t(bits[0]) * 0x9e3779b97f4a7c15ull) ^ (uint64_t(bits[1]) << 21) ^ bits[2];
        auto& bucket = buckets[key];
        for (uint32_t i : bucket)
            if (m.positions[i] == p) return i;
        m.positions.push_back(p);
        bucket.push_back(uint32_t(m.positions.size() - 1));
        return bucket.back();
    }
};

/// The facet count of a binary STL whose size is exactly 84 + 50 x the count in its header.
std::optional<uint32_t> exactBinaryStlCount(std::string_view bytes) {
    if (bytes.size() < 84) return std::nullopt;
    uint32_t count;
    std::memcpy(&count, bytes.data() + 80, 4);
    if (84 + uint64_t(count) * 50 != bytes.size()) return std::nullopt;
    return count;
}

MeshBuffers readBinaryStl(std::string_view bytes, uint32_t count, const std::string& name) {
    MeshBuffers m;
    Welder weld{m, {}};
    for (uint32_t t = 0; t < count; ++t) {
        const std::size_t at = 84 + std::size_t(t) * 50;
        uint32_t tri[3];
        for (int k = 0; k < 3; ++k) {
            glm::vec3 p;
            std::memcpy(&p, bytes.data() + at + 12 + 12 * k, 12);
            if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
                throw FileError(name, "facet " + std::to_string(t) + " (byte " +
                                          std::to_string(at) + ") has a non-finite vertex");
            tri[k] = weld.add(p);
        }
        addPolygon(m, tri, 3);
    }
    return m;
}

MeshBuffers readAsciiStl(std::string_view text, const std::string& name, WarningLog& log) {
    MeshBuffers m;
    Welder weld{m, {}};
    TextReader r(text, name, log);
    std::string_view line;
    std::vector<std::string_view> tok;
    std::vector<uint32_t> facet;
    // A facet ends at endloop; endfacet, the next facet or endsolid end one whose endloop is
    // missing.
    auto closeFacet = [&] {
        if (facet.empty()) return;
        if (facet.size() < 3) {
            r.warn("stl-short", [] { return "a facet with fewer than 3 vertices is skipped"; });
        } else {
            if (facet.size() > 3)
                r.warn("stl-long", [&] {
                    return "a facet with " + std::to_string(facet.size()) +
                           " vertices is fanned into triangles";
                });
            addPolygon(m, facet.data(), facet.size());
        }
        facet.clear();
    };
    while (r.nextLine(line)) {
        const std::size_t n = split(line, tok);
        if (n == 0) continue;
        const std::string_view k = tok[0];
        if (equalsNoCase(k, "vertex")) {
            if (n < 4) r.fail("a vertex needs 3 coordinates");
            glm::vec3 p;
            for (int a = 0; a < 3; ++a)
                if (!parseFloat(tok[1 + a], p[a]))
                    r.fail("bad vertex coordinate " + quoted(tok[1 + a]));
            if (n > 4)
                r.warn("stl-values",
                       [] { return "values after a vertex's 3 coordinates are ignored"; });
            facet.push_back(weld.add(p));
        } else if (equalsNoCase(k, "endloop") || equalsNoCase(k, "endfacet") ||
                   equalsNoCase(k, "facet") || equalsNoCase(k, "endsolid")) {
            closeFacet();
        } else if (!equalsNoCase(k, "solid") && !equalsNoCase(k, "outer")) {
            r.warn("stl-line " + std::string(k.substr(0, 40)),
                   [&] { return "unknown line " + quoted(k) + " skipped"; });
        }
    }
    if (!facet.empty()) r.fail("truncated: the last facet is incomplete");
    return m;
}

MeshBuffers readStl(std::string_view bytes, const std::string& name, WarningLog& log) {
    if (const auto count = exactBinaryStlCount(bytes)) return readBinaryStl(bytes, *count, name);
    if (hasUtf16Mark(bytes) || looksLikeText(bytes)) {
        std::string storage;
        bool transcoded;
        const std::string_view text = textOf(bytes, storage, transcoded, &log);
        if (!startsWithNoCase(text, "solid")) {
            if (!containsNoCase(text.substr(0, kSniffBytes), "facet"))
                throw FileError(
                    name, "not an STL file (no 'solid' header, and not the size of a binary STL)");
            log.add("stl-solid", [] { return "no 'solid' header: read as ASCII STL"; });
        }
        return readAsciiStl(text, name, log);
    }
    if (bytes.size() < 84)
        throw FileError(name, "not an STL file (too short, and no 'solid' header)");
    uint32_t count;
    std::memcpy(&count, bytes.data() + 80, 4);
    const uint64_t held = (bytes.size() - 84) / 50;
    if (count == 0 && held > 0) {
        // Some exporters leave the count at 0; the size says how many facets there are.
        count = uint32_t(std::min<uint64_t>(held, 0xFFFFFFFFu));
        log.add("stl-count", [&] {
            return "the header counts 0 facets; the " + std::to_string(count) +
                   " the file holds are read";
        });
    }
    if (count > held)
        throw FileError(name, "binary STL size does not match its facet count: it counts " +
                                  std::to_string(count) + " facets and holds " +
                                  std::to_string(held) + " (truncated?)");
    if (const uint64_t tail = bytes.size() - 84 - uint64_t(count) * 50; tail > 0)
        log.add("stl-tail", [&] {
            return std::to_string(tail) + " bytes after the last of " + std::to_string(count) +
                   " facets are ignored";
        });
    return readBinaryStl(bytes, count, name);
}

// ---- OFF ----

/// True for the header keywords of 3D OFF: [ST][C][N]OFF.
bool isOffKeyword(std::string_view k) {
    if (k.substr(0, 2) == "ST") k.remove_prefix(2);
    if (!k.empty() && k[0] == 'C') k.remove_prefix(1);
    if (!k.empty() && k[0] == 'N') k.remove_prefix(1);
    return k == "OFF";
}

bool endsWithOff(std::string_view k) {
    return k.size() >= 3 && k.substr(k.size() - 3) == "OFF";
}

MeshBuffers readOff(std::string_view text, const std::string& name, WarningLog& log) {
    TextReader r(text, name, log);
    std::string_view line;
    std::vector<std::string_view> tok;
    auto next = [&]() -> std::size_t {
        while (r.nextLine(line)) {
            const std::size_t n = split(line, tok);
            if (n > 0) return n;
        }
        r.fail("truncated: the file ends early");
    };
    std::size_t n = next();
    std::size_t at = 0;  // where the counts start on the current line
    uint64_t nv, nf;
    if (endsWithOff(tok[0])) {
        if (!isOffKeyword(tok[0]))
            r.fail("the OFF variant " + quoted(tok[0]) + " (not 3D) cannot be read");
        if (n >= 2 && tok[1] == "BINARY") r.fail("binary OFF cannot be read");
        at = 1;  // the counts may follow the keyword on the same line
        if (n == 1) {
            n = next();
            at = 0;
        }
    } else if (parseNumber(tok[0], nv)) {
        r.warn("off-header", [] {
            return "no OFF header keyword (it is optional): the counts are read from here";
        });
    } else {
        r.fail("not an OFF file (no OFF header)");
    }
    if (n < at + 2 || !parseNumber(tok[at], nv) || !parseNumber(tok[at + 1], nf))
        r.fail("expected vertex and face counts");
    if (nv > r.bytesLeft() || nf > r.bytesLeft()) r.fail("counts exceed the size of the file");
    MeshBuffers m;
    m.positions.reserve(std::size_t(nv));
    for (uint64_t i = 0; i < nv; ++i) {
        if (next() < 3) r.fail("a vertex needs 3 coordinates");
        glm::vec3 p;
        for (int a = 0; a < 3; ++a)
            if (!parseFloat(tok[a], p[a])) r.fail("bad vertex coordinate " + quoted(tok[a]));
        m.positions.push_back(p);
    }
    std::vector<uint32_t> face;
    for (uint64_t f = 0; f < nf; ++f) {
        const std::size_t k = next();
        std::size_t count;
        if (!parseNumber(tok[0], count))
            r.fail("a face needs a vertex count, not " + quoted(tok[0]));
        if (count > k - 1)
            r.fail("a face of " + std::to_string(count) + " corners lists " +
                   std::to_string(k - 1));
        if (count < 3) {
            r.warn("off-face", [] { return "a face with fewer than 3 corners is skipped"; });
            continue;
        }
        face.clear();
        for (std::size_t j = 0; j < count; ++j) {
            uint32_t i;
            if (!parseNumber(tok[1 + j], i) || i >= m.positions.size())
                r.fail("face index " + quoted(tok[1 + j]) + " out of range (" +
                       std::to_string(m.positions.size()) + " vertices)");
            face.push_back(i);
        }
        addPolygon(m, face.data(), face.size());
    }
    return m;
}

/// True when the lines of `text` read as OBJ: a `v` line, and at least as many OBJ statements
/// (v, f and the rest) as other lines.
bool looksLikeObj(std::string_view text) {
    WarningLog ignored;
    const std::string noName;
    TextReader r(text, noName, ignored);
    std::string_view line;
    std::vector<std::string_view> tok;
    std::size_t vertices = 0, statements = 0, others = 0;
    while (r.nextLine(line)) {
        if (split(line, tok) == 0) continue;
        if (tok[0] == "v") ++vertices;
        if (tok[0] == "v" || tok[0] == "f" || isOtherObjStatement(tok[0]))
            ++statements;
        else
            ++others;
    }
    return vertices > 0 && statements >= others;
}

}  // namespace

std::optional<MeshFormat> meshFormatOfContent(std::string_view bytes) {
    if (bytes.empty()) return std::nullopt;
    if (bytes.substr(0, 4) == "glTF") return MeshFormat::Glb;
    std::string storage;
    bool transcoded;
    const std::string_view head =
        textOf(bytes, storage, transcoded, nullptr, kSniffBytes).substr(0, kSniffBytes);
    if (head.size() > 3 && head.substr(0, 3) == "ply" && (head[3] == '\n' || head[3] == '\r'))
        return MeshFormat::Ply;
    if (!transcoded && exactBinaryStlCount(bytes)) return MeshFormat::Stl;
    if (!looksLikeText(head)) return std::nullopt;
    {
        WarningLog ignored;
        const std::string noName;
        TextReader r(head, noName, ignored);
        std::string_view line;
        std::vector<std::string_view> tok;
        while (r.nextLine(line))
            if (split(line, tok) > 0) break;
        if (!tok.empty() && endsWithOff(tok[0])) return MeshFormat::Off;
    }
    if (startsWithNoCase(head, "solid") && containsNoCase(head, "facet")) return MeshFormat::Stl;
    if (looksLikeObj(head)) return MeshFormat::Obj;
    return std::nullopt;
}

MeshBuffers decodeMesh(std::string_view bytes, MeshFormat format, const std::string& name,
                       std::vector<std::string>* warnings) {
    if (bytes.empty()) throw FileError(name, "the file is empty");
    WarningLog log;
    std::string storage;
    bool transcoded = false;
    MeshBuffers m;
    switch (format) {
        case MeshFormat::Obj:
            m = readObj(textOf(bytes, storage, transcoded, &log), name, log);
            break;
        case MeshFormat::Stl:
            m = readStl(bytes, name, log);
            break;  // binary or text: it decides
        case MeshFormat::Ply: {
            const std::string_view text = textOf(bytes, storage, transcoded, &log);
            m = readPly(text, name, log, transcoded);
            break;
        }
        case MeshFormat::Off:
            m = readOff(textOf(bytes, storage, transcoded, &log), name, log);
            break;
        case MeshFormat::Glb:
            throw FileError(name, "glTF binary is read through assimp (importMesh), not here");
    }
    if (m.triangleCount() == 0) throw FileError(name, "the file holds no triangles");
    log.appendTo(warnings, name);
    return m;
}

namespace {

/// The formats whose unit the helper applies (glTF is metres by its specification; FBX's
/// UnitScaleFactor and COLLADA's <unit> are converted): the rest (3DS, X, 3MF, AMF, ...) come as
/// their numbers, like ours.
bool assimpConvertsToMetres(std::string_view extension) {
    for (const char* e : {"gltf", "glb", "fbx", "dae"})
        if (equalsNoCase(extension, e)) return true;
    return false;
}

}  // namespace

MeshBuffers importMesh(const std::string& path, std::vector<std::string>* warnings, bool* inMetres) {
    const std::string bytes = util::readWholeFile(path);
    if (inMetres != nullptr) *inMetres = false;
    // Content first, then the extension; our readers (faster, and fuzzed) before assimp, which
    // runs in a child process (mesh_import_assimp.h). Glb: we only write it, assimp reads it.
    const MeshFormat none = MeshFormat::Glb;  // "not one of ours"
    MeshFormat byName = none;
    try {
        byName = meshFormatOf(path);
    } catch (const FileError&) {
        // Not one of our extensions: the content, or assimp's extensions, decide.
    }
    const MeshFormat byContent = meshFormatOfContent(bytes).value_or(none);
    std::optional<AssimpFormat> foreign;  // a format only assimp reads, by the content
    if (byContent == none) foreign = assimpFormatOfContent(bytes);
    const std::string extension = std::filesystem::path(path).extension().string();
    const bool foreignName = byName == none && assimpReadsExtension(path);
    if (byContent == none && !foreign && byName == none) {
        if (foreignName) {
            if (inMetres != nullptr) *inMetres = assimpConvertsToMetres(extension.empty() ? "" : extension.substr(1));
            return importWithAssimp(path, {}, warnings);
        }
        throw FileError(path,
                        "unknown mesh format: neither the extension nor the content is one Kizamu "
                        "reads (OBJ, STL, PLY, OFF; through assimp glTF, FBX, COLLADA, 3DS, ...)");
    }
    AssimpImportSettings settings;
    if (foreign && !equalsNoCase(extension, "." + std::string(foreign->extension)))
        settings.asExtension = foreign->extension;  // assimp would go by the name
    if ((byContent != none && byContent != byName) || !settings.asExtension.empty()) {
        const std::string content =
            byContent != none ? formatName(byContent) : std::string(foreign->name);
        std::string named = "no mesh extension";
        if (byName != none)
            named = "the extension names " + std::string(formatName(byName));
        else if (foreignName)
            named = "the extension is " + extension;
        if (warnings != nullptr)
            warnings->push_back(path + ": " + named + ", but the content is " + content +
                                ": read as " + content);
    }
    if (foreign) {
        if (inMetres != nullptr) *inMetres = assimpConvertsToMetres(foreign->extension);
        return importWithAssimp(path, settings, warnings);
    }
    return decodeMesh(bytes, byContent != none ? byContent : byName, path, warnings);
}

}  // namespace kizamu::mesh
