// SPDX-License-Identifier: Apache-2.0
/// @file openvdb_peer.cpp
/// @brief Builds the OpenVDB narrow-band level set of a DistanceSource and samples it.
///
/// The build culls 8^3 voxel blocks (OpenVDB leaves) hierarchically with the 1-Lipschitz
/// bound of the source, fills the surviving leaves in parallel (each task owns its own leaf,
/// so no locking), then hands the non-empty leaves to the tree serially, which is cheap next
/// to the distance evaluations. Signed flood fill then gives the culled interior -background.
#include "bench/openvdb_peer.h"

#include <openvdb/Grid.h>
#include <openvdb/math/Stencils.h>
#include <openvdb/math/Transform.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/MeshToVolume.h>
#include <openvdb/tools/SignedFloodFill.h>
#include <openvdb/tools/VolumeToMesh.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <glm/vec3.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <optional>
#include <span>
#include <stdexcept>
#include <vector>

namespace kizamu::bench {

namespace {

using LeafT = openvdb::FloatTree::LeafNodeType;
constexpr int kLeafDim = int(LeafT::DIM);  // 8
static_assert(LeafT::DIM == 8 && LeafT::SIZE == 512, "the culling assumes 8^3 leaves");

/// Lattice-point bounds of the leaves that may hold band voxels, found by octree culling.
class BlockCuller {
public:
    BlockCuller(const adf::DistanceSource& source, const adf::Domain& domain, double background)
        : mSource(source), mDomain(domain), mBackground(background),
          mLast(domain.latticeSize()), mH(domain.finestCellSize()) {}

    /// Origins (lattice units, multiples of 8) of every leaf the 1-Lipschitz test cannot reject.
    std::vector<openvdb::Coord> run() {
        // Blocks cover lattice points 0..N inclusive, so N/8 + 1 of them per axis; recurse over
        // the enclosing power-of-two cube and drop the parts beyond the lattice.
        const uint32_t blocks = mLast / kLeafDim + 1;
        uint32_t cube = 1;
        while (cube < blocks) cube *= 2;
        std::vector<openvdb::Coord> out;
        visit(0, 0, 0, cube * kLeafDim, out);
        return out;
    }

private:
    void visit(uint32_t x0, uint32_t y0, uint32_t z0, uint32_t size,
               std::vector<openvdb::Coord>& out) const {
        if (x0 > mLast || y0 > mLast || z0 > mLast) return;
        // Bounding box of the lattice points actually inside this cube.
        const uint32_t x1 = std::min(x0 + size - 1, mLast);
        const uint32_t y1 = std::min(y0 + size - 1, mLast);
        const uint32_t z1 = std::min(z0 + size - 1, mLast);
        const glm::dvec3 lo = mDomain.latticeToWorld(x0, y0, z0);
        const glm::dvec3 hi = mDomain.latticeToWorld(x1, y1, z1);
        const glm::dvec3 half = 0.5 * (hi - lo);
        const double halfDiagonal = std::sqrt(half.x * half.x + half.y * half.y + half.z * half.z);
        // Slack of a hundredth of a cell absorbs rounding in d and in the centre position.
        if (std::abs(mSource.distance(lo + half)) > halfDiagonal + mBackground + 0.01 * mH) return;
        if (size == uint32_t(kLeafDim)) {
            out.emplace_back(int(x0), int(y0), int(z0));
            return;
        }
        const uint32_t s = size / 2;
        for (int c = 0; c < 8; ++c)
            visit(x0 + (c & 1 ? s : 0), y0 + (c & 2 ? s : 0), z0 + (c & 4 ? s : 0), s, out);
    }

