// SPDX-License-Identifier: Apache-2.0
/// @file lod.h
/// @brief Level-of-detail meshes (Kizamu 7.2): SurfaceNets over the coarsest cells whose error
/// is under a threshold.
///
/// The fine field is re-sampled top-down into a new ADF whose cells stop splitting as soon as
/// the fine field is within `errorWorld` of their trilinear reconstruction at the 19 test
/// points (surface band only), then meshed by SurfaceNets: the result keeps every guarantee of
/// surface_nets.h (closed, oriented, manifold), and the work follows the cells of the output,
/// not the fine ADF. Complexity: O(output cells) samples of the fine field, each O(tile span).
/// Threading: parallel on `pool`. Memory: the coarse ADF while it runs.
#pragma once

#include "adf/adf.h"
#include "adf/distance_source.h"
#include "mesh/mesh_buffers.h"
#include "mesh/surface_nets.h"

#include <cstddef>

namespace kizamu::util {
class ThreadPool;
}

namespace kizamu::mesh {

/// The fine field as the source coarsenAdf re-samples: trilinear reconstruction, which at a
/// lattice point of `fine` is the value stored there. It answers the lattice points of any
/// domain whose lattice is a sub-lattice of fine's (the same cube, no more levels) directly
/// (adf::DistanceSource::answersLattice), the same values as at their world positions.
/// @throw std::invalid_argument for a null snapshot.
adf::SourcePtr makeFineFieldSource(adf::AdfPtr fine);

/// The coarse ADF: `fine` re-sampled with error bound `errorWorld` (m) at the surface.
/// @throw std::invalid_argument if errorWorld is not positive and finite.
adf::AdfPtr coarsenAdf(const adf::AdfPtr& fine, double errorWorld, util::ThreadPool* pool = nullptr);

/// The LOD mesh of `fine` at error `errorWorld` (m), with vertex colours from `fine`'s paint
/// when it has any (the coarse ADF itself carries none).
MeshBuffers meshLod(const adf::AdfPtr& fine, double errorWorld, util::ThreadPool* pool = nullptr,
                    SurfaceNetsStats* stats = nullptr);

/// The error (m) whose LOD mesh has about `triangles` triangles (bisection on a log scale,
/// within 15 %): what the benchmarks and tests ask for (`kizamu convert --lod` takes an error).
double lodErrorForTriangles(const adf::AdfPtr& fine, std::size_t triangles, util::ThreadPool* pool = nullptr);

}  // namespace kizamu::mesh
