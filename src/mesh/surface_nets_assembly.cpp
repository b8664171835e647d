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
#include "util/default_init_allocator.h"
#include "util/thread_pool.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <span>
#include <stdexcept>

namespace kizamu::mesh {

using namespace detail;

namespace {

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

/// One tile's share of the assembled mesh: owned by one mesh() call (the tiles are only read).
struct TileShare {
    uint32_t vertices = 0, triangles = 0, centres = 0;
    uint32_t offset = 0;  ///< its first vertex in the mesh
    uint32_t centreOffset = 0;
    std::size_t triangleOffset = 0;
    /// Slots below this are numbered by slot (`number` empty): the fast path.
    uint32_t denseEnd = 0;
    /// Vertex slot (then split) -> number within the share, a range of Assembly::numbers;
    /// empty where no slot is released (the number is the slot).
    std::span<uint32_t> number;
};

/// The state of one mesh() call: the tiles in key order, their shares, and the way from a
/// tile to its share.
struct Assembly {
    std::vector<const TileMesh*> order;  ///< the tiles, by key
    std::vector<TileShare> shares;       ///< per entry of `order`
    FlatMap64 position;                  ///< tile key -> its index in `order`
    /// Every share's `number`, one block owned (and freed) by the mesh() call's thread: after
    /// updates many tiles have released slots, and a vector each, allocated on the home threads,
    /// would be freed across threads.
    std::vector<uint32_t, util::DefaultInitAllocator<uint32_t>> numbers;

    std::size_t indexOf(uint64_t tileKey) const {
        const uint32_t* at = position.find(tileKey);
        if (!at) throw std::logic_error("surface nets: a crossing's cell has no tile");
        return *at;
    }
    /// Gives each tile with a released slot its range of `numbers` (serial, before
    /// numberVertices).
    void reserveNumbers() {
        std::size_t total = 0;
        for (const TileMesh* tm : order)
            if (!tm->freeVertices.empty()) total += tm->vertices.size() + tm->splits.size();
        numbers.resize(total);
        std::size_t at = 0;
        for (std::size_t t = 0; t < order.size(); ++t) {
            const TileMesh& tm = *order[t];
            if (tm.freeVertices.empty()) continue;
            const std::size_t n = tm.vertices.size() + tm.splits.size();
            shares[t].number = std::span<uint32_t>(numbers.data() + at, n);
            at += n;
        }
    }
    /// Numbers tile t's vertices and counts its share of them and of the plain triangles.
    void numberVertices(std::size_t t) {
        const TileMesh& tm = *order[t];
        TileShare& sh = shares[t];
        sh.triangles = tm.plainTriangles;
        if (tm.freeVertices.empty()) {  // every slot live (a build): numbers are slots
            sh.denseEnd = uint32_t(tm.vertices.size());
            sh.vertices = uint32_t(tm.vertices.size() + tm.splits.size());
            return;
        }
        std::fill(sh.number.begin(), sh.number.end(), UINT32_MAX);
        uint32_t next = 0;
        for (uint32_t i = 0; i < tm.vertices.size(); ++i)
            if (tm.vertices[i].alive) sh.number[i] = next++;
        for (uint32_t i = 0; i < tm.splits.size(); ++i) sh.number[tm.vertices.size() + i] = next++;
        sh.vertices = next;
    }
    /// Polygons with split vertices (on the multi-crossing faces only) are fans: their tiles'
    /// shares grow by the difference. Then every share's offsets; returns the vertices (centres
    /// included) and triangles of the mesh.
    std::pair<std::size_t, std::size_t> placeShares(const adf::Adf& adf) {
        std::vector<const Crossing*> split;
        for (const TileMesh* tm : order)
            for (const MultiFace& mf : tm->multiFaces)
                for (const auto& [e, l] : mf.segments) split.insert(split.end(), {e.x, l.x});
        sortUnique(split);
        for (const Crossing* x : split) {
            if (!x->alive) continue;  // as the triangles
            const PolygonShape ps = polygonShape(*x);
            if (!ps.fan) continue;
            TileShare& sh = shares[indexOf(ownerKey(adf, x->ringCell[x->emitter]))];
            sh.triangles += ps.triangles - plainTriangles(*x);
            ++sh.centres;
        }
        std::size_t vertices = 0, triangles = 0;
        for (TileShare& sh : shares) {
            sh.offset = uint32_t(vertices);
            vertices += sh.vertices;
        }
        std::size_t centres = vertices;
        for (TileShare& sh : shares) {
            sh.centreOffset = uint32_t(centres);
            sh.triangleOffset = triangles;
            centres += sh.centres;
            triangles += sh.triangles;
        }
        return {centres, triangles};
    }
    /// The mesh's number of vertex `r`, whose tile's share is `sh`.
    static uint32_t vertexNumber(const VertexRef& r, const TileShare& sh) {
        if (r.index < sh.denseEnd) return sh.offset + r.index;
        if (r.index >= sh.number.size() || sh.number[r.index] == UINT32_MAX)
            throw std::logic_error("surface nets: a crossing refers to a released vertex");
        return sh.offset + sh.number[r.index];
    }
    /// The mesh's number of the split vertex on the face between ring cells q and q + 1 of `x`.
    uint32_t splitNumber(const adf::Adf& adf, const Crossing& x, int q) const {
        const std::size_t t = indexOf(ownerKey(adf, x.faceCell(q)));
        const TileMesh& owner = *order[t];
        const TileShare& sh = shares[t];
        const std::size_t slot = owner.vertices.size() + x.split[q];
        if (sh.number.empty() && x.split[q] < owner.splits.size()) return sh.offset + uint32_t(slot);
        if (slot >= sh.number.size())
            throw std::logic_error("surface nets: a split vertex out of its tile's range");
        return sh.offset + sh.number[slot];
    }
    void writeVertices(std::size_t t, const adf::Domain& domain, MeshBuffers& m) const;
    void writeTriangles(std::size_t t, const adf::Adf& adf, MeshBuffers& m) const;
};

void Assembly::writeVertices(std::size_t t, const adf::Domain& domain, MeshBuffers& m) const {
    const TileMesh& tm = *order[t];
    const glm::dvec3 origin = domain.originWorld;
    const double h = domain.finestCellSize();
    auto world = [&](const glm::vec3& lattice) { return glm::vec3(origin + glm::dvec3(lattice) * h); };
    uint32_t out = shares[t].offset;
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
}

void Assembly::writeTriangles(std::size_t t, const adf::Adf& adf, MeshBuffers& m) const {
    const TileMesh& tm = *order[t];
    const TileShare& own = shares[t];
    // The share of a vertex's tile: nearly always this tile's, else mostly the last other one.
    // Their offsets in locals, so they stay in registers (a store to the indices could change
    // a share's fields, as far as the compiler knows).
    const uint32_t ownOffset = own.offset, ownDenseEnd = own.denseEnd;
    const TileMesh* otherTile = &tm;  // (never asked for: a ref to this tile is answered first)
    const TileShare* other = &own;
    uint32_t otherOffset = 0, otherDenseEnd = 0;
    auto index = [&](const VertexRef& r) {
        if (r.tile == &tm) return r.index < ownDenseEnd ? ownOffset + r.index : vertexNumber(r, own);
        if (r.tile != otherTile) {
            if (!r.tile) throw std::logic_error("surface nets: a crossing has no vertex");
            otherTile = r.tile;
            other = &shares[indexOf(r.tile->key)];
            otherOffset = other->offset;
            otherDenseEnd = other->denseEnd;
        }
        return r.index < otherDenseEnd ? otherOffset + r.index : vertexNumber(r, *other);
    };
    uint32_t* tri = m.indices.data() + 3 * own.triangleOffset;
    uint32_t* const triEnd = tri + 3 * std::size_t(own.triangles);
    uint32_t centre = own.centreOffset;
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
                polygon[n++] = splitNumber(adf, x, q);
                fan = true;
            }
        }
        if (fan) {
            // Fan around a new centre: its edges cannot coincide with any other.
            if (centre == own.centreOffset + own.centres)
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
    if (tri != triEnd || centre != own.centreOffset + own.centres)
        throw std::logic_error("surface nets: a tile's polygons differ from its count");
}

}  // namespace

