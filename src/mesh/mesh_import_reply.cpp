// SPDX-License-Identifier: Apache-2.0
/// @file mesh_import_reply.cpp
/// @brief The import helper's reply: encoding (in kizamu-import) and strict decoding (in the
/// parent). Layout in mesh_import_reply.h.
#include "mesh/mesh_import_reply.h"

#include "util/file_error.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>

namespace kizamu::mesh {

static_assert(std::endian::native == std::endian::little,
              "the import reply is little-endian and copied as is");

namespace {

constexpr uint32_t kKindMesh = 1;
constexpr uint32_t kKindError = 2;

void putU32(std::string& out, uint32_t v) {
    out.append(reinterpret_cast<const char*>(&v), 4);
}

void putMessage(std::string& out, std::string_view text) {
    const std::string line = replyLine(text);
    putU32(out, uint32_t(line.size()));
    out += line;
}

/// Reads the reply front to back; every read is checked against the bytes left.
class ReplyReader {
public:
    ReplyReader(std::string_view bytes, const std::string& name) : mBytes(bytes), mName(name) {}

    /// Names `what` and the byte it is at (where the reader is, unless given).
    [[noreturn]] void fail(const std::string& what, std::size_t at = SIZE_MAX) const {
        throw FileError(mName, "the import helper's reply is malformed: " + what + " (byte " +
                                   std::to_string(at == SIZE_MAX ? mAt : at) + " of " +
                                   std::to_string(mBytes.size()) + ")");
    }
    std::size_t at() const { return mAt; }
    std::size_t left() const { return mBytes.size() - mAt; }
    std::string_view take(std::size_t n, const char* what) {
        if (n > left()) fail(std::string("truncated in ") + what);
        const std::string_view s = mBytes.substr(mAt, n);
        mAt += n;
        return s;
    }
    uint32_t u32(const char* what) {
        uint32_t v;
        std::memcpy(&v, take(4, what).data(), 4);
        return v;
    }
    std::string message(const char* what) {
        const uint32_t n = u32(what);
        if (n == 0 || n > kMaxReplyMessageBytes)
            fail(std::string("a ") + what + " of " + std::to_string(n) + " bytes");
        const std::string_view s = take(n, what);
        for (const char c : s)
            if (static_cast<unsigned char>(c) < 0x20 || c == 0x7F)
                fail(std::string("a control character in a ") + what);
        return std::string(s);
    }

private:
    std::string_view mBytes;
    const std::string& mName;
    std::size_t mAt = 0;
};

}  // namespace

std::string replyLine(std::string_view text) {
    std::string out;
    for (const char c : text) {
        const bool space = static_cast<unsigned char>(c) <= 0x20 || c == 0x7F;
        if (space) {
            if (!out.empty() && out.back() != ' ') out += ' ';
        } else {
            out += c;
        }
    }
    while (!out.empty() && out.back() == ' ') out.pop_back();
    if (out.size() > kMaxReplyMessageBytes) {
        std::size_t n = kMaxReplyMessageBytes - 3;
        while (n > 0 && (static_cast<unsigned char>(out[n]) & 0xC0) == 0x80) --n;
        out.resize(n);
        out += "...";
    }
    return out.empty() ? "?" : out;
}

std::string encodeImportReply(const MeshBuffers& mesh, const std::vector<std::string>& warnings) {
    std::string out(kImportReplyMagic);
    putU32(out, kKindMesh);
    const uint32_t kept = uint32_t(std::min<std::size_t>(warnings.size(), kMaxReplyWarnings));
    putU32(out, kept);
    for (uint32_t i = 0; i < kept; ++i) putMessage(out, warnings[i]);
    putU32(out, uint32_t(mesh.vertexCount()));
    putU32(out, uint32_t(mesh.triangleCount()));
    out.append(reinterpret_cast<const char*>(mesh.positions.data()), mesh.vertexCount() * 12);
    out.append(reinterpret_cast<const char*>(mesh.indices.data()), mesh.triangleCount() * 12);
    return out;
}

std::string encodeImportError(std::string_view message) {
    std::string out(kImportReplyMagic);
    putU32(out, kKindError);
    putMessage(out, message);
    return out;
}

MeshBuffers decodeImportReply(std::string_view reply, const std::string& name,
                              std::vector<std::string>* warnings) {
    if (reply.empty()) throw FileError(name, "the import helper gave no reply");
    ReplyReader r(reply, name);
    if (r.take(std::min(r.left(), kImportReplyMagic.size()), "the magic") != kImportReplyMagic)
        r.fail("no KZIMPRT1 magic");
    const uint32_t kind = r.u32("the kind");
    if (kind == kKindError) {
        const std::string message = r.message("message");
        if (r.left() != 0) r.fail(std::to_string(r.left()) + " bytes after the error message");
        throw FileError(name, message);
    }
    if (kind != kKindMesh) r.fail("unknown kind " + std::to_string(kind));
    const uint32_t warningCount = r.u32("the warning count");
    if (warningCount > kMaxReplyWarnings) r.fail(std::to_string(warningCount) + " warnings");
    std::vector<std::string> said;
    for (uint32_t i = 0; i < warningCount; ++i) said.push_back(r.message("warning"));
    const uint32_t vertexCount = r.u32("the vertex count");
    const uint32_t triangleCount = r.u32("the triangle count");
    if (vertexCount == 0) r.fail("no vertices");
    if (triangleCount == 0) r.fail("no triangles");
    // Checked before anything is allocated: the counts must account for every byte left.
    const uint64_t need = uint64_t(vertexCount) * 12 + uint64_t(triangleCount) * 12;
    if (need != r.left())
        r.fail(std::to_string(vertexCount) + " vertices and " + std::to_string(triangleCount) +
               " triangles need " + std::to_string(need) + " bytes, " + std::to_string(r.left()) +
               " are left");
    MeshBuffers m;
    const std::size_t positionsAt = r.at(), indicesAt = positionsAt + std::size_t(vertexCount) * 12;
    m.positions.resize(vertexCount);
    std::memcpy(m.positions.data(), r.take(std::size_t(vertexCount) * 12, "positions").data(),
                std::size_t(vertexCount) * 12);
    for (uint32_t v = 0; v < vertexCount; ++v) {
        const glm::vec3& p = m.positions[v];
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
            r.fail("vertex " + std::to_string(v) + " is not finite", positionsAt + v * 12);
    }
    m.indices.resize(std::size_t(triangleCount) * 3);
    std::memcpy(m.indices.data(), r.take(std::size_t(triangleCount) * 12, "indices").data(),
                std::size_t(triangleCount) * 12);
    for (std::size_t i = 0; i < m.indices.size(); ++i)
        if (m.indices[i] >= vertexCount)
            r.fail("triangle " + std::to_string(i / 3) + " has index " +
                       std::to_string(m.indices[i]) + " of " + std::to_string(vertexCount) +
                       " vertices",
                   indicesAt + i * 4);
    if (warnings != nullptr)
        for (const std::string& w : said) warnings->push_back(name + ": " + w);
    return m;
}

}  // namespace kizamu::mesh
