// SPDX-License-Identifier: Apache-2.0
/// @file mesh_export.h
/// @brief Writes MeshBuffers as OBJ, binary STL, binary PLY, glTF 2.0 binary (.glb) or 3MF, in
/// a chosen length unit.
///
/// Formats other tools read: normals are written where the format has them (OBJ `vn`, PLY
/// nx/ny/nz, glTF NORMAL; STL carries per-facet normals from the triangle), colours where it
/// has them (OBJ `v x y z r g b`, PLY red/green/blue, glTF COLOR_0; 3MF gets geometry only).
/// OBJ, STL and PLY have no unit: their coordinates are millimetres by default, what slicers and
/// most importers assume for a unitless file. 3MF names its unit in the file (millimetres by
/// default). glTF is metres by its specification. The clay (MeshBuffers) is in metres. Files
/// are replaced atomically. Cold path; any thread.
#pragma once

#include "mesh/mesh_buffers.h"
#include "mesh/mesh_untangle.h"

#include <optional>
#include <string>
#include <string_view>

namespace kizamu::mesh {

/// Glb is written only; Off is read only. (3MF, written only, is ExportFormat::ThreeMf.)
enum class MeshFormat { Obj, Stl, Ply, Glb, Off };

/// Format from the file extension (case-insensitive). @throw kizamu::FileError if unknown.
MeshFormat meshFormatOf(const std::string& path);

/// The formats exportMesh writes.
enum class ExportFormat { Obj, Stl, Ply, Glb, ThreeMf };

/// A length unit of a mesh file's coordinates.
enum class LengthUnit { Millimetre, Centimetre, Metre };

/// Metres in one `unit` (0.001, 0.01, 1).
double metresPer(LengthUnit unit);
/// Scales `m`'s positions from `unit` to metres, as the ADF and the clay hold them (nothing to
/// do for metres). Complexity: O(vertices).
void scaleToMetres(MeshBuffers& m, LengthUnit unit);
/// The unit's symbol: "mm", "cm" or "m".
const char* unitSymbol(LengthUnit unit);
/// The unit a symbol names ("mm", "cm", "m"); empty for anything else.
std::optional<LengthUnit> lengthUnitOf(std::string_view symbol);

/// How exportMesh writes a file.
struct ExportOptions {
    /// The unit of the file's coordinates; empty: the format's default (defaultUnit). glTF is
    /// metres by its specification: any other unit is refused for .glb.
    std::optional<LengthUnit> unit;
    /// The unit the mesh's positions are in: metres for the clay; a mesh read from a file and
    /// written again unchanged may stay in its file's unit (then equal units copy coordinates
    /// exactly).
    LengthUnit meshUnit = LengthUnit::Metre;
    /// Untangle the positions as written (mesh_untangle.h): no two vertices at one position and
    /// no two triangles meeting but along what they share, on the file's float32 coordinates.
    /// For the mesher's meshes; a mesh read from a file is written as it came.
    bool untangle = false;
    /// Where the untangling's pair tests run (nullptr: the caller's thread), and where its
    /// report goes (nullptr: nowhere; the file is written even if contacts remain, which the
    /// report's `remaining` says).
    util::ThreadPool* pool = nullptr;
    UntangleReport* untangled = nullptr;
};

/// Format to write from the file extension (case-insensitive: .obj .stl .ply .glb .3mf).
/// @throw kizamu::FileError for any other extension (.off is read only).
ExportFormat exportFormatOf(const std::string& path);

/// The unit a format is written in when ExportOptions::unit is empty: millimetres for OBJ, STL,
/// PLY and 3MF, metres for glTF.
LengthUnit defaultUnit(ExportFormat format);

/// The unit exportMesh would write `path` in with `options`.
/// @throw kizamu::FileError for an unknown extension, or a unit other than metres for glTF;
/// call it before long work to refuse a bad request early.
LengthUnit exportUnit(const std::string& path, const ExportOptions& options);

/// Writes `mesh` to `path` in the format its extension names, its positions scaled from
/// options.meshUnit to the file's unit (exportUnit).
/// @throw kizamu::FileError on an invalid mesh, an unknown extension, a unit the format cannot
/// take or an I/O failure.
/// Complexity: O(vertices + triangles). Memory: one buffer the size of the file, plus a scaled
/// copy of the positions when the units differ (3MF: lib3mf's model of the mesh besides).
void exportMesh(const MeshBuffers& mesh, const std::string& path,
                const ExportOptions& options = {});

}  // namespace kizamu::mesh
