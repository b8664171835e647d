// SPDX-License-Identifier: Apache-2.0
/// @file mesh_import_assimp.h
/// @brief The formats our readers do not read (glTF, FBX, COLLADA, 3DS and the rest of
/// assimp's), imported by assimp in a child process: `kizamu-import`.
///
/// importMesh sends a file here when neither its content nor its extension is OBJ, STL, PLY or
/// OFF (ours, faster) but its content or extension is one assimp reads. Assimp is not ours to
/// fix and Debian's build is not fuzzed, so it never runs in this process: a crash, a hang or
/// an exhausted memory inside it ends the child, and the caller gets a one-line FileError
/// (docs/decisions/0028-assimp-in-a-child-process.md). The child flattens the scene (every
/// mesh with its node transforms, triangulated, points and lines dropped) and writes it in the
/// reply format of mesh_import_reply.h, which this side decodes strictly.
///
/// Units: metres, as everywhere. glTF is metres by its specification. The child applies the
/// unit a file declares where assimp reads one: FBX's UnitScaleFactor (centimetres per unit)
/// through aiProcess_GlobalScale, with a warning when the scale is not 1; COLLADA's
/// `<unit meter>` in the root node's transform. Formats without units (3DS, X, ...) are taken
/// as metres. Axes are kept as the file has them (src/import/assimp_read.h).
///
/// Threading: any thread; each call starts its own child and waits for it (posix_spawn, safe
/// in a multi-threaded process). Cold path.
#pragma once

#include "mesh/mesh_buffers.h"

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace kizamu::mesh {

struct AssimpImportSettings {
    /// The helper executable. Empty: $KIZAMU_IMPORT_HELPER, else `kizamu-import` in the running
    /// executable's folder, else `kizamu-import` on the PATH.
    std::string helper;
    /// Seconds the helper may run before it is killed. 0 or less: $KIZAMU_IMPORT_TIMEOUT_S,
    /// else 120.
    double timeoutS = 0.0;
    /// Read the file as if its extension were this one ("glb"): for content whose format its
    /// name does not say (assimp picks its reader by the extension first). Empty: its own.
    std::string asExtension;
};

/// Imports `path` through the helper.
/// @param warnings  the child's warnings, one line each, starting with `path`; may be null.
/// @throw kizamu::FileError (one line, starting with `path`) when assimp cannot read the file,
/// the helper cannot start, crashes (signal), exits non-zero, runs past the timeout, or
/// replies with anything mesh_import_reply.h does not allow. The child is always reaped.
/// Complexity: assimp's; the reply is O(vertices + triangles). Memory: the reply and the mesh.
MeshBuffers importWithAssimp(const std::string& path, const AssimpImportSettings& settings = {},
                             std::vector<std::string>* warnings = nullptr);

/// A format only assimp reads, recognised by its content.
struct AssimpFormat {
    std::string_view name;       ///< for messages: "glTF binary", "glTF", "COLLADA", "FBX", "3DS"
    std::string_view extension;  ///< what assimp knows it by: "glb", "gltf", "dae", "fbx", "3ds"
};

/// The format `bytes` hold where it is one only assimp reads and its content says so (glTF
/// binary or JSON, COLLADA, FBX binary or ASCII, 3DS). Empty otherwise.
/// Complexity: O(1): looks at the first 64 KiB at most.
std::optional<AssimpFormat> assimpFormatOfContent(std::string_view bytes);

/// True when the extension of `path` (case-insensitive) is one assimp 5.2 reads and ours do
/// not (.gltf, .glb, .fbx, .dae, .3ds, .x, .blend, ...).
bool assimpReadsExtension(const std::string& path);

}  // namespace kizamu::mesh
