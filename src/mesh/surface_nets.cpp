// SPDX-License-Identifier: Apache-2.0
/// @file surface_nets.cpp
/// @brief SurfaceMesher::build and the scheduling of its phases: which thread (home) meshes
/// which tile, and the tiles' lifetimes.
///
/// A build runs three phases over the tiles, each a parallel loop with a barrier after it:
/// crossings (surface_nets_crossings.cpp), vertices (surface_nets_vertices.cpp, cycles in
/// surface_nets_cycles.cpp), relaxation. Takes in: a snapshot. Produces: one TileMesh per tile
/// holding a crossing or a vertex. The update (surface_nets_update.cpp, surface_nets_remesh.cpp) and the assembly
/// (surface_nets_assembly.cpp) reuse these tiles.
/// Complexity: O(boundary leaves) for a build. Threading: every phase runs a tile on its home
/// thread (util::parallelForHomes); the homes are runs of tiles in key order of about equal
/// weight (docs/decisions/0012-mesher-homes-and-place-table.md).
#include "mesh/surface_nets.h"

#include "mesh/surface_nets_internal.h"
#include "util/thread_pool.h"

#include <algorithm>
#include <chrono>
#include <functional>
#include <numeric>
#include <stdexcept>

namespace kizamu::mesh {

using adf::Adf;
using adf::Tile;
using namespace detail;

namespace detail {

void neighbourKeys(const Adf& adf, glm::uvec3 lo, glm::uvec3 end, std::vector<uint64_t>& out) {
    const Tile* last = nullptr;
    forSlotsAround(lo, end, adf.domain().slotsPerAxis(), [&](glm::uvec3 slot) {
        const Tile* t = adf.tileAtSlot(slot);
        if (t == last) return;
        last = t;
        out.push_back(packLattice(t->latticeOrigin()));
    });
}

void setTile(const Adf& adf, const Tile& t, TileMesh& tm) {
    const uint32_t shift = uint32_t(adf.domain().maxLevel - adf.domain().tileLevel());
    tm.tile = &t;
    tm.key = packLattice(t.latticeOrigin());
    tm.slotMin = t.latticeOrigin() >> shift;
    tm.slotEnd = tm.slotMin + glm::uvec3(1u << uint32_t(adf.domain().tileLevel() - t.level()));
    tm.outside = outsideOf(t, adf.domain().maxLevel);
}

}  // namespace detail

namespace {

/// A build's tiles by slot where the domain has at most 2^18 slots (level 12 with 6-level
/// tiles), else by key through a flat map: what the vertex phase finds each tile's neighbours
/// through (docs/decisions/0012-mesher-homes-and-place-table.md).
struct TileIndex {
    static constexpr uint32_t kMaxSlots = 1u << 18;
    std::vector<TileBuild>& tiles;   ///< the build's tiles (not resized while indexed)
    std::vector<TileBuild*> bySlot;  ///< slot (x fastest) -> its tile, or null; or empty
    uint32_t slotsPerAxis = 0;
    FlatMap64 position;  ///< key -> index in `tiles`, where bySlot is empty