MeshBuffers SurfaceMesher::mesh() const {
    MeshBuffers m;
    if (!mAdf) return m;
    Assembly as;
    as.order.reserve(mTiles.size());
    for (const auto& [key, tm] : mTiles) as.order.push_back(tm.get());
    std::sort(as.order.begin(), as.order.end(), [](const TileMesh* l, const TileMesh* r) { return l->key < r->key; });
    as.shares.resize(as.order.size());
    as.position.reserve(as.order.size());
    for (uint32_t t = 0; t < as.order.size(); ++t) as.position.assign(as.order[t]->key, t);
    // Each tile's share on the thread that built it (build()), in three passes: number and
    // count, (serially) place the shares, then write vertices and triangles.
    auto homeOf = [&](std::size_t t) { return as.order[t]->home; };
    as.reserveNumbers();
    util::parallelForHomes(mPool, as.order.size(), homeOf, [&](std::size_t t) { as.numberVertices(t); });
    const auto [vertices, triangles] = as.placeShares(*mAdf);
    m.positions.resize(vertices);
    m.normals.resize(vertices);
    m.indices.resize(3 * triangles);
    util::parallelForHomes(mPool, as.order.size(), homeOf,
                           [&](std::size_t t) { as.writeVertices(t, mAdf->domain(), m); });
    util::parallelForHomes(mPool, as.order.size(), homeOf, [&](std::size_t t) { as.writeTriangles(t, *mAdf, m); });
    // Paint: one colour per vertex from its position, so an incremental mesh gets the same
    // colours as a full one; nothing at all (not even a branch per vertex) when unpainted.
    if (mAdf->colours()) colourPoints(*mAdf->colours(), m.positions, m.colours, mPool);
    return m;
}

}  // namespace kizamu::mesh
