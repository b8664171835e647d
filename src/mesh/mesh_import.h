// SPDX-License-Identifier: Apache-2.0
/// @file mesh_import.h
/// @brief Reads triangle meshes from OBJ, STL (ASCII or binary), PLY (ASCII or binary, either
/// byte order) and OFF into MeshBuffers.
///
/// Polygons are fanned into triangles, STL's per-facet vertices are welded by exact position,
/// and vertex colours are kept where the file has them (OBJ `v x y z r g b`, PLY red/green/blue).
/// Normals are not read: the ADF recomputes them. Counts are checked against the bytes left
/// before anything is allocated, and indices must be whole and in range, so a damaged, empty,
/// enormous or hostile file gives a one-line FileError (with the line, or for binary data the
/// entry and byte, that is wrong); the fuzz harness holds the readers to that.
///
/// The readers are as lenient as the widely used ones (assimp, MeshLab, tinyobjloader): what
/// they do not understand but can step over (a PLY header line that is neither `comment` nor a
/// keyword, an unknown OBJ statement, a face of fewer than 3 corners, trailing bytes after a
/// binary STL's facets) is skipped with a warning; numbers may carry a leading `+`; text may be
/// UTF-8 with a byte-order mark or UTF-16 (either byte order) with one, and its lines may end in
/// LF, CRLF or CR. Only what cannot be read is refused. Warnings are one line each, name the
/// file and the line, and repeat a kind only as a count ("and 41 more like it"). Cold path;
/// any thread.
///
/// importMesh sends every other format it recognises (glTF/GLB, FBX, COLLADA, 3DS and the rest
/// of assimp's) to assimp in a child process (mesh_import_assimp.h).
#pragma once

#include "mesh/mesh_buffers.h"
#include "mesh/mesh_export.h"

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace kizamu::mesh {

/// Parses `bytes` as `format`; `name` prefixes error messages and warnings.
/// @param warnings  where the problems that were stepped over are appended (one line each,
///                  starting with `name`); may be null, then they are dropped.
/// @throw kizamu::FileError (one line, naming the line or entry) for what cannot be read.
/// Complexity: O(bytes). Memory: the mesh, plus a UTF-8 copy of UTF-16 text.
MeshBuffers decodeMesh(std::string_view bytes, MeshFormat format, const std::string& name,
                       std::vector<std::string>* warnings = nullptr);

/// The format `bytes` hold, by their content: PLY's `ply` magic, an OFF header keyword, a
/// binary STL whose size is 84 + 50 x its facet count, an ASCII STL (`solid` then `facet`),
/// glTF binary (`glTF` magic; named, and read by importMesh through assimp), or OBJ (`v` lines, most lines OBJ
/// statements). Text may carry a byte-order mark. Empty when none of these fits.
/// Complexity: O(1): looks at the first 64 KiB at most.
std::optional<MeshFormat> meshFormatOfContent(std::string_view bytes);

/// Reads `path`. Its content decides the format where meshFormatOfContent or
/// assimpFormatOfContent recognises it (with a warning when that disagrees with the extension,
/// or the extension is not a mesh format's); otherwise its extension does. OBJ, STL, PLY and
/// OFF are read by our readers (decodeMesh); every other format by assimp in a child process
/// (importWithAssimp, default settings).
/// @param warnings  as for decodeMesh; may be null.
/// @param inMetres  set where not null: true when the format carries its unit and the positions
///                  were converted to metres (glTF, FBX, COLLADA, read through assimp), false
///                  when the numbers are as the file holds them (OBJ, STL, PLY, OFF, and assimp's
///                  other formats: 3DS, X, 3MF, ...).
/// @throw kizamu::FileError when the file cannot be read, neither its content nor its extension
/// names a format, or decodeMesh or importWithAssimp fails.
MeshBuffers importMesh(const std::string& path, std::vector<std::string>* warnings = nullptr,
                       bool* inMetres = nullptr);

}  // namespace kizamu::mesh
