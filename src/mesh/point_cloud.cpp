// SPDX-License-Identifier: Apache-2.0
/// @file point_cloud.cpp
/// @brief surfacePointCloud.
#include "mesh/point_cloud.h"

#include "adf/boundary_cells.h"
#include "mesh/mesh_colours.h"
#include "util/thread_pool.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <functional>

namespace kizamu::mesh {

namespace {

/// Small, fast, good enough for jitter (splitmix64).
struct SplitMix {
    uint64_t s;
    uint64_t next() {
        uint64_t z = (s += 0x9e3779b97f4a7c15ull);
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
        return z ^ (z >> 31);
    }
    float unit() { return float(next() >> 40) * (1.0f / 16777216.0f); }
};

/// Estimated surface area of a boundary cell (lattice units squared): its face area over the
/// L1 norm of the unit gradient at its centre, the mean area of a plane across it.
double cellArea(const adf::BoundaryCell& cell) {
    const adf::Sample s = adf::trilinear(cell.corners, glm::vec3(0.5f));
    const float g1 = std::abs(s.gradient.x) + std::abs(s.gradient.y) + std::abs(s.gradient.z);
    const float g2 = glm::length(s.gradient);
    const double size = double(cell.size);
    return g1 > 0.0f ? size * size * double(g2 / g1) : size * size;
}

}  // namespace

PointCloud surfacePointCloud(const adf::Adf& adf, std::size_t count, uint64_t seed, util::ThreadPool* pool) {
    PointCloud out;
    // Boundary cells and their running area, tile by tile (in slot order, so the result does
    // not depend on threads); the cells stay in their tile's list.
    std::vector<const adf::Tile*> tiles;
    adf.forEachTile([&](const adf::Tile& t) { tiles.push_back(&t); });
    std::vector<std::vector<adf::BoundaryCell>> cells(tiles.size());
    std::vector<std::vector<double>> area(tiles.size());  // per tile: area of its cells before each, then the total
    const int maxLevel = adf.domain().maxLevel;
    util::parallelFor(pool, tiles.size(), [&](std::size_t i) {
        adf::appendBoundaryCells(*tiles[i], maxLevel, cells[i]);
        area[i].resize(cells[i].size() + 1);
        area[i][0] = 0.0;
        for (std::size_t j = 0; j < cells[i].size(); ++j) area[i][j + 1] = area[i][j] + cellArea(cells[i][j]);
    });
    // Where each tile's cells and area start in the whole.
    std::vector<std::size_t> firstCell(tiles.size() + 1, 0);
    std::vector<double> areaBefore(tiles.size() + 1, 0.0);
    for (std::size_t i = 0; i < tiles.size(); ++i) {
        firstCell[i + 1] = firstCell[i] + cells[i].size();
        areaBefore[i + 1] = areaBefore[i] + area[i].back();
    }
    if (firstCell.back() == 0 || count == 0) return out;

    // Cell j of tile i gets the points whose stratified positions k + 0.5 fall in its share of
    // the total (a tile's last bound is the next tile's first: the same sum).
    const double total = areaBefore.back();
    auto firstPoint = [&](std::size_t i, std::size_t j) {
        return std::size_t(std::min(double(count), std::ceil((areaBefore[i] + area[i][j]) / total * double(count) - 0.5)));
    };
    out.positions.resize(count);  // every point is written below, by the thread that places it
    out.normals.resize(count);
    const glm::vec3 origin = adf.originWorldF();
    const float h = adf.metresPerLattice();
    util::parallelFor(pool, tiles.size(), [&](std::size_t i) {
        for (std::size_t j = 0; j < cells[i].size(); ++j) {
            const adf::BoundaryCell& cell = cells[i][j];
            SplitMix rng{seed * 0x2545f4914f6cdd1dull + firstCell[i] + j};
            const float size = float(cell.size);
            const glm::vec3 cellOrigin = origin + glm::vec3(cell.origin) * h;
            const float cellMetres = size * h;
            const std::size_t end = firstPoint(i, j + 1);
            for (std::size_t k = firstPoint(i, j); k < end; ++k) {
                glm::vec3 f(rng.unit(), rng.unit(), rng.unit());
                const adf::Sample s = adf::trilinear(cell.corners, f);
                // One projection step along the gradient, in cell units: f -= d g / |g|^2,
                // with d in metres and g in metres per cell (one division, none per axis).
                const glm::vec3 g = s.gradient;
                const float g2 = glm::dot(g, g);
                if (g2 > 1e-12f * cellMetres * cellMetres) f -= (s.distance / g2) * g;
                f = glm::clamp(f, glm::vec3(-0.5f), glm::vec3(1.5f));
                const glm::vec3 n = adf::trilinear(cell.corners, f).gradient;
                const float n2 = glm::dot(n, n);
                out.positions[k] = cellOrigin + f * cellMetres;
                out.normals[k] = n2 > 0.0f ? n * (1.0f / std::sqrt(n2)) : glm::vec3(0.0f, 0.0f, 1.0f);
            }
        }
    });
    if (adf.colours()) colourPoints(*adf.colours(), out.positions, out.colours, pool);
    return out;
}

}  // namespace kizamu::mesh
