// SPDX-License-Identifier: Apache-2.0
/// @file openvdb_peer.h
/// @brief The OpenVDB side of the peer benchmarks: the same part as a narrow-band level set.
///
/// Only benchmark code includes this; nothing in src/ sees OpenVDB. The level set samples the
/// same DistanceSource at the same lattice points as the ADF (voxel = finest cell), so both
/// answer queries about the same field at the same resolution. Queries use OpenVDB's own
/// BoxStencil (trilinear value and gradient, cached ValueAccessor), its fastest path.
/// Threading: build is parallel (TBB inside OpenVDB); one OpenVdbPeer queries on one thread.
#pragma once

#include "adf/adf.h"
#include "adf/distance_source.h"
#include "adf/domain.h"

#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>

namespace kizamu::bench {

class OpenVdbPeer {
public:
    /// Narrow-band level set of `source`: voxels at the lattice points of `domain` with
    /// |d| < halfWidthVoxels finest cells are active; inside/outside tiles carry -/+ background.
    /// Complexity: O(voxels in the band) distance evaluations. Memory: the grid.
    OpenVdbPeer(const adf::DistanceSource& source, const adf::Domain& domain, float halfWidthVoxels = 3.0f);
    ~OpenVdbPeer();
    OpenVdbPeer(const OpenVdbPeer&) = delete;
    OpenVdbPeer& operator=(const OpenVdbPeer&) = delete;

    /// Grid::memUsage() of the level set, bytes.
    std::size_t memoryBytes() const;
    /// Active voxels.
    std::size_t activeVoxels() const;
    /// Wall time of the build, s.
    double buildSeconds() const;
    /// Trilinear distance (m) and gradient at `pWorld` through a BoxStencil with a cached accessor.
    /// Not thread-safe (the stencil caches). Memory: none.
    adf::Sample sample(const glm::vec3& pWorld);

    /// What tools::volumeToMesh produced.
    struct MeshResult {
        double seconds = 0.0;
        std::size_t points = 0, quads = 0, triangles = 0;
        /// Triangles if every quad were split in two (what our count compares with).
        std::size_t triangleEquivalent() const { return triangles + 2 * quads; }
    };
    /// tools::volumeToMesh of the zero level set with adaptivity 0 (OpenVDB's own threading).
    MeshResult meshSurface() const;

    /// A carve dab the OpenVDB way: the sphere's distance written into the voxels of its box
    /// plus the narrow band (max(old, -sphere), through an accessor), then the region (that box)
    /// clipped out and meshed with volumeToMesh.
    struct DabResult {
        double stampSeconds = 0.0, meshSeconds = 0.0;
        std::size_t triangles = 0;  ///< triangle equivalent of the region mesh
    };
    DabResult carveSphereAndMeshRegion(const glm::dvec3& centreWorld, double radiusWorld);

private:
    struct Impl;
    std::unique_ptr<Impl> mImpl;
};

/// tools::meshToLevelSet of a triangle mesh (m) at voxel size `voxelWorld` with a band of
/// `halfWidthVoxels`: OpenVDB's mesh import, timed (s). Returns the seconds; `activeVoxels`
/// gets the voxel count of the result.
double openVdbMeshToLevelSet(std::span<const glm::vec3> positions, std::span<const uint32_t> indices,
                             double voxelWorld, float halfWidthVoxels, std::size_t* activeVoxels = nullptr);

}  // namespace kizamu::bench