    const adf::DistanceSource& mSource;
    const adf::Domain& mDomain;
    double mBackground;
    uint32_t mLast;  ///< last lattice index per axis (latticeSize)
    double mH;
};

/// A leaf for the block at `origin` with band voxels active and the rest at +-background,
/// or null when no voxel of the block is in the band.
LeafT* fillLeaf(const adf::DistanceSource& source, const adf::Domain& domain,
                const openvdb::Coord& origin, float background) {
    const uint32_t last = domain.latticeSize();
    const int nx = int(std::min<uint32_t>(kLeafDim, last - uint32_t(origin.x()) + 1));
    const int ny = int(std::min<uint32_t>(kLeafDim, last - uint32_t(origin.y()) + 1));
    const int nz = int(std::min<uint32_t>(kLeafDim, last - uint32_t(origin.z()) + 1));

    std::array<glm::dvec3, LeafT::SIZE> points;
    std::array<openvdb::Index, LeafT::SIZE> offsets;
    std::array<double, LeafT::SIZE> d;
    std::size_t n = 0;
    for (int i = 0; i < nx; ++i) {
        for (int j = 0; j < ny; ++j) {
            for (int k = 0; k < nz; ++k) {
                // Same expression as the ADF's lattice points, so both see identical inputs.
                points[n] = domain.latticeToWorld(uint32_t(origin.x() + i),
                                                  uint32_t(origin.y() + j),
                                                  uint32_t(origin.z() + k));
                offsets[n] = LeafT::coordToOffset(origin.offsetBy(i, j, k));
                ++n;
            }
        }
    }
    source.distances(std::span<const glm::dvec3>(points.data(), n), std::span<double>(d.data(), n));

    bool any = false;
    for (std::size_t p = 0; p < n; ++p) any = any || std::abs(d[p]) < double(background);
    if (!any) return nullptr;

    auto* leaf = new LeafT(origin, background, false);
    for (std::size_t p = 0; p < n; ++p) {
        const float v = float(d[p]);
        if (std::abs(d[p]) < double(background)) {
            leaf->setValueOn(offsets[p], v);
        } else {
            // The sign of their side, which flood fill's scanline pass reproduces anyway; set
            // here so the leaf does not depend on that pass being exact.
            leaf->setValueOff(offsets[p], d[p] < 0.0 ? -background : background);
        }
    }
    return leaf;
}

}  // namespace

struct OpenVdbPeer::Impl {
    openvdb::FloatGrid::Ptr grid;
    // Declared after the grid: its accessor must be destroyed before the tree it watches.
    std::optional<openvdb::math::BoxStencil<openvdb::FloatGrid>> stencil;
    double buildSeconds = 0.0;
};

OpenVdbPeer::OpenVdbPeer(const adf::DistanceSource& source, const adf::Domain& domain,
                         float halfWidthVoxels)
    : mImpl(std::make_unique<Impl>()) {
    if (!domain.valid()) throw std::invalid_argument("OpenVdbPeer: invalid domain");
    if (!(halfWidthVoxels > 0.0f)) throw std::invalid_argument("OpenVdbPeer: halfWidthVoxels <= 0");
    openvdb::initialize();

    const auto start = std::chrono::steady_clock::now();
    const double h = domain.finestCellSize();
    const float background = float(double(halfWidthVoxels) * h);

    auto grid = openvdb::FloatGrid::create(background);
    grid->setGridClass(openvdb::GRID_LEVEL_SET);
    auto xform = openvdb::math::Transform::createLinearTransform(h);
    xform->postTranslate(openvdb::Vec3d(domain.originWorld.x, domain.originWorld.y,
                                        domain.originWorld.z));
    grid->setTransform(xform);

    const std::vector<openvdb::Coord> origins =
        BlockCuller(source, domain, double(background)).run();

    std::vector<LeafT*> leaves(origins.size(), nullptr);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, origins.size(), 64),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                          for (std::size_t b = r.begin(); b != r.end(); ++b)
                              leaves[b] = fillLeaf(source, domain, origins[b], background);
                      });

    // Serial: the tree structure is not thread-safe, but linking a ready leaf is O(depth).
    {
        openvdb::FloatGrid::Accessor acc = grid->getAccessor();
        for (LeafT* leaf : leaves)
            if (leaf) acc.addLeaf(leaf);  // the tree takes ownership
    }

    openvdb::tools::signedFloodFill(grid->tree());
    // Tolerance zero: only collapses nodes whose values are all identical, so no value changes.
    grid->tree().prune();

    mImpl->buildSeconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    mImpl->grid = grid;
    mImpl->stencil.emplace(*grid);
}

OpenVdbPeer::~OpenVdbPeer() = default;

std::size_t OpenVdbPeer::memoryBytes() const { return std::size_t(mImpl->grid->memUsage()); }

std::size_t OpenVdbPeer::activeVoxels() const {
    return std::size_t(mImpl->grid->activeVoxelCount());
}

double OpenVdbPeer::buildSeconds() const { return mImpl->buildSeconds; }

adf::Sample OpenVdbPeer::sample(const glm::vec3& pWorld) {
    const openvdb::Vec3d ijk =
        mImpl->grid->transform().worldToIndex(openvdb::Vec3d(pWorld.x, pWorld.y, pWorld.z));
    auto& stencil = *mImpl->stencil;
    stencil.moveTo(ijk);
    const openvdb::Vec3f xyz(ijk);
    // BoxStencil::gradient already maps the index-space derivative through the transform's
    // inverse Jacobian (applyIJT), i.e. divides by h: the result is per metre, like ours.
    const float d = stencil.interpolation(xyz);
    const openvdb::Vec3f g = stencil.gradient(xyz);
    return adf::Sample{d, glm::vec3(g.x(), g.y(), g.z())};
}

OpenVdbPeer::MeshResult OpenVdbPeer::meshSurface() const {
    std::vector<openvdb::Vec3s> points;
    std::vector<openvdb::Vec3I> triangles;
    std::vector<openvdb::Vec4I> quads;
    const auto start = std::chrono::steady_clock::now();
    openvdb::tools::volumeToMesh(*mImpl->grid, points, triangles, quads, 0.0, 0.0);
    MeshResult r;
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    r.points = points.size();
    r.quads = quads.size();
    r.triangles = triangles.size();
    return r;
}