    std::size_t at(glm::uvec3 slot) const { return (std::size_t(slot.z) * slotsPerAxis + slot.y) * slotsPerAxis + slot.x; }
    void build(const Adf& adf) {
        slotsPerAxis = adf.domain().slotsPerAxis();
        if (uint64_t(slotsPerAxis) * slotsPerAxis * slotsPerAxis <= kMaxSlots) {
            bySlot.assign(std::size_t(slotsPerAxis) * slotsPerAxis * slotsPerAxis, nullptr);
            for (TileBuild& tb : tiles) {
                const TileMesh* tm = tb.mesh;
                for (uint32_t z = tm->slotMin.z; z < tm->slotEnd.z; ++z)
                    for (uint32_t y = tm->slotMin.y; y < tm->slotEnd.y; ++y)
                        for (uint32_t x = tm->slotMin.x; x < tm->slotEnd.x; ++x) bySlot[at({x, y, z})] = &tb;
            }
            return;
        }
        position.reserve(tiles.size());
        for (uint32_t i = 0; i < tiles.size(); ++i) position.assign(tiles[i].mesh->key, i);
    }
    /// The tiles whose slots touch (closed) `tm`'s, `tm` included, each once.
    void neighbours(const Adf& adf, const TileMesh& tm, std::vector<TileBuild*>& out, std::vector<uint64_t>& keys) const {
        out.clear();
        if (bySlot.empty()) {
            keys.clear();
            neighbourKeys(adf, tm.slotMin, tm.slotEnd, keys);
            sortUnique(keys);  // a coarse tile covers several slots
            for (uint64_t k : keys)
                if (const uint32_t* i = position.find(k)) out.push_back(&tiles[*i]);
            return;
        }
        forSlotsAround(tm.slotMin, tm.slotEnd, slotsPerAxis, [&](glm::uvec3 slot) {
            TileBuild* n = bySlot[at(slot)];
            if (n && std::find(out.begin(), out.end(), n) == out.end()) out.push_back(n);
        });
    }
};

/// Splits tiles 0..n-1, in key order, into `threads` runs of about equal weight: run k's
/// tiles get home k.
template <class Key, class Weight>
std::vector<unsigned> homesByKey(std::size_t n, Key key, Weight weight, unsigned threads) {
    std::vector<std::size_t> byKey(n);
    std::iota(byKey.begin(), byKey.end(), std::size_t(0));
    std::sort(byKey.begin(), byKey.end(), [&](std::size_t l, std::size_t r) { return key(l) < key(r); });
    uint64_t total = 0, before = 0;
    for (std::size_t i = 0; i < n; ++i) total += uint64_t(weight(i));
    std::vector<unsigned> home(n, 0u);
    for (std::size_t i : byKey) {
        // The run holding the middle of this tile's weight.
        const uint64_t middle = before + uint64_t(weight(i)) / 2;
        home[i] = total > 0 ? unsigned(std::min<uint64_t>(threads - 1, middle * threads / total)) : 0u;
        before += uint64_t(weight(i));
    }
    return home;
}

/// fn(i) for i in 0..n-1, each on its home thread, the heaviest of each home first (serially:
/// index order).
template <class Home, class Weight>
void inHomes(util::ThreadPool* pool, std::size_t n, Home home, Weight weight, const std::function<void(std::size_t)>& fn) {
    if (!pool || pool->threadCount() < 2) return util::parallelFor(nullptr, n, fn);
    const std::vector<std::size_t> order = util::heaviestFirst(n, weight);
    util::parallelForHomes(pool, order.size(), [&](std::size_t k) { return home(order[k]); },
                           [&](std::size_t k) { fn(order[k]); });
}

/// inHomes over a build's tiles (their homes are set).
template <class Weight>
void inHomes(util::ThreadPool* pool, const std::vector<TileBuild>& tiles, Weight weight,
             const std::function<void(std::size_t)>& fn) {
    inHomes(pool, tiles.size(), [&](std::size_t i) { return tiles[i].mesh->home; }, weight, fn);
}

}  // namespace

SurfaceMesher::SurfaceMesher(util::ThreadPool* pool) : mPool(pool) {}
SurfaceMesher::~SurfaceMesher() { clearTiles(); }

void SurfaceMesher::clearTiles() {
    std::vector<std::unique_ptr<TileMesh>*> owned;
    owned.reserve(mTiles.size());
    for (auto& [key, tm] : mTiles) owned.push_back(&tm);
    util::parallelForHomes(mPool, owned.size(), [&](std::size_t i) { return (*owned[i])->home; },
                           [&](std::size_t i) { owned[i]->reset(); });
    mTiles.clear();
}

void SurfaceMesher::build(adf::AdfPtr adf) {
    if (!adf) throw std::invalid_argument("surface nets: no snapshot");
    clearTiles();
    mAdf = std::move(adf);
    const auto tStart = std::chrono::steady_clock::now();
    const Adf& a = *mAdf;
    SurfaceNetsStats st;
    // 1. Boundary leaves and the crossings they emit, per tile.
    std::vector<const Tile*> withSurface;
    a.forEachTile([&](const Tile& t) {
        if (mayEmit(t)) withSurface.push_back(&t);
    });
    // Every phase, the assembly included, runs a tile on its home thread (util::parallelForHomes):
    // the threads take runs of tiles in key order (neighbours, which read each other's
    // crossings, mostly share one) of about equal node counts, so each phase reads what the
    // last one wrote for the same tile from its own core's cache. Within a thread's share the
    // largest tiles go first, so that no large tile ends a phase alone: the scan by nodes, the
    // others by boundary leaves (docs/decisions/0012-mesher-homes-and-place-table.md). A task
    // writes only its tile's records and its own quadrants of other tiles' crossings, so
    // neither the thread nor the order changes a result.
    // A scanned tile's TileMesh is made by its task (on its home thread, which uses it after).
    const std::size_t nScan = withSurface.size();
    std::vector<std::unique_ptr<TileMesh>> made(nScan);
    std::vector<TileBuild> tiles(nScan);  // the build's state of each tile, freed by phase 3
    std::vector<SurfaceNetsStats> scanStats(nScan);
    // Tiles that hold a ring cell but no boundary leaf (figure 9B), as each scan met them.
    std::vector<std::vector<uint64_t>> unscannedOwners(nScan);
    const uint32_t slotShift = uint32_t(a.domain().maxLevel - a.domain().tileLevel());
    auto nodes = [&](std::size_t i) { return withSurface[i]->nodeCount(); };
    const std::vector<unsigned> scanHome = homesByKey(
        nScan, [&](std::size_t i) { return packLattice(withSurface[i]->latticeOrigin()); }, nodes,
        mPool ? mPool->threadCount() : 1u);
    inHomes(mPool, nScan, [&](std::size_t i) { return scanHome[i]; }, nodes, [&](std::size_t i) {
        made[i] = std::make_unique<TileMesh>();
        TileMesh& tm = *made[i];
        TileBuild& tb = tiles[i];
        tb.mesh = &tm;
        setTile(a, *withSurface[i], tm);
        tm.home = scanHome[i];
        // In walk order; walked into a warm per-thread buffer and copied once (grown in place,
        // the tile's vector would be reallocated and copied several times).
        BuildScratch& scratch = buildScratch();
        std::vector<BoundaryCell>& walked = scratch.walkedLeaves;
        walked.clear();
        appendBoundaryCells(*tm.tile, a.domain().maxLevel, walked);
        tb.leaves.assign(walked.begin(), walked.end());
        scanStats[i].boundaryLeaves = tb.leaves.size();
        PoolAppender appender{tm.crossings};
        computeCrossings(a, *tm.tile, tb.leaves, appender, scanStats[i]);
        tm.liveCrossings = tm.crossings.size();
        listBorder(a, tm, tb.border, scratch.borderList);
        for (std::size_t b = 0; b < tb.border.size(); ++b) {
            if (b > 0 && tb.border[b].owner == tb.border[b - 1].owner) continue;
            const Tile& owner = *a.tileAtSlot(unpackLattice(tb.border[b].owner) >> slotShift);
            if (!mayEmit(owner)) unscannedOwners[i].push_back(tb.border[b].owner);
        }
    });
    mTiles.reserve(nScan + nScan / 8);
    for (std::size_t i = 0; i < nScan; ++i) mTiles.emplace(tiles[i].mesh->key, std::move(made[i]));
    st.tilesScanned = nScan;
    for (const SurfaceNetsStats& s : scanStats) {
        st.boundaryLeaves += s.boundaryLeaves;
        st.openCrossings += s.openCrossings;
        st.crossingsComputed += s.crossingsComputed;
    }

    const auto tPhase1 = std::chrono::steady_clock::now();
    // 2. Vertices of every tile owning a cell of a crossing (a tile with no boundary leaf can
    // still own one, figure 9B).
    for (const std::vector<uint64_t>& keys : unscannedOwners)
        for (uint64_t k : keys)
            if (!mTiles.count(k)) tiles.push_back({ensureTile(k), {}, {}});
    TileIndex index{tiles};
    index.build(a);
    // A tile's boundary leaves: about its cells, so its vertices (taken now: relaxation drops them).
    std::vector<std::size_t> leaves(tiles.size());
    for (std::size_t i = 0; i < tiles.size(); ++i) leaves[i] = tiles[i].leaves.size();
    auto byLeaves = [&](std::size_t i) { return leaves[i]; };
    std::vector<SurfaceNetsStats> meshStats(tiles.size());
    inHomes(mPool, tiles, byLeaves, [&](std::size_t i) {
        BuildScratch& s = buildScratch();
        index.neighbours(a, *tiles[i].mesh, s.neighbours, s.neighbourKeys);
        computeVertices(a, tiles[i], s.neighbours, meshStats[i]);
    });
    st.tilesMeshed = tiles.size();
    for (const SurfaceNetsStats& s : meshStats) addVertexCounters(st, s);

    const auto tPhase2 = std::chrono::steady_clock::now();
    // 3. Relaxation reads neighbours' projected vertices.
    inHomes(mPool, tiles, byLeaves, [&](std::size_t i) {
        TileMesh& tm = *tiles[i].mesh;
        splitFaces(tm);
        relaxInOrder(tm.vertices.size(), [&](std::size_t k) { return VertexRef{&tm, uint32_t(k)}; });
        // The build's state of the tile, freed on its home thread.
        tiles[i].leaves = {};
        tiles[i].border = {};
    });
    st.verticesRelaxed = st.verticesComputed;

    const auto tPhase3 = std::chrono::steady_clock::now();
    auto ms = [](auto from, auto to) { return std::chrono::duration<double, std::milli>(to - from).count(); };
    st.crossingMs = ms(tStart, tPhase1);
    st.vertexMs = ms(tPhase1, tPhase2);
    st.relaxMs = ms(tPhase2, tPhase3);
    dropEmptyTiles();
    totals(st);
    mStats = st;
    // Every share is new: the next take is a full delta.
    ++mGeneration;
    mResetPending = true;
    mChangedTiles.clear();
}

TileMesh* SurfaceMesher::ensureTile(uint64_t key) {
    auto it = mTiles.find(key);
    if (it != mTiles.end()) return it->second.get();
    const Adf& a = *mAdf;
    const uint32_t shift = uint32_t(a.domain().maxLevel - a.domain().tileLevel());
    const Tile* t = a.tileAtSlot(unpackLattice(key) >> shift);
    if (packLattice(t->latticeOrigin()) != key) return nullptr;
    auto tm = std::make_unique<TileMesh>();
    setTile(a, *t, *tm);
    TileMesh* raw = tm.get();
    mTiles.emplace(key, std::move(tm));
    return raw;
}

void SurfaceMesher::dropEmptyTiles() {
    for (auto it = mTiles.begin(); it != mTiles.end();) {
        if (it->second->liveCrossings == 0 && it->second->liveVertices == 0)
            it = mTiles.erase(it);
        else
            ++it;
    }
}

void SurfaceMesher::totals(SurfaceNetsStats& st) const {
    st.crossings = st.vertices = st.splitEdges = st.crossingSlots = 0;
    for (const auto& [key, tm] : mTiles) {
        st.crossings += tm->liveCrossings;
        st.crossingSlots += tm->crossings.size();
        st.vertices += tm->liveVertices;
        st.splitEdges += tm->splits.size();
    }
}

MeshBuffers meshAdf(adf::AdfPtr adf, util::ThreadPool* pool, SurfaceNetsStats* stats) {
    SurfaceMesher mesher(pool);
    mesher.build(std::move(adf));
    if (stats) *stats = mesher.stats();
    return mesher.mesh();
}

}  // namespace kizamu::mesh
