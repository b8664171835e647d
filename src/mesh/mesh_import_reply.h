// SPDX-License-Identifier: Apache-2.0
/// @file mesh_import_reply.h
/// @brief The reply the import helper (`kizamu-import`, assimp in its own process) writes on its
/// standard output, and its strict decoder in the parent.
///
/// The helper runs code that is not ours and not built for fuzzing, so the parent trusts nothing
/// in the reply: every count is checked against the bytes left before anything is allocated,
/// every index against the vertex count, every coordinate for finiteness, every message for
/// control characters, and the reply must end exactly where its counts say. The fuzz harness
/// (tests/fuzz/fuzz_import_reply.cpp) holds the decoder to that. Layout, little-endian, no
/// padding:
/// ```
///   magic      8 bytes  "KZIMPRT1"
///   kind       u32      1: a mesh, 2: an error
///   error:     message (below); the reply ends there
///   mesh:      u32 warning count (at most kMaxReplyWarnings), each a message;
///              u32 vertex count, u32 triangle count (each at least 1);
///              vertex count x 3 f32 positions (finite; metres, world frame);
///              triangle count x 3 u32 indices (each below the vertex count)
///   message:   u32 byte count (1 to kMaxReplyMessageBytes), then UTF-8 bytes, no byte below
///              0x20 and no 0x7F: one line
/// ```
/// Cold path; any thread.
#pragma once

#include "mesh/mesh_buffers.h"

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace kizamu::mesh {

inline constexpr std::string_view kImportReplyMagic = "KZIMPRT1";
inline constexpr std::size_t kMaxReplyMessageBytes = 1024;
inline constexpr uint32_t kMaxReplyWarnings = 64;

/// `text` as one line a reply may carry: control characters become spaces, runs of spaces one
/// space, ends trimmed, at most kMaxReplyMessageBytes bytes (whole UTF-8 characters, "..." where
/// cut). "?" when nothing is left.
std::string replyLine(std::string_view text);

/// The reply for a mesh. `mesh` must be valid() with finite positions and at least one
/// triangle, and its vertex count must fit in 32 bits; `warnings` are folded with replyLine and
/// only the first kMaxReplyWarnings are kept.
/// Complexity: O(vertices + triangles). Memory: the reply.
std::string encodeImportReply(const MeshBuffers& mesh, const std::vector<std::string>& warnings);

/// The reply for a file the helper could not read; `message` is folded with replyLine.
std::string encodeImportError(std::string_view message);

/// Decodes a reply. Only positions and indices are filled in.
/// @param name      prefixes the error and the warnings (the imported file's path)
/// @param warnings  where the reply's warnings are appended as "name: warning"; may be null.
/// @throw kizamu::FileError (one line): "name: MESSAGE" for an error reply; "name: the import
///        helper's reply is malformed: WHAT" for anything the layout above does not allow.
/// Complexity: O(reply bytes). Memory: the mesh.
MeshBuffers decodeImportReply(std::string_view reply, const std::string& name,
                              std::vector<std::string>* warnings = nullptr);

}  // namespace kizamu::mesh