OpenVdbPeer::DabResult OpenVdbPeer::carveSphereAndMeshRegion(const glm::dvec3& c, double r) {
    openvdb::FloatGrid& grid = *mImpl->grid;
    const openvdb::math::Transform& xf = grid.transform();
    const double band = double(grid.background());  // the narrow band's half width, m
    const openvdb::Vec3d lo = xf.worldToIndex(openvdb::Vec3d(c.x - r - band, c.y - r - band, c.z - r - band));
    const openvdb::Vec3d hi = xf.worldToIndex(openvdb::Vec3d(c.x + r + band, c.y + r + band, c.z + r + band));
    const openvdb::CoordBBox box(openvdb::Coord::floor(lo), openvdb::Coord::floor(hi) + openvdb::Coord(1));
    DabResult out;
    const auto t0 = std::chrono::steady_clock::now();
    {
        openvdb::FloatGrid::Accessor acc = grid.getAccessor();
        for (openvdb::Coord ijk = box.min(); ijk.x() <= box.max().x(); ++ijk.x())
            for (ijk.y() = box.min().y(); ijk.y() <= box.max().y(); ++ijk.y())
                for (ijk.z() = box.min().z(); ijk.z() <= box.max().z(); ++ijk.z()) {
                    const openvdb::Vec3d w = xf.indexToWorld(ijk);
                    const double sphere = std::sqrt((w.x() - c.x) * (w.x() - c.x) + (w.y() - c.y) * (w.y() - c.y) +
                                                    (w.z() - c.z) * (w.z() - c.z)) - r;
                    const float old = acc.getValue(ijk);
                    const float v = std::max(old, float(-sphere));
                    if (std::abs(v) < float(band)) {
                        acc.setValue(ijk, v);
                    } else if (acc.isValueOn(ijk) || v > 0.0f) {
                        acc.setValueOff(ijk, v > 0.0f ? float(band) : -float(band));  // left the band
                    }
                }
    }
    const auto t1 = std::chrono::steady_clock::now();
    // The region's active voxels copied into a small grid (tools::clip would copy the whole
    // tree first), inside and outside restored by a signed flood fill.
    openvdb::FloatGrid::Ptr region = openvdb::FloatGrid::create(grid.background());
    region->setTransform(grid.transformPtr());
    region->setGridClass(openvdb::GRID_LEVEL_SET);
    {
        openvdb::FloatGrid::ConstAccessor src = grid.getConstAccessor();
        openvdb::FloatGrid::Accessor dst = region->getAccessor();
        for (openvdb::Coord ijk = box.min(); ijk.x() <= box.max().x(); ++ijk.x())
            for (ijk.y() = box.min().y(); ijk.y() <= box.max().y(); ++ijk.y())
                for (ijk.z() = box.min().z(); ijk.z() <= box.max().z(); ++ijk.z()) {
                    float v;
                    if (src.probeValue(ijk, v)) dst.setValue(ijk, v);
                }
    }
    openvdb::tools::signedFloodFill(region->tree());
    std::vector<openvdb::Vec3s> points;
    std::vector<openvdb::Vec3I> triangles;
    std::vector<openvdb::Vec4I> quads;
    openvdb::tools::volumeToMesh(*region, points, triangles, quads, 0.0, 0.0);
    const auto t2 = std::chrono::steady_clock::now();
    out.stampSeconds = std::chrono::duration<double>(t1 - t0).count();
    out.meshSeconds = std::chrono::duration<double>(t2 - t1).count();
    out.triangles = triangles.size() + 2 * quads.size();
    return out;
}

double openVdbMeshToLevelSet(std::span<const glm::vec3> positions, std::span<const uint32_t> indices,
                             double voxelWorld, float halfWidthVoxels, std::size_t* activeVoxels) {
    openvdb::initialize();
    std::vector<openvdb::Vec3s> points;
    points.reserve(positions.size());
    for (const glm::vec3& p : positions) points.emplace_back(p.x, p.y, p.z);  // world space
    std::vector<openvdb::Vec3I> triangles;
    triangles.reserve(indices.size() / 3);
    for (std::size_t i = 0; i + 2 < indices.size(); i += 3)
        triangles.emplace_back(indices[i], indices[i + 1], indices[i + 2]);
    const auto xform = openvdb::math::Transform::createLinearTransform(voxelWorld);
    const auto start = std::chrono::steady_clock::now();
    auto grid = openvdb::tools::meshToLevelSet<openvdb::FloatGrid>(*xform, points, triangles, halfWidthVoxels);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (activeVoxels) *activeVoxels = std::size_t(grid->activeVoxelCount());
    return seconds;
}

}  // namespace kizamu::bench
