// SPDX-License-Identifier: Apache-2.0
/// @file surface_nets_assembly.cpp
/// @brief Tiles -> MeshBuffers: SurfaceMesher::mesh().
///
/// Takes in: every tile's live vertices (placed), split vertices and live crossings. Produces:
/// the mesh's positions (world, m), normals and triangles. Numbering: live vertices in slot
/// order, then split vertices, tile by tile in key order; then the centres of fanned polygons;
/// triangles in crossing order, tile by tile. Each tile counts its share, then writes it at its
/// offsets: the same buffers as a serial pass, whatever the threads.
/// Complexity: O(vertices + crossings); the few polygons with split vertices are found through
/// the multi-crossing faces, not by reading every crossing.
/// Threading: each tile's share on its home thread (the thread that built it, whose cache holds
/// its records), three passes separated by barriers.
#include "mesh/surface_nets.h"

#include "mesh/mesh_colours.h"
#include "mesh/surface_nets_internal.h"
#include "util/thread_pool.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <stdexcept>

namespace kizamu::mesh {

using namespace detail;

namespace {

template <class T>
void sortUnique(std::vector<T>& v) {
    std::sort(v.begin(), v.end());
    v.erase(std::unique(v.begin(), v.end()), v.end());
}

/// Triangles a crossing's dual polygon becomes, and whether it is fanned around a new centre
/// vertex (a split vertex on one of its sides).
struct PolygonShape {
    uint32_t triangles;
    bool fan;
};
inline PolygonShape polygonShape(const Crossing& x) {
    uint32_t corners = 0;
    bool split = false;
    for (int q = 0; q < 4; ++q) {
        corners += x.ringCell[q] != x.ringCell[(q + 3) % 4];
        if (x.split[q] != Crossing::kNoSplit && x.ringCell[q] != x.ringCell[(q + 1) % 4]) {
            ++corners;
            split = true;
        }
    }
    if (split) return {corners, true};
    return {plainTriangles(x), false};
}

}  // namespace

MeshBuffers SurfaceMesher::mesh() const {
    MeshBuffers m;
    if (!mAdf) return m;
    std::vector<TileMesh*> order;
    order.reserve(mTiles.size());
    for (const auto& [key, tm] : mTiles) order.push_back(tm.get());
    std::sort(order.begin(), order.end(), [](const TileMesh* l, const TileMesh* r) { return l->key < r->key; });
    // Output numbering: live vertices in slot order, then split vertices, tile by tile; then
    // the centres of fanned polygons and the triangles, in crossing order, tile by tile. Each
    // tile counts its share, then writes it at its offsets: the same buffers as a serial pass.
    struct Share {
        uint32_t vertices = 0, triangles = 0, centres = 0;
        uint32_t centreOffset = 0;
        std::size_t triangleOffset = 0;
    };
    std::vector<Share> share(order.size());
    // Each tile's share on the thread that built it (build()).
    auto homeOf = [&](std::size_t t) { return order[t]->home; };
    util::parallelForHomes(mPool, order.size(), homeOf, [&](std::size_t t) {
        TileMesh& tm = *order[t];
        tm.share = uint32_t(t);
        Share& sh = share[t];
        sh.triangles = tm.plainTriangles;
        if (tm.freeVertices.empty()) {  // every slot live (a build): numbers are slots
            tm.outNumber.clear();
            tm.denseEnd = uint32_t(tm.vertices.size());
            sh.vertices = uint32_t(tm.vertices.size() + tm.splits.size());
            return;
        }
        tm.denseEnd = 0;
        tm.outNumber.assign(tm.vertices.size() + tm.splits.size(), UINT32_MAX);
        uint32_t next = 0;
        for (uint32_t i = 0; i < tm.vertices.size(); ++i)
            if (tm.vertices[i].alive) tm.outNumber[i] = next++;
        for (uint32_t i = 0; i < tm.splits.size(); ++i) tm.outNumber[tm.vertices.size() + i] = next++;
        sh.vertices = next;
    });
    // Polygons with split vertices (on the multi-crossing faces only) are fans: their tiles'
    // shares grow by the difference.
    std::vector<const Crossing*> split;
    for (const TileMesh* tm : order)
        for (const MultiFace& mf : tm->multiFaces)
            for (const auto& [e, l] : mf.segments) split.insert(split.end(), {e.x, l.x});
    sortUnique(split);
    for (const Crossing* x : split) {
        if (!x->alive) continue;  // as the triangles below
        const PolygonShape ps = polygonShape(*x);
        if (!ps.fan) continue;
        Share& sh = share[mTiles.at(ownerKey(*mAdf, x->ringCell[x->emitter]))->share];
        sh.triangles += ps.triangles - plainTriangles(*x);
        ++sh.centres;
    }
    std::size_t vertices = 0, triangles = 0;
    for (std::size_t t = 0; t < order.size(); ++t) {
        order[t]->offset = uint32_t(vertices);
        vertices += share[t].vertices;
    }
    std::size_t centres = vertices;
    for (Share& sh : share) {
        sh.centreOffset = uint32_t(centres);
        sh.triangleOffset = triangles;
        centres += sh.centres;
        triangles += sh.triangles;
    }
    m.positions.resize(centres);
    m.normals.resize(centres);
    m.indices.resize(3 * triangles);
    const glm::dvec3 origin = mAdf->domain().originWorld;
    const double h = mAdf->domain().finestCellSize();
    auto world = [&](const glm::vec3& lattice) { return glm::vec3(origin + glm::dvec3(lattice) * h); };
    util::parallelForHomes(mPool, order.size(), homeOf, [&](std::size_t t) {
        const TileMesh& tm = *order[t];
        uint32_t out = tm.offset;
        const bool allLive = tm.freeVertices.empty();  // (a build's: no record to look at)
        for (uint32_t i = 0; i < tm.placed.size(); ++i) {
            if (!allLive && !tm.vertices[i].alive) continue;
            m.positions[out] = world(tm.placed[i].position);
            m.normals[out++] = tm.placed[i].normal;
        }
        for (const SplitVertex& sv : tm.splits) {
            const Placed& a = sv.a.tile->placed[sv.a.index];
            const Placed& b = sv.b.tile->placed[sv.b.index];
            m.positions[out] = world(0.5f * (a.position + b.position));
            const glm::vec3 n = a.normal + b.normal;
            m.normals[out++] = glm::dot(n, n) > 0.0f ? glm::normalize(n) : a.normal;
        }
    });
    auto index = [](const VertexRef& r) {
        if (!r.tile) throw std::logic_error("surface nets: a crossing has no vertex");
        const TileMesh& t = *r.tile;
        if (r.index < t.denseEnd) return t.offset + r.index;
        const std::vector<uint32_t>& num = t.outNumber;
        if (r.index >= num.size() || num[r.index] == UINT32_MAX)
            throw std::logic_error("surface nets: a crossing refers to a released vertex");
        return t.offset + num[r.index];
    };
    auto splitIndex = [&](const Crossing& x, int q) {
        const TileMesh& owner = *mTiles.at(ownerKey(*mAdf, x.faceCell(q)));
        const std::size_t slot = owner.vertices.size() + x.split[q];
        if (owner.outNumber.empty() && x.split[q] < owner.splits.size()) return owner.offset + uint32_t(slot);
        return owner.offset + owner.outNumber.at(slot);
    };
    util::parallelForHomes(mPool, order.size(), homeOf, [&](std::size_t t) {
        const TileMesh& tm = *order[t];
        uint32_t* tri = m.indices.data() + 3 * share[t].triangleOffset;
        uint32_t* const triEnd = tri + 3 * std::size_t(share[t].triangles);
        uint32_t centre = share[t].centreOffset;
        uint32_t polygon[8];
        for (uint32_t xi = 0; xi < tm.crossings.size(); ++xi) {
            const Crossing& x = tm.crossings[xi];
            if (!x.alive) continue;
            auto emit = [&](uint32_t a, uint32_t b, uint32_t c) {
                if (tri == triEnd) throw std::logic_error("surface nets: a tile's polygons exceed its count");
                tri[0] = a;
                tri[1] = x.startInside ? b : c;
                tri[2] = x.startInside ? c : b;
                tri += 3;
            };
            // A quad (its four ring cells' vertices in ring order) is split along the diagonal
            // through the smallest leaf (the emitter), which no other polygon can share.
            auto quad = [&](const uint32_t* v) {
                const int e = x.emitter;
                emit(v[e], v[(e + 1) % 4], v[(e + 2) % 4]);
                emit(v[e], v[(e + 2) % 4], v[(e + 3) % 4]);
            };
            // Nearly always four leaves and no split vertex: straight to the quad.
            const uint64_t* ring = x.ringCell;
            if (ring[0] != ring[1] && ring[1] != ring[2] && ring[2] != ring[3] && ring[3] != ring[0] &&
                (x.split[0] & x.split[1] & x.split[2] & x.split[3]) == Crossing::kNoSplit) {
                const uint32_t v[4] = {index(x.ringVertex[0]), index(x.ringVertex[1]), index(x.ringVertex[2]),
                                       index(x.ringVertex[3])};
                quad(v);
                continue;
            }
            // The dual polygon in ring order, with any split vertices on its sides.
            uint32_t n = 0;
            bool fan = false;
            for (int q = 0; q < 4; ++q) {
                if (x.ringCell[q] != x.ringCell[(q + 3) % 4]) polygon[n++] = index(x.ringVertex[q]);
                if (x.split[q] != Crossing::kNoSplit && x.ringCell[q] != x.ringCell[(q + 1) % 4]) {
                    polygon[n++] = splitIndex(x, q);
                    fan = true;
                }
            }
            if (fan) {
                // Fan around a new centre: its edges cannot coincide with any other.
                if (centre == share[t].centreOffset + share[t].centres)
                    throw std::logic_error("surface nets: a tile's fans exceed its count");
                glm::vec3 c(0.0f), nsum(0.0f);
                for (uint32_t i = 0; i < n; ++i) {
                    c += m.positions[polygon[i]];
                    nsum += m.normals[polygon[i]];
                }
                m.positions[centre] = c / float(n);
                m.normals[centre] = glm::dot(nsum, nsum) > 0.0f ? glm::normalize(nsum) : glm::vec3(0.0f, 0.0f, 1.0f);
                for (uint32_t i = 0; i < n; ++i) emit(centre, polygon[i], polygon[(i + 1) % n]);
                ++centre;
            } else if (n == 3) {
                emit(polygon[0], polygon[1], polygon[2]);
            } else {
                quad(polygon);  // four ring cells
            }
        }
        if (tri != triEnd || centre != share[t].centreOffset + share[t].centres)
            throw std::logic_error("surface nets: a tile's polygons differ from its count");
    });
    // Paint: one colour per vertex from its position, so an incremental mesh gets the same
    // colours as a full one; nothing at all (not even a branch per vertex) when unpainted.
    if (mAdf->colours()) colourPoints(*mAdf->colours(), m.positions, m.colours, mPool);
    return m;
}

}  // namespace kizamu::mesh
