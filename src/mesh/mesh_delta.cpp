// SPDX-License-Identifier: Apache-2.0
/// @file mesh_delta.cpp
/// @brief Tiles -> shares (SurfaceMesher::takeDelta, fullDelta), coalescing deltas, and the
/// consumer's mirror (MeshMirror::apply, flatten).
///
/// A share is read from a tile exactly as the assembly (surface_nets_assembly.cpp) reads it:
/// live vertex slots, split vertices, the triangles of its live crossings in slot order (quads
/// split along the diagonal through the emitter, polygons with a split vertex fanned); but each
/// corner as an address (mesh_delta.h) instead of a number in one buffer. The mirror's flatten
/// repeats the assembly's float operations (world transform, split mid-points, fan centres in
/// corner order), so its mesh equals mesh()'s bit for bit up to order.
/// Threading: the shares of a delta in parallel over tiles on the mesher's pool (each task
/// writes one share); the rest on the calling thread.
#include "mesh/mesh_delta.h"

#include "mesh/surface_nets.h"
#include "mesh/surface_nets_internal.h"
#include "util/thread_pool.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <iterator>
#include <stdexcept>

namespace kizamu::mesh {

using namespace detail;

namespace {

VertexAddress addressOf(const VertexRef& r) {
    if (!r.tile) throw std::logic_error("mesh delta: a crossing has no vertex");
    return {r.tile->key, r.index};
}

/// Tile `tm`'s share (see the file comment). Complexity: O(its vertex slots + crossings).
void shareOf(const adf::Adf& adf, const TileMesh& tm, MeshTileShare& out) {
    out.key = tm.key;
    const std::size_t slots = tm.vertices.size();
    out.positions.resize(slots);
    out.normals.resize(slots);
    out.alive.resize(slots);
    for (std::size_t i = 0; i < slots; ++i) {
        const bool live = tm.vertices[i].alive;
        out.alive[i] = live;
        out.positions[i] = live ? tm.placed[i].position : glm::vec3(0.0f);
        out.normals[i] = live ? tm.placed[i].normal : glm::vec3(0.0f);
    }
    out.splits.clear();
    for (const SplitVertex& sv : tm.splits) out.splits.push_back({addressOf(sv.a), addressOf(sv.b)});
    out.triangles.clear();
    out.triangles.reserve(tm.plainTriangles);
    out.fans.clear();
    for (uint32_t xi = 0; xi < tm.crossings.size(); ++xi) {
        const Crossing& x = tm.crossings[xi];
        if (!x.alive) continue;
        auto emit = [&](const VertexAddress& a, const VertexAddress& b, const VertexAddress& c) {
            out.triangles.push_back({a, x.startInside ? b : c, x.startInside ? c : b});
        };
        VertexAddress polygon[8];
        uint32_t n = 0;
        bool fan = false;
        for (int q = 0; q < 4; ++q) {
            if (x.ringCell[q] != x.ringCell[(q + 3) % 4]) polygon[n++] = addressOf(x.ringVertex[q]);
            if (x.split[q] != Crossing::kNoSplit && x.ringCell[q] != x.ringCell[(q + 1) % 4]) {
                polygon[n++] = {ownerKey(adf, x.faceCell(q)), VertexAddress::kSplitSlot + x.split[q]};
                fan = true;
            }
        }
        if (fan) {
            MeshFan& f = out.fans.emplace_back();
            std::copy(polygon, polygon + n, f.corners.begin());
            f.count = uint8_t(n);
            f.flip = !x.startInside;
        } else if (n == 3) {
            emit(polygon[0], polygon[1], polygon[2]);
        } else {  // a quad, split along the diagonal through the emitter (as the assembly)
            const int e = x.emitter;
            emit(polygon[e], polygon[(e + 1) % 4], polygon[(e + 2) % 4]);
            emit(polygon[e], polygon[(e + 2) % 4], polygon[(e + 3) % 4]);
        }
    }
}

}  // namespace

MeshDelta SurfaceMesher::deltaOf(std::vector<uint64_t> keys, bool reset) {
    MeshDelta d;
    d.base = mTakenGeneration;
    d.generation = mGeneration;
    d.reset = reset;
    mTakenGeneration = mGeneration;
    mResetPending = false;
    if (!mAdf) return d;
    d.originWorld = mAdf->domain().originWorld;
    d.cellSize = mAdf->domain().finestCellSize();
    sortUnique(keys);
    std::vector<const TileMesh*> present;
    present.reserve(keys.size());
    for (uint64_t k : keys) {
        auto it = mTiles.find(k);
        if (it == mTiles.end())
            d.removed.push_back(k);
        else
            present.push_back(it->second.get());
    }
    d.tiles.resize(present.size());
    util::parallelFor(mPool, present.size(), [&](std::size_t i) { shareOf(*mAdf, *present[i], d.tiles[i]); });
    return d;
}

MeshDelta SurfaceMesher::takeDelta() {
    if (mResetPending) return fullDelta();
    std::vector<uint64_t> keys;
    keys.swap(mChangedTiles);
    MeshDelta d = deltaOf(std::move(keys), false);
    return d;
}

MeshDelta SurfaceMesher::fullDelta() {
    mChangedTiles.clear();
    std::vector<uint64_t> keys;
    keys.reserve(mTiles.size());
    for (const auto& [key, tm] : mTiles) keys.push_back(key);
    return deltaOf(std::move(keys), true);
}

void coalesce(MeshDelta& older, MeshDelta&& newer) {
    const int64_t newestSampleNs = std::max(older.newestSampleNs, newer.newestSampleNs);
    if (newer.reset) {
        older = std::move(newer);
        older.newestSampleNs = newestSampleNs;
        return;
    }
    if (newer.base != older.generation) throw std::invalid_argument("mesh delta: coalescing deltas that do not follow");
    // Both lists are by key: merge them, the newer share winning, a newer removal dropping an
    // older share. A tile removed and then made again is a share, not a removal; a reset delta
    // keeps no removal (its mirror starts empty).
    std::vector<uint64_t> newerKeys;
    newerKeys.reserve(newer.tiles.size());
    for (const MeshTileShare& s : newer.tiles) newerKeys.push_back(s.key);
    auto removedByNewer = [&](uint64_t k) { return std::binary_search(newer.removed.begin(), newer.removed.end(), k); };
    std::vector<MeshTileShare> tiles;
    tiles.reserve(older.tiles.size() + newer.tiles.size());
    std::size_t o = 0;
    for (MeshTileShare& s : newer.tiles) {
        for (; o < older.tiles.size() && older.tiles[o].key < s.key; ++o)
            if (!removedByNewer(older.tiles[o].key)) tiles.push_back(std::move(older.tiles[o]));
        if (o < older.tiles.size() && older.tiles[o].key == s.key) ++o;
        tiles.push_back(std::move(s));
    }
    for (; o < older.tiles.size(); ++o)
        if (!removedByNewer(older.tiles[o].key)) tiles.push_back(std::move(older.tiles[o]));
    older.tiles = std::move(tiles);
    if (!older.reset) {
        std::vector<uint64_t> removed;
        std::set_union(older.removed.begin(), older.removed.end(), newer.removed.begin(), newer.removed.end(),
                       std::back_inserter(removed));
        std::erase_if(removed, [&](uint64_t k) { return std::binary_search(newerKeys.begin(), newerKeys.end(), k); });
        older.removed = std::move(removed);
    }
    older.generation = newer.generation;
    older.originWorld = newer.originWorld;
    older.cellSize = newer.cellSize;
    older.newestSampleNs = newestSampleNs;
}

bool MeshMirror::apply(MeshDelta&& delta) {
    if (!delta.reset && (!mSynced || delta.base != mGeneration)) return false;
    if (delta.reset) {
        mTiles.clear();
        mSynced = true;
    }
    for (uint64_t k : delta.removed) mTiles.erase(k);
    for (MeshTileShare& s : delta.tiles) {
        const uint64_t key = s.key;
        mTiles[key] = std::move(s);
    }
    mGeneration = delta.generation;
    mNewestSampleNs = std::max(mNewestSampleNs, delta.newestSampleNs);
    mOriginWorld = delta.originWorld;
    mCellSize = delta.cellSize;
    return true;
}

const MeshTileShare* MeshMirror::tile(uint64_t key) const {
    auto it = mTiles.find(key);
    return it == mTiles.end() ? nullptr : &it->second;
}

MeshBuffers MeshMirror::flatten() const {
    MeshBuffers m;
    // Tiles by key; per tile its first number and each slot's number (splits after the slots).
    struct Numbered {
        const MeshTileShare* share;
        uint32_t offset;
        std::vector<uint32_t> number;  // per slot (UINT32_MAX where free), then per split
    };
    std::vector<Numbered> order;
    order.reserve(mTiles.size());
    for (const auto& [key, s] : mTiles) order.push_back({&s, 0, {}});
    std::sort(order.begin(), order.end(), [](const Numbered& l, const Numbered& r) { return l.share->key < r.share->key; });
    std::unordered_map<uint64_t, std::size_t> position;
    position.reserve(order.size());
    std::size_t vertices = 0, triangles = 0, fans = 0;
    for (std::size_t t = 0; t < order.size(); ++t) {
        Numbered& nt = order[t];
        const MeshTileShare& s = *nt.share;
        position.emplace(s.key, t);
        nt.offset = uint32_t(vertices);
        nt.number.assign(s.alive.size() + s.splits.size(), UINT32_MAX);
        uint32_t next = 0;
        for (std::size_t i = 0; i < s.alive.size(); ++i)
            if (s.alive[i]) nt.number[i] = next++;
        for (std::size_t i = 0; i < s.splits.size(); ++i) nt.number[s.alive.size() + i] = next++;
        vertices += next;
        triangles += s.triangles.size();
        for (const MeshFan& f : s.fans) triangles += f.count;
        fans += s.fans.size();
    }
    auto tileOf = [&](const VertexAddress& a) -> const Numbered& {
        auto it = position.find(a.tile);
        if (it == position.end()) throw std::logic_error("mesh mirror: an address names a tile the mirror lacks");
        return order[it->second];
    };
    auto numberOf = [&](const VertexAddress& a) {
        const Numbered& nt = tileOf(a);
        const std::size_t i = a.isSplit() ? nt.share->alive.size() + (a.slot - VertexAddress::kSplitSlot) : a.slot;
        if (i >= nt.number.size() || nt.number[i] == UINT32_MAX)
            throw std::logic_error("mesh mirror: an address names a free or missing slot");
        return nt.offset + nt.number[i];
    };
    m.positions.resize(vertices + fans);
    m.normals.resize(vertices + fans);
    m.indices.resize(3 * triangles);
    const glm::dvec3 origin = mOriginWorld;
    const double h = mCellSize;
    auto world = [&](const glm::vec3& lattice) { return glm::vec3(origin + glm::dvec3(lattice) * h); };
    // Vertices, then split vertices (their ends are plain vertices, read from their shares).
    for (const Numbered& nt : order) {
        const MeshTileShare& s = *nt.share;
        uint32_t out = nt.offset;
        for (std::size_t i = 0; i < s.alive.size(); ++i) {
            if (!s.alive[i]) continue;
            m.positions[out] = world(s.positions[i]);
            m.normals[out++] = s.normals[i];
        }
        for (const auto& [ea, eb] : s.splits) {
            auto slotOf = [&](const VertexAddress& e) -> std::size_t {
                const Numbered& owner = tileOf(e);
                if (e.isSplit() || e.slot >= owner.share->alive.size() || !owner.share->alive[e.slot])
                    throw std::logic_error("mesh mirror: a split vertex's end is no live vertex");
                return e.slot;
            };
            const MeshTileShare& sa = *tileOf(ea).share;
            const MeshTileShare& sb = *tileOf(eb).share;
            const glm::vec3 pa = sa.positions[slotOf(ea)], pb = sb.positions[slotOf(eb)];
            const glm::vec3 na = sa.normals[ea.slot], nb = sb.normals[eb.slot];
            m.positions[out] = world(0.5f * (pa + pb));
            const glm::vec3 n = na + nb;
            m.normals[out++] = glm::dot(n, n) > 0.0f ? glm::normalize(n) : na;
        }
    }
    // Triangles, then fans around their centres (numbered after every vertex).
    uint32_t* tri = m.indices.data();
    uint32_t centre = uint32_t(vertices);
    for (const Numbered& nt : order) {
        const MeshTileShare& s = *nt.share;
        for (const auto& t : s.triangles) {
            for (int i = 0; i < 3; ++i) tri[i] = numberOf(t[std::size_t(i)]);
            tri += 3;
        }
        for (const MeshFan& f : s.fans) {
            uint32_t polygon[8];
            glm::vec3 c(0.0f), nsum(0.0f);
            for (uint32_t i = 0; i < f.count; ++i) {
                polygon[i] = numberOf(f.corners[i]);
                c += m.positions[polygon[i]];
                nsum += m.normals[polygon[i]];
            }
            m.positions[centre] = c / float(f.count);
            m.normals[centre] = glm::dot(nsum, nsum) > 0.0f ? glm::normalize(nsum) : glm::vec3(0.0f, 0.0f, 1.0f);
            for (uint32_t i = 0; i < f.count; ++i) {
                const uint32_t a = polygon[i], b = polygon[(i + 1) % f.count];
                tri[0] = centre;
                tri[1] = f.flip ? b : a;
                tri[2] = f.flip ? a : b;
                tri += 3;
            }
            ++centre;
        }
    }
    return m;
}

}  // namespace kizamu::mesh
