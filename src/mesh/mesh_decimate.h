// SPDX-License-Identifier: Apache-2.0
/// @file mesh_decimate.h
/// @brief A decimated copy of a mesh for export: meshoptimizer's edge-collapse simplifier
/// (meshopt_simplify, Garland and Heckbert's quadric error metric) down to a fraction of the
/// triangles, the border kept where it is.
///
/// Where it sits: after the mesher (surface_nets.h) and before the exporter (mesh_export.h),
/// on an export's own thread. The simplifier takes vertices at one position for one vertex, so
/// the source's coincident vertices (where two sheets of the mesher's surface touch) are first
/// separated by the least that tells them apart (mesh_untangle.h). It only collapses edges onto
/// vertices that exist, so every vertex of the result is a vertex of the source, and carries
/// that vertex's colour and normal (its nearest source vertex). A closed mesh stays closed: the
/// simplifier avoids flipped faces but may pinch the surface, so the collapse runs in passes and
/// a pass that adds edge defects (an edge used twice or left unpaired) is retried with half the
/// step. Border vertices never move (meshopt_SimplifyLockBorder), so an open mesh keeps its
/// outline. Cold path; any thread.
#pragma once

#include "mesh/mesh_buffers.h"

#include <cstddef>
#include <string>

namespace kizamu::mesh {

struct DecimateSettings {
    /// The fraction of the triangles to keep, (0, 1]. The result may stay above it where every
    /// remaining collapse would pinch the surface or move the border.
    double ratio = 0.5;
    /// The largest deviation allowed, as a fraction of the mesh's extent (meshopt_simplify's
    /// target_error); 1: the triangle count alone decides.
    double maxErrorRelative = 1.0;
};

/// What a decimation did.
struct DecimateReport {
    std::size_t trianglesBefore = 0, trianglesAfter = 0;
    double errorWorld = 0.0;  ///< the simplifier's estimate of the largest deviation, in `mesh`'s unit
};

/// The decimated copy of `mesh` (indexed, vertices shared between triangles as the mesher
/// makes them; a triangle soup has only borders and keeps them all). Its vertices are the used
/// subset of `mesh`'s (untangled), in their order, with their normals and colours where `mesh`
/// has them.
/// @throw std::invalid_argument for a ratio outside (0, 1] or an invalid mesh
/// Complexity: O(T log T) per pass in the source's triangles T; one pass, a few more where the
///             simplifier pinched the surface
/// Threading:  any thread; reads `mesh` only
/// Memory:     the result, plus a copy of the positions and index and remap arrays the size of the source's
MeshBuffers decimateMesh(const MeshBuffers& mesh, const DecimateSettings& settings, DecimateReport* report = nullptr);

/// Where an export's decimated copy goes: NAME.decimated.EXT beside `path` ("bust.stl" gives
/// "bust.decimated.stl"). Complexity: O(path length).
std::string decimatedPath(const std::string& path);

}  // namespace kizamu::mesh
