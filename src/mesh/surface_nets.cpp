// SPDX-License-Identifier: Apache-2.0
/// @file surface_nets.cpp
/// @brief Crossings per tile, cycles and vertices per cell, relaxation, a full build and the
/// assembled mesh (surface_nets.h); the incremental update is in surface_nets_update.cpp.
#include "mesh/surface_nets.h"

#include "mesh/mesh_colours.h"
#include "mesh/surface_nets_internal.h"
#include "util/thread_pool.h"

#include <glm/geometric.hpp>
#if defined(__SSE__)
#include <immintrin.h>
#endif

#include <algorithm>
#include <array>
#include <bit>
#include <chrono>
#include <cmath>
#include <functional>
#include <numeric>
#include <stdexcept>

namespace kizamu::mesh {

using adf::Adf;
using adf::Tile;
using namespace detail;

namespace {

/// A leaf as a crossing records it: packed origin (what the ring array holds), size in
/// lattice units, level.
struct CellLoc {
    uint64_t cell;
    uint32_t size;
    uint32_t level;
};

/// A tile's cells by their place in it (the origin's offset, 6 bits an axis), for tiles at most
/// 64 lattice units a side (those at the tile level with the default 6-level tiles): what a
/// build numbers its cells through and looks its leaves up in without a hash map's probing
/// (that took a third of the incidence gathering). Larger tiles use a hash map and the locator.
/// Per thread, 1 MiB; each user leaves every entry it set empty again (ClearOnExit).
class PlaceTable {
public:
    static constexpr int kBits = 6;
    static constexpr uint32_t kNone = UINT32_MAX;
    static bool fits(const Tile& t, int maxLevel) { return maxLevel - t.level() <= kBits; }
    /// `cell` (packed) lies in the tile whose packed origin is `tileKey`.
    static uint32_t place(uint64_t cell, uint64_t tileKey) {
        const uint64_t d = cell - tileKey;  // a cell of the tile: no field borrows
        constexpr uint64_t m = (1u << kBits) - 1;
        return uint32_t((d & m) | (((d >> 20) & m) << kBits) | (((d >> 40) & m) << (2 * kBits)));
    }
    static uint32_t* entries() {
        thread_local std::vector<uint32_t> table(std::size_t(1) << (3 * kBits), kNone);
        return table.data();
    }
    /// Empties the places of `cells` cells (key(i) for i < cells) when it goes, thrown past or not.
    template <class Key>
    struct ClearOnExit {
        uint32_t* table;
        uint64_t tileKey;
        std::size_t cells;
        Key key;
        ~ClearOnExit() {
            if (table)
                for (std::size_t i = 0; i < cells; ++i) table[place(key(i), tileKey)] = kNone;
        }
    };
};

/// The leaf containing a lattice point (like Adf::locateLeaf), for the neighbours of a leaf of
/// a given size: where that leaf is smaller, any smaller cell (all the callers ask then).
/// Two caches:
/// - the leaf found, by the block of the given size holding the point: neighbouring leaves
///   ask about the same blocks (136k distinct of 313k asks on the level-10 test part, before
///   computeCrossings answered most blocks of its own tile from the PlaceTable). Where
///   the leaf is no smaller than the block it holds the whole block (cells nest); where it is
///   smaller, so is the leaf at any point of the block. Direct-mapped: a collision only costs
///   a search (callers copy what they need before the next lookup).
/// - the path of the last search: a search near it climbs only to their common cell. It keeps
///   node indices only: a cell's size and origin follow from its depth and the point, and a
///   child's index from one bit per axis (sizes are powers of two: shifts, no divisions).
class LeafLocator {
public:
    explicit LeafLocator(const Adf& adf)
        : mAdf(adf), mMaxLevel(adf.domain().maxLevel),
          mSlotShift(uint32_t(adf.domain().maxLevel - adf.domain().tileLevel())) {
        std::fill(std::begin(mKeys), std::end(mKeys), kEmpty);
    }

    /// The reference stays valid until the next call. (Returning a copy made the compiler
    /// move it through the stack in overlapping pieces: a stalled load took a sixth of the
    /// crossing phase.)
    /// `block`: the packed origin of a block of `size` (aligned to it).
    const CellLoc& locate(uint64_t block, uint32_t size) {
        // Lattice coordinates stay below 2^17: bits 57 up of a packed point are free.
        const uint64_t key = block | (uint64_t(std::countr_zero(size)) << 58);
        const uint32_t i = uint32_t((key * 0x9e3779b97f4a7c15ull) >> (64 - kCacheBits));
        if (mKeys[i] != key) {
            mKeys[i] = key;
            mFound[i] = search(unpackLattice(block));
        }
        return mFound[i];
    }

private:
    CellLoc search(glm::uvec3 p) {
        if (mDepth > 0) {
            // Keep the cells that hold p: every cell of the path holds the last point, and
            // cells are aligned to their size, so those larger than every bit where p differs
            // from it (entry i has size 2^(rootShift - i)).
            const glm::uvec3 d = p ^ mLast;
            mDepth = std::clamp(mRootShift - int(std::bit_width(d.x | d.y | d.z)) + 1, 0, mDepth);
        }
        if (mDepth == 0) {
            mTile = mAdf.tileAtSlot(p >> mSlotShift);
            mRootShift = mMaxLevel - mTile->level();
            mNode[0] = 0;
            mDepth = 1;
        }
        mLast = p;
        uint32_t w = mTile->node(mNode[mDepth - 1]);
        while (adf::node::isInternal(w)) {
            const int shift = mRootShift - mDepth;  // of the child's size
            const uint32_t child = ((p.x >> shift) & 1u) | (((p.y >> shift) & 1u) << 1) | (((p.z >> shift) & 1u) << 2);
            mNode[mDepth++] = w + child;
            w = mTile->node(w + child);
        }
        const int depth = mDepth - 1 + int(adf::node::isBrick(w));  // a brick: its child holding p
        const uint32_t shift = uint32_t(mRootShift - depth);
        return {packLattice((p >> shift) << shift), 1u << shift, uint32_t(mTile->level() + depth)};
    }

    const Adf& mAdf;
    int mMaxLevel;
    uint32_t mSlotShift;
    static constexpr int kCacheBits = 10;  // 1,024 entries: 2 % less crossing time than 256 with leaves in walk order
    static constexpr uint64_t kEmpty = ~uint64_t(0);
    uint64_t mKeys[1u << kCacheBits];
    CellLoc mFound[1u << kCacheBits];
    const Tile* mTile = nullptr;
    int mRootShift = 0;  ///< the tile root's size is 2^mRootShift
    glm::uvec3 mLast{0};
    int mDepth = 0;
    uint32_t mNode[adf::kMaxSupportedLevel + 2];
};

/// Bit c: corner c negative (as the crossings' signs). Eight compares in two instructions
/// where SSE has them: the scalar loop took 40.
inline uint32_t insideCorners(const float* c) {
#if defined(__SSE__)
    const __m128 zero = _mm_setzero_ps();
    return uint32_t(_mm_movemask_ps(_mm_cmplt_ps(_mm_loadu_ps(c), zero))) |
           uint32_t(_mm_movemask_ps(_mm_cmplt_ps(_mm_loadu_ps(c + 4), zero))) << 4;
#else
    uint32_t inside = 0;
    for (int i = 0; i < 8; ++i) inside |= uint32_t(c[i] < 0.0f) << i;
    return inside;
#endif
}

inline bool isBoundary(const float* c) {
    const uint32_t inside = insideCorners(c);
    return inside != 0 && inside != 0xffu;
}

template <class T>
void sortUnique(std::vector<T>& v) {
    std::sort(v.begin(), v.end());
    v.erase(std::unique(v.begin(), v.end()), v.end());
}

/// Position of a cell of a tile whose side spans 2^bits lattice units, at `local` (its origin
/// less the tile's), in the boundary-cell walk's order: depth first, children by their x, y, z
/// bits (interleaved bits, z highest). A build keeps cells in that order, as the walk gives the
/// leaves: no sort, and neighbouring leaves come close together (the leaf locator's caches).
uint64_t walkOrder(glm::uvec3 local, int bits) {
    uint64_t k = 0;
    for (int b = bits - 1; b >= 0; --b)
        k = (k << 3) | (((local.z >> b) & 1u) << 2) | (((local.y >> b) & 1u) << 1) | ((local.x >> b) & 1u);
    return k;
}

/// Lattice box of a ring cell.
inline void ringBox(const Adf& adf, const Crossing& x, int q, glm::uvec3& lo, uint32_t& size) {
    lo = unpackLattice(x.ringCell[q]);
    size = 1u << uint32_t(adf.domain().maxLevel - x.ringLevel[q]);
}

/// Pairs the crossings on the face shared by cells A and B so that every segment cuts off a
/// run of inside lattice points (the rule both cells apply). Returns false if the signs do not
/// alternate around the face.
bool pairOnFace(glm::uvec3 loA, uint32_t sizeA, glm::uvec3 loB, uint32_t sizeB,
                const std::vector<const Crossing*>& xs, std::vector<std::pair<uint32_t, uint32_t>>& pairs) {
    int n = -1;
    for (int i = 0; i < 3; ++i)
        if (loA[i] + sizeA == loB[i] || loB[i] + sizeB == loA[i]) n = i;
    if (n < 0) return false;
    const int u = (n + 1) % 3, w = (n + 2) % 3;
    const double u0 = std::max(loA[u], loB[u]), u1 = std::min(loA[u] + sizeA, loB[u] + sizeB);
    const double w0 = std::max(loA[w], loB[w]), w1 = std::min(loA[w] + sizeA, loB[w] + sizeB);
    struct Item {
        double t;
        bool enter;
        uint32_t index;
    };
    std::vector<Item> items;
    for (uint32_t i = 0; i < xs.size(); ++i) {
        const Crossing& x = *xs[i];
        glm::dvec3 mid(x.start());
        mid[x.axis] += 0.5 * x.length;
        const bool in0 = x.startInside;
        Item it{0.0, false, i};
        if (x.axis == u) {
            if (mid[w] == w0) {  // bottom, walked toward +u
                it.t = (mid[u] - u0) / (u1 - u0);
                it.enter = !in0;
            } else {  // top, walked toward -u
                it.t = 2.0 + (u1 - mid[u]) / (u1 - u0);
                it.enter = in0;
            }
        } else {
            if (mid[u] == u1) {  // right, toward +w
                it.t = 1.0 + (mid[w] - w0) / (w1 - w0);
                it.enter = !in0;
            } else {  // left, toward -w
                it.t = 3.0 + (w1 - mid[w]) / (w1 - w0);
                it.enter = in0;
            }
        }
        items.push_back(it);
    }
    std::sort(items.begin(), items.end(), [](const Item& l, const Item& r) { return l.t < r.t; });
    const std::size_t m = items.size();
    std::size_t s = 0;
    while (s < m && !items[s].enter) ++s;
    if (s == m) return false;
    for (std::size_t i = 0; i < m; i += 2) {
        const Item& e = items[(s + i) % m];
        const Item& l = items[(s + i + 1) % m];
        if (!e.enter || l.enter) return false;
        pairs.emplace_back(e.index, l.index);
    }
    return true;
}

inline glm::vec3 clampToCell(glm::vec3 p, const Vertex& v) {
    const glm::vec3 lo(v.origin), hi = lo + float(v.size);
    return glm::clamp(p, lo, hi);
}

/// The cell's trilinear field at lattice point `p`: distance (m) and gradient (m per lattice unit).
/// kPacked: adf::trilinearPacked (the same value; where samples are not chained).
template <bool kPacked = false>
inline adf::Sample cellSample(const Vertex& v, glm::vec3 p) {
    const float inv = 1.0f / float(v.size);
    const glm::vec3 f = (p - glm::vec3(v.origin)) * inv;
    adf::Sample s = kPacked ? adf::trilinearPacked(v.corners, f) : adf::trilinear(v.corners, f);
    s.gradient *= inv;
    return s;
}

/// One Newton step onto the cell's zero set along its gradient, in lattice units, kept in the
/// cell. Reads only the cell's corners: inside its box that is the field itself.
template <bool kPacked = false>
inline glm::vec3 projectOnce(const Vertex& v, glm::vec3 p, glm::vec3* gradient = nullptr) {
    const adf::Sample s = cellSample<kPacked>(v, p);
    if (gradient) *gradient = s.gradient;
    const float g2 = glm::dot(s.gradient, s.gradient);
    if (!(g2 > 1e-20f) || !std::isfinite(s.distance)) return p;
    return clampToCell(p - (s.distance / g2) * s.gradient, v);
}

/// A build's per-thread buffers, reused across tiles and builds (pool workers live on): a
/// tile's buffers grew from empty every time, thousands of allocations per small mesh.
struct VertexScratch {
    std::vector<uint64_t> nbrs;
    std::vector<TileMesh*> nbrMeshes;
    std::vector<BoundaryCell> leaves;  ///< a scan's walk
    std::vector<TileMesh::BorderRef> border;  ///< a scan's border list
    /// A tile whose crossings are gathered: all (end == UINT32_MAX) or those its border list
    /// names in [begin, end).
    struct Source {
        TileMesh* tile;
        uint32_t begin, end;
    };
    std::vector<Source> sources;
    std::vector<Incidence> met, inc;       ///< incidences as gathered, then grouped by cell (only grow)
    std::vector<uint32_t> metCell;         ///< per gathered incidence: its cell's number
    std::vector<std::pair<uint64_t, uint32_t>> cells;  ///< (key, number) of each cell met that is no boundary leaf
    std::vector<uint32_t> rank;            ///< cell number -> position in walk order
    std::vector<uint64_t> rankKey;         ///< position in walk order -> the cell's key
    std::vector<uint32_t> cellBegin;       ///< per cell in walk order: its first incidence, then the end
    FlatMap64 number;                      ///< cell key -> its number, for tiles too large for PlaceTable
    CellScratch cell;
};
VertexScratch& vertexScratch() {
    thread_local VertexScratch s;
    return s;
}

/// A build's tiles by slot where the domain has at most 2^18 slots (level 12 with 6-level tiles), else by key
/// through a flat map (std::unordered_map's lookups took 1.4 % of a build; the flat map's
/// probing and the reads of the neighbours' tiles for their keys, 3 % more).
struct TileIndex {
    static constexpr uint32_t kMaxSlots = 1u << 18;
    std::vector<TileMesh*> tiles;
    std::vector<TileMesh*> bySlot;  ///< slot (x fastest) -> its tile's mesh, or null; or empty
    uint32_t slotsPerAxis = 0;
    FlatMap64 position;  ///< key -> index in `tiles`, where bySlot is empty

    std::size_t at(glm::uvec3 slot) const { return (std::size_t(slot.z) * slotsPerAxis + slot.y) * slotsPerAxis + slot.x; }
    void build(const Adf& adf) {
        slotsPerAxis = adf.domain().slotsPerAxis();
        if (uint64_t(slotsPerAxis) * slotsPerAxis * slotsPerAxis <= kMaxSlots) {
            bySlot.assign(std::size_t(slotsPerAxis) * slotsPerAxis * slotsPerAxis, nullptr);
            for (TileMesh* tm : tiles)
                for (uint32_t z = tm->slotMin.z; z < tm->slotEnd.z; ++z)
                    for (uint32_t y = tm->slotMin.y; y < tm->slotEnd.y; ++y)
                        for (uint32_t x = tm->slotMin.x; x < tm->slotEnd.x; ++x) bySlot[at({x, y, z})] = tm;
            return;
        }
        position.reserve(tiles.size());
        for (uint32_t i = 0; i < tiles.size(); ++i) position.assign(tiles[i]->key, i);
    }
    /// The meshes of the tiles whose slots touch (closed) `tm`'s, `tm` included, each once.
    void neighbours(const Adf& adf, const TileMesh& tm, std::vector<TileMesh*>& out, std::vector<uint64_t>& keys) const {
        out.clear();
        if (bySlot.empty()) {
            keys.clear();
            neighbourKeys(adf, tm.slotMin, tm.slotEnd, keys);
            sortUnique(keys);  // a coarse tile covers several slots
            for (uint64_t k : keys)
                if (const uint32_t* i = position.find(k)) out.push_back(tiles[*i]);
            return;
        }
        forSlotsAround(tm.slotMin, tm.slotEnd, slotsPerAxis, [&](glm::uvec3 slot) {
            TileMesh* n = bySlot[at(slot)];
            if (n && std::find(out.begin(), out.end(), n) == out.end()) out.push_back(n);
        });
    }
};

/// Incidences of cell-owner `tm` during a build: crossings in its own pool and its neighbours'
/// border lists that have a leaf owned by it, into s.inc grouped by cell in walk order (cell
/// i's run is [s.cellBegin[i], s.cellBegin[i + 1]), its key s.rankKey[i]), each cell's sorted
/// by crossing key. A counting sort: cells are numbered through s.number, the tile's boundary
/// leaves in their order and other cells as met, then merged in; each cell's handful of incidences is sorted by insertion. A boundary
/// leaf may get an empty run (its crossings all leave the domain).
void gatherIncidences(int maxLevel, TileMesh& tm, const std::vector<TileMesh*>& nbrs, VertexScratch& s) {
    // The crossings read: the tile's own, and the runs of its neighbours' border lists naming it.
    s.sources.clear();
    std::size_t bound = 0;  // incidences at most (4 a crossing)
    for (TileMesh* found : nbrs) {
        TileMesh& src = *found;
        if (src.key == tm.key) {
            s.sources.push_back({&src, 0, UINT32_MAX});
            bound += 4 * std::size_t(src.crossings.size());
        } else {
            const auto b = std::lower_bound(src.border.begin(), src.border.end(), TileMesh::BorderRef{tm.key, 0});
            auto e = b;
            while (e != src.border.end() && e->owner == tm.key) ++e;
            s.sources.push_back({&src, uint32_t(b - src.border.begin()), uint32_t(e - src.border.begin())});
            bound += 4 * std::size_t(e - b);
        }
    }
    // Written through raw pointers into buffers that only grow: push_back's checks took a third
    // of this function.
    if (s.met.size() < bound) {
        s.met.resize(bound);
        s.metCell.resize(bound);
        s.cells.resize(bound);
    }
    Incidence* met = s.met.data();
    uint32_t* metCell = s.metCell.data();
    std::pair<uint64_t, uint32_t>* cellsMet = s.cells.data();
    // Nearly every cell is a boundary leaf of the tile: those are numbered first, in their
    // (walk) order, so only the few others need sorting in (sorting every cell took 2 % of a build).
    const uint32_t nLeaves = uint32_t(tm.leaves.size());
    uint32_t nMet = 0, nCells = nLeaves, nExtra = 0;
    // In locals: the writes through `add` could alias tm's fields.
    const uint64_t tileKey = tm.key, outside = tm.outside;
    // Numbers through the place table; a larger (coarse) tile through a hash map.
    uint32_t* const byPlace = PlaceTable::fits(*tm.tile, maxLevel) ? PlaceTable::entries() : nullptr;
    auto place = [&](uint64_t cell) { return PlaceTable::place(cell, tileKey); };
    if (!byPlace) s.number.resetFor(nLeaves + nLeaves / 8 + 8);
    s.rankKey.resize(nLeaves);
    // The leaves' places, then the other cells' (numbered after them). From the leaves
    // themselves: s.rankKey is merged with the other cells before the table is cleared.
    const auto cellKey = [&](std::size_t i) {
        return i < nLeaves ? packLattice(tm.leaves[i].origin) : cellsMet[i - nLeaves].first;
    };
    PlaceTable::ClearOnExit<decltype(cellKey)> clear{byPlace, tileKey, 0, cellKey};
    for (uint32_t i = 0; i < nLeaves; ++i) {
        s.rankKey[i] = packLattice(tm.leaves[i].origin);
        if (byPlace) byPlace[place(s.rankKey[i])] = i;
        else s.number.assign(s.rankKey[i], i);
        clear.cells = i + 1;
    }
    auto add = [&](Crossing& x, uint64_t key, int q, uint8_t first, uint8_t last) {
        uint32_t number;
        if (byPlace) {
            uint32_t& slot = byPlace[place(x.ringCell[q])];
            if (slot == PlaceTable::kNone) {
                slot = nCells;
                clear.cells = nCells + 1;  // (cellsMet's entry is written below)
            }
            number = slot;
        } else {
            number = s.number.findOrAssign(x.ringCell[q], nCells);
        }
        if (number == nCells) cellsMet[nExtra++] = {x.ringCell[q], nCells++};
        met[nMet] = {x.ringCell[q], key, &x, first, last};
        metCell[nMet++] = number;
    };
    auto owned = [&](uint64_t cell) { return inTile(cell, tileKey, outside); };
    // Inlined: called out of line, it kept nothing in registers (+11 % instructions here).
    auto take = [&](Crossing& x) __attribute__((always_inline)) {
        const uint64_t key = x.key();
        // A leaf fills a run of adjacent quadrants: nearly always one each (four leaves).
        const uint64_t* c = x.ringCell;
        if (c[0] != c[1] && c[1] != c[2] && c[2] != c[3] && c[3] != c[0]) {
            for (int q = 0; q < 4; ++q)
                if (owned(c[q])) add(x, key, q, uint8_t(q), uint8_t(q));
            return;
        }
        uint8_t done = 0;
        for (int q = 0; q < 4; ++q) {
            if (!owned(c[q]) || ((done >> q) & 1)) continue;
            uint8_t first, last;
            incidenceRun(x, q, first, last);
            for (uint8_t r = first;; r = uint8_t((r + 1) % 4)) {
                done |= uint8_t(1u << r);
                if (r == last) break;
            }
            add(x, key, q, first, last);
        }
    };
    for (const VertexScratch::Source& from : s.sources) {
        TileMesh& src = *from.tile;
        if (from.end == UINT32_MAX) {
            for (uint32_t j = 0; j < src.crossings.size(); ++j) take(src.crossings[j]);
        } else {
            for (uint32_t b = from.begin; b < from.end; ++b) take(src.crossings[src.border[b].index]);
        }
    }
    const std::size_t cells = nCells;
    s.rank.resize(cells);
    if (nExtra == 0) {
        std::iota(s.rank.begin(), s.rank.end(), 0u);
    } else {  // merge the others into the leaves' (walk) order
        const glm::uvec3 o = tm.tile->latticeOrigin();
        const int bits = maxLevel - tm.tile->level();
        auto order = [&](uint64_t key) { return walkOrder(unpackLattice(key) - o, bits); };
        std::vector<std::pair<uint64_t, uint32_t>> extras(nExtra);  // (walk order, index in cellsMet)
        for (uint32_t j = 0; j < nExtra; ++j) extras[j] = {order(cellsMet[j].first), j};
        std::sort(extras.begin(), extras.end());
        std::vector<uint64_t> leafKeys(s.rankKey.begin(), s.rankKey.end());
        s.rankKey.resize(cells);
        uint32_t leaf = 0, extra = 0;
        for (uint32_t r = 0; r < cells; ++r) {
            if (extra == nExtra || (leaf < nLeaves && order(leafKeys[leaf]) < extras[extra].first)) {
                s.rank[leaf] = r;
                s.rankKey[r] = leafKeys[leaf++];
            } else {
                const auto& [key, number] = cellsMet[extras[extra++].second];
                s.rank[number] = r;
                s.rankKey[r] = key;
            }
        }
    }
    s.inc.resize(nMet);
    groupByRank(nMet, s.rank, s.cellBegin, [&](std::size_t j) { return metCell[j]; },
                [&](std::size_t j, uint32_t at) { s.inc[at] = met[j]; });
    for (std::size_t i = 0; i < cells; ++i) {
        Incidence* run = s.inc.data() + s.cellBegin[i];
        const uint32_t n = s.cellBegin[i + 1] - s.cellBegin[i];
        for (uint32_t j = 1; j < n; ++j) {
            if (run[j - 1].crossingKey < run[j].crossingKey) continue;  // in place (keys are distinct)
            const Incidence v = run[j];
            uint32_t k = j;
            for (; k > 0 && v.crossingKey < run[k - 1].crossingKey; --k) run[k] = run[k - 1];
            run[k] = v;
        }
    }
}

/// Cycles and projected vertices of every cell `tm` owns, during a build.
void computeVertices(const Adf& adf, TileMesh& tm, const std::vector<TileMesh*>& nbrs, SurfaceNetsStats& st) {
    VertexScratch& scratchAll = vertexScratch();
    gatherIncidences(adf.domain().maxLevel, tm, nbrs, scratchAll);
    const std::vector<Incidence>& inc = scratchAll.inc;
    const std::vector<uint32_t>& cellBegin = scratchAll.cellBegin;
    const std::size_t cells = cellBegin.size() - 1;
    tm.vertices.clear();
    tm.projected.clear();
    tm.placed.clear();
    tm.freeVertices.clear();
    tm.liveVertices = 0;
    tm.incidences.clear();
    tm.multiFaces.clear();
    tm.vertices.reserve(cells + cells / 8);  // a few cells hold several sheets
    tm.projected.reserve(cells + cells / 8);
    tm.placed.reserve(cells + cells / 8);
    tm.incidences.reserve(inc.size());       // each incidence goes to one vertex
    CellScratch& scratch = scratchAll.cell;
    scratch.freshCrossings = true;  // a build made every crossing this phase reads
    std::size_t leafAt = 0;  // the cells in walk order take tm.leaves in turn
    for (std::size_t i = 0; i < cells; ++i) {
        const uint32_t i0 = cellBegin[i], i1 = cellBegin[i + 1];
        const uint64_t cell = scratchAll.rankKey[i];
        const BoundaryCell* leaf =
            leafAt < tm.leaves.size() && packLattice(tm.leaves[leafAt].origin) == cell ? &tm.leaves[leafAt++] : nullptr;
        if (i0 == i1) continue;  // a boundary leaf whose crossings all leave the domain: no vertex
        // The cell's corners: a boundary leaf of this tile, or (figure 9B) looked up.
        float corners[8];
        if (leaf) {
            std::copy(leaf->corners, leaf->corners + 8, corners);
        } else {
            const adf::LeafRef r = adf.findLeaf(unpackLattice(cell));
            std::copy(r.corners, r.corners + 8, corners);
            if (!isBoundary(corners)) ++st.signlessCells;
        }
        meshCell(adf, tm, &inc[i0], i1 - i0, corners, scratch, st);
    }
    tm.liveIncidences = tm.incidences.size();
    tm.cellVertex.clear();
    tm.cellVertexPending = true;
}

}  // namespace

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

/// The 12 edges of a cell in the order crossings are emitted: start and end corner, axis, the
/// quadrant the cell fills around the edge, and per quadrant the step back from the edge's
/// start to the unit cube next to it there (1 along a and/or b), packed (packLattice).
struct CellEdge {
    uint8_t c0, c1, axis, a, b, mine;
    uint64_t packedStep[4];
};
/// Quadrant q lies on the -a (-b) side of an edge.
constexpr bool kMinusA[4] = {false, true, true, false}, kMinusB[4] = {false, false, true, true};
constexpr std::array<CellEdge, 12> kCellEdges = [] {
    std::array<CellEdge, 12> e{};
    int i = 0;
    for (int k = 0; k < 3; ++k)
        for (int c0 = 0; c0 < 8; ++c0) {
            if ((c0 >> k) & 1) continue;
            const int a = (k + 1) % 3, b = (k + 2) % 3;
            const bool plusA = !((c0 >> a) & 1), plusB = !((c0 >> b) & 1);
            const int mine = plusA ? (plusB ? 0 : 3) : (plusB ? 1 : 2);
            CellEdge& x = e[i++];
            x = {uint8_t(c0), uint8_t(c0 | (1 << k)), uint8_t(k), uint8_t(a), uint8_t(b), uint8_t(mine), {}};
            for (int q = 0; q < 4; ++q) {
                uint32_t d[3] = {0, 0, 0};
                d[a] = kMinusA[q];
                d[b] = kMinusB[q];
                x.packedStep[q] = packLattice({d[0], d[1], d[2]});
            }
        }
    return e;
}();
/// Corner c's offset from a cell's origin in a cell's size, packed (packLattice).
constexpr std::array<uint64_t, 8> kPackedCorner = [] {
    std::array<uint64_t, 8> t{};
    for (uint32_t c = 0; c < 8; ++c) t[c] = packLattice({c & 1, (c >> 1) & 1, c >> 2});
    return t;
}();
/// Bit i: edge i of kCellEdges changes sign, by the cell's inside corners (bit c: corner c).
constexpr std::array<uint16_t, 256> kSignChangingEdges = [] {
    std::array<uint16_t, 256> t{};
    for (uint32_t inside = 0; inside < 256; ++inside)
        for (int i = 0; i < 12; ++i)
            t[inside] |= uint16_t((((inside >> kCellEdges[i].c0) ^ (inside >> kCellEdges[i].c1)) & 1u) << i);
    return t;
}();
/// The edge of kCellEdges along `axis` that the cell fills quadrant q around.
constexpr auto kEdgeAt = [] {
    std::array<std::array<uint8_t, 4>, 3> t{};
    for (int i = 0; i < 12; ++i) t[kCellEdges[i].axis][kCellEdges[i].mine] = uint8_t(i);
    return t;
}();
/// By the cell's inside corners: how many sign-changing edges it has where they make one cycle
/// across its faces (two on a face are joined) and no face has four of them (their pairing
/// needs the points); otherwise 0.
constexpr std::array<uint8_t, 256> kOneSheetEdges = [] {
    std::array<uint8_t, 256> t{};
    for (uint32_t inside = 0; inside < 256; ++inside) {
        const uint16_t edges = kSignChangingEdges[inside];
        uint8_t parent[12];
        for (int i = 0; i < 12; ++i) parent[i] = uint8_t(i);
        auto find = [&](int i) {
            while (parent[i] != i) i = parent[i];
            return i;
        };
        int components = std::popcount(edges);
        bool ambiguous = false;
        for (int j = 0; j < 3; ++j)  // the faces where coordinate j is 0 or 1
            for (int side = 0; side < 2; ++side) {
                int on[4], m = 0;
                for (int i = 0; i < 12; ++i)
                    if (((edges >> i) & 1) && kCellEdges[i].axis != j && ((kCellEdges[i].c0 >> j) & 1) == side)
                        on[m++] = i;
                if (m == 4) ambiguous = true;
                if (m == 2 && find(on[0]) != find(on[1])) {
                    parent[find(on[0])] = uint8_t(find(on[1]));
                    --components;
                }
            }
        t[inside] = uint8_t(!ambiguous && components == 1 ? std::popcount(edges) : 0);
    }
    return t;
}();

/// For a brick child (by its position in the brick) and each edge: the quadrants whose unit
/// cube lies in a sibling (same size, same tile: no lookup), and whether one of them comes
/// before the child's own quadrant, so that the sibling emits the crossing (12-bit mask).
struct BrickEdges {
    uint8_t siblings[12];
    uint16_t settled;
};
constexpr std::array<BrickEdges, 8> kBrickEdges = [] {
    std::array<BrickEdges, 8> t{};
    for (int child = 0; child < 8; ++child)
        for (int i = 0; i < 12; ++i) {
            const CellEdge& e = kCellEdges[i];
            // In units of the child: its offset in the brick plus the edge's start corner.
            const int va = ((child >> e.a) & 1) + ((e.c0 >> e.a) & 1), vb = ((child >> e.b) & 1) + ((e.c0 >> e.b) & 1);
            for (int q = 0; q < 4; ++q) {
                if (q == e.mine) continue;
                const bool inA = va == 1 || (va == 0 && !kMinusA[q]) || (va == 2 && kMinusA[q]);
                const bool inB = vb == 1 || (vb == 0 && !kMinusB[q]) || (vb == 2 && kMinusB[q]);
                if (!(inA && inB)) continue;
                t[child].siblings[i] |= uint8_t(1u << q);
                if (q < e.mine) t[child].settled |= uint16_t(1u << i);
            }
        }
    return t;
}();

template <class Out>
void computeCrossings(const Adf& adf, const Tile& tile, const std::vector<BoundaryCell>& leaves, Out& out,
                      SurfaceNetsStats& st, StartFilter filter) {
    const uint32_t top = adf.domain().latticeSize();
    const int maxLevel = adf.domain().maxLevel;
    LeafLocator locator(adf);
    // The leaves by place: a block of the tile whose origin is a leaf's is answered by that leaf
    // (it holds the block, or is smaller), with no search. The rest ask the locator.
    const uint64_t tileKey = packLattice(tile.latticeOrigin());
    const uint64_t outside = outsideOf(tile, maxLevel);
    uint32_t* const byPlace = PlaceTable::fits(tile, maxLevel) ? PlaceTable::entries() : nullptr;
    const auto leafKey = [&](std::size_t i) { return packLattice(leaves[i].origin); };
    PlaceTable::ClearOnExit<decltype(leafKey)> clear{byPlace, tileKey, 0, leafKey};
    if (byPlace) {
        for (uint32_t i = 0; i < leaves.size(); ++i) byPlace[PlaceTable::place(leafKey(i), tileKey)] = i;
        clear.cells = leaves.size();
    }
    auto locate = [&](uint64_t block, uint32_t size) -> CellLoc {
        if (byPlace && inTile(block, tileKey, outside)) {
            const uint32_t i = byPlace[PlaceTable::place(block, tileKey)];
            if (i != PlaceTable::kNone) return {block, leaves[i].size, uint32_t(maxLevel - std::countr_zero(leaves[i].size))};
        }
        return locator.locate(block, size);
    };
    for (const BoundaryCell& leaf : leaves) {
        const uint32_t inside = insideCorners(leaf.corners);
        uint32_t todo = kSignChangingEdges[inside];
        // Away from the domain's border no quadrant can leave it; there a brick child knows its
        // siblings from its position, and skips the edges a sibling emits without a lookup.
        const glm::uvec3 hi = leaf.origin + leaf.size;
        const bool interior = glm::all(glm::greaterThan(leaf.origin, glm::uvec3(0))) && glm::all(glm::lessThan(hi, glm::uvec3(top)));
        const BrickEdges* brick = nullptr;
        if (interior && leaf.brickChild) {
            const glm::uvec3 at = glm::min(leaf.origin & leaf.size, glm::uvec3(1));
            brick = &kBrickEdges[at.x | (at.y << 1) | (at.z << 2)];
            todo &= ~uint32_t(brick->settled);
        }
        const glm::uvec3 parent = leaf.origin & ~glm::uvec3(2 * leaf.size - 1);
        const uint8_t leafLevel = uint8_t(maxLevel - std::countr_zero(leaf.size));
        // Points and blocks as packed integers (packLattice): where no field can go below zero
        // a step is one multiply-subtract, and a packed block is what the ring records.
        const uint64_t origin = packLattice(leaf.origin), size = leaf.size;
        for (; todo; todo &= todo - 1) {
            const CellEdge& edge = kCellEdges[std::countr_zero(todo)];
            const int c0 = edge.c0, c1 = edge.c1, k = edge.axis, a = edge.a, b = edge.b, mine = edge.mine;
            const uint64_t start = origin + size * kPackedCorner[c0];
            if (filter.keep && !filter.keep(filter.context, unpackLattice(start))) continue;
            // The block of the leaf's size next to the edge's start in each quadrant (a leaf
            // holding its unit cube there is no smaller than the block, or lies inside it);
            // whether it leaves the domain; whether it is a sibling of the same brick.
            uint64_t block[4];
            uint32_t openAt = 0, siblingAt = 0;
            if (interior) {  // the start is at least one leaf size from the domain's low faces
                for (int q = 0; q < 4; ++q) block[q] = start - size * edge.packedStep[q];
                if (brick) siblingAt = brick->siblings[std::countr_zero(todo)];
            } else {
                const glm::uvec3 p = unpackLattice(start);
                for (int q = 0; q < 4; ++q) {
                    if (q == mine) continue;
                    // Plain arrays: glm's operator[] on a run-time axis is a switch.
                    uint32_t s[3] = {p.x, p.y, p.z};
                    if ((kMinusA[q] && s[a] == 0) || (kMinusB[q] && s[b] == 0)) {
                        openAt |= 1u << q;
                        continue;
                    }
                    s[a] -= kMinusA[q];
                    s[b] -= kMinusB[q];
                    if (s[a] >= top || s[b] >= top) {
                        openAt |= 1u << q;
                        continue;
                    }
                    const glm::uvec3 cube(s[0], s[1], s[2]);
                    block[q] = packLattice(cube & ~glm::uvec3(leaf.size - 1));
                    if (leaf.brickChild && glm::all(glm::lessThan(cube - parent, glm::uvec3(2 * leaf.size))))
                        siblingAt |= 1u << q;
                }
            }
            // Leaf at each quadrant: the one holding that block. Not minimal: a smaller leaf
            // splits this edge. Not canonical: an equal leaf earlier in quadrant order emits it.
            // Any one of these settles it, so siblings are asked first and lookups stop at the
            // first; only where a quadrant leaves the domain does the quadrant order decide
            // (whether the crossing is counted open).
            // The ring as found (copied at once: a later lookup may reuse the cache entry).
            uint64_t ringCell[4];
            uint32_t ringLevel[4];
            const uint32_t others = 0xfu & ~(1u << mine);
            const uint32_t asks = openAt ? others : (siblingAt & others) | ((~siblingAt & others) << 4);  // in order
            bool skip = false, open = false;
            for (uint32_t m = asks; m && !skip; m &= m - 1) {
                const int q = std::countr_zero(m) & 3;
                if ((openAt >> q) & 1) {
                    open = true;
                    break;
                }
                if ((siblingAt >> q) & 1) {
                    ringCell[q] = block[q];
                    ringLevel[q] = leafLevel;
                    skip = q < mine;
                } else {
                    const CellLoc found = locate(block[q], leaf.size);
                    ringCell[q] = found.cell;
                    ringLevel[q] = found.level;
                    skip = found.size < leaf.size || (found.size == leaf.size && q < mine);
                }
            }
            if (open) {
                ++st.openCrossings;
                continue;
            }
            if (skip) continue;
            Crossing& x = out.emplace_back();
            const glm::uvec3 p = unpackLattice(start);
            x.length = leaf.size;
            x.axis = uint8_t(k);
            x.startInside = (inside >> c0) & 1;
            x.emitter = uint8_t(mine);
            ringCell[mine] = origin;
            ringLevel[mine] = leafLevel;
            for (int q = 0; q < 4; ++q) {
                x.ringCell[q] = ringCell[q];
                x.ringLevel[q] = uint8_t(ringLevel[q]);
            }
            const float v0 = leaf.corners[c0], v1 = leaf.corners[c1];
            const float t = v0 / (v0 - v1);
            // Added on its axis only (adding zero elsewhere changes nothing): written through an
            // array indexed by the axis, the point was read back before the store had landed.
            const float along = t * float(leaf.size);
            x.point = glm::vec3(float(p.x) + (k == 0 ? along : 0.0f), float(p.y) + (k == 1 ? along : 0.0f),
                                float(p.z) + (k == 2 ? along : 0.0f));
            x.alive = 1;
            ++st.crossingsComputed;
        }
    }
}

template void computeCrossings(const Adf&, const Tile&, const std::vector<BoundaryCell>&, std::vector<Crossing>&,
                               SurfaceNetsStats&, StartFilter);
template void computeCrossings(const Adf&, const Tile&, const std::vector<BoundaryCell>&, PoolAppender&,
                               SurfaceNetsStats&, StartFilter);

void incidenceRun(const Crossing& x, int q, uint8_t& first, uint8_t& last) {
    // The run of equal ring cells through q, walked both ways (a cyclic run of at most three:
    // no leaf holds an edge inside it); nearly always q alone, two comparisons.
    const uint64_t* c = x.ringCell;
    int f = q, l = q;
    for (int i = 0; i < 2 && c[(f + 3) % 4] == c[q]; ++i) f = (f + 3) % 4;
    for (int i = 0; i < 2 && c[(l + 1) % 4] == c[q]; ++i) l = (l + 1) % 4;
    first = uint8_t(f);
    last = uint8_t(l);
}

uint32_t meshCell(const Adf& adf, TileMesh& tm, const Incidence* inc, uint32_t n, const float corners[8],
                  CellScratch& s, SurfaceNetsStats& st) {
    if (n == 0) return UINT32_MAX;
    glm::uvec3 origin;
    uint32_t size;
    ringBox(adf, *inc[0].x, inc[0].first, origin, size);
    // Nearly every cell has a handful of crossings: stack buffers, the scratch only beyond.
    constexpr uint32_t kSmall = 16;
    CellScratch::FaceEntry faceBuf[2 * kSmall];
    uint32_t parentBuf[kSmall], cycleBuf[kSmall];
    CellScratch::FaceEntry* faces = faceBuf;
    uint32_t* parent = parentBuf;
    uint32_t* cycleOf = cycleBuf;
    if (n > kSmall) {
        s.faces.resize(2 * std::size_t(n));
        s.parent.resize(n);
        s.cycleOf.resize(n);
        faces = s.faces.data();
        parent = s.parent.data();
        cycleOf = s.cycleOf.data();
    }
    // Disjoint sets of the cell's crossings (the cycles depend only on the partition), set up
    // only where the faces do not close one cycle through all of them.
    uint32_t cycles = n;
    auto separate = [&] {
        for (uint32_t j = 0; j < n; ++j) parent[j] = j;
        cycles = n;
    };
    auto find = [&](uint32_t i) {
        while (parent[i] != i) i = parent[i] = parent[parent[i]];
        return i;
    };
    auto unite = [&](uint32_t a, uint32_t b) {
        a = find(a);
        b = find(b);
        if (a == b) return;
        parent[std::max(a, b)] = std::min(a, b);
        --cycles;
    };
    const uint32_t nf = 2 * n;
    // Entry 2j (2j + 1): crossing j's face toward the ring cell before (after) its run.
    auto faceRing = [&](uint32_t f) {
        const Incidence& c = inc[f / 2];
        return f % 2 ? (c.last + 1) % 4 : (c.first + 3) % 4;
    };
    // This cell owns the faces toward larger keys: their split vertices are decided again
    // (splitFaces), so forget old ones (the crossing may be kept unchanged).
    if (!s.freshCrossings)
        for (uint32_t j = 0; j < n; ++j) {
            const Incidence& c = inc[j];
            const int qa = faceRing(2 * j), qb = faceRing(2 * j + 1);
            if (c.cell < c.x->ringCell[qa]) c.x->split[qa] = Crossing::kNoSplit;
            if (c.cell < c.x->ringCell[qb]) c.x->split[c.last] = Crossing::kNoSplit;
        }
    // Most cells need no pairing: where the crossings are exactly the cell's own sign-changing
    // edges, a face carrying two of them has one leaf behind it (a smaller one would split the
    // face's edges, and their crossings would be shorter than the cell), so the cycles are the
    // cube's, known from the corner signs (kOneSheetEdges).
    // A crossing as long as the cell, with the cell in one quadrant around it, lies on the
    // cell's edge at that quadrant (edges start at multiples of their length).
    const uint32_t inside = insideCorners(corners);
    const uint32_t edges = kSignChangingEdges[inside];
    bool oneSheet = n == kOneSheetEdges[inside];  // n > 0
    for (uint32_t j = 0, seen = 0; j < n && oneSheet; ++j) {
        const Incidence& in = inc[j];
        const uint32_t bit = 1u << kEdgeAt[in.x->axis][in.first];
        oneSheet = in.x->length == size && in.first == in.last && (edges & ~seen & bit);
        seen |= bit;
    }
    if (oneSheet) {
        cycles = 1;
    } else {
        // Otherwise nearly every face carries two crossings: pair the entries by neighbour through
        // a small open-addressed table (no sort, no search). Any other count on a face regroups all
        // entries in order below, from scratch.
        constexpr uint32_t kTable = 32;  // twice the most entries taken here
        uint64_t tableKey[kTable];
        uint32_t tableEntry[kTable], partner[kTable / 2];  // partner: the other entry on the face
        uint32_t used = 0, closed = 0;  // bit t: slot t holds a neighbour; its second entry came
        bool paired = nf <= kTable / 2;
        for (uint32_t f = 0; f < nf && paired; ++f) {
            const uint64_t neighbour = inc[f / 2].x->ringCell[faceRing(f)];
            uint32_t t = uint32_t((neighbour * 0x9E3779B97F4A7C15ull) >> 59);
            while (((used >> t) & 1) && tableKey[t] != neighbour) t = (t + 1) % kTable;
            if (!((used >> t) & 1)) {
                used |= 1u << t;
                tableKey[t] = neighbour;
                tableEntry[t] = f;
            } else if ((closed >> t) & 1) {
                paired = false;  // a third entry on this face
            } else {
                closed |= 1u << t;
                partner[f] = tableEntry[t];
                partner[tableEntry[t]] = f;
            }
        }
        paired = paired && used == closed;
        if (paired) {
            // One cycle when the walk from crossing 0, across a face to the partner entry and out
            // through its crossing's other face, meets every crossing before it is back.
            uint32_t met = 1;
            for (uint32_t f = partner[1]; f / 2 != 0; f = partner[f ^ 1]) ++met;
            if (met == n) {
                cycles = 1;
            } else {
                separate();
                for (uint32_t f = 0; f < nf; ++f)
                    if (f < partner[f]) unite(f / 2, partner[f] / 2);
            }
        } else {
            separate();
            for (uint32_t f = 0; f < nf; ++f) faces[f] = {inc[f / 2].x->ringCell[faceRing(f)], faceRing(f), f / 2};
        }
        // Group the entries by face (stable: within a face they stay in crossing order).
        auto before = [](const CellScratch::FaceEntry& l, const CellScratch::FaceEntry& r) {
            return l.neighbour < r.neighbour;
        };
        if (paired) {
            // done
        } else if (nf > 32) {
            std::stable_sort(faces, faces + nf, before);
        } else {
            for (uint32_t i = 1; i < nf; ++i) {
                const CellScratch::FaceEntry v = faces[i];
                uint32_t j = i;
                for (; j > 0 && before(v, faces[j - 1]); --j) faces[j] = faces[j - 1];
                faces[j] = v;
            }
        }
        for (uint32_t f0 = 0; f0 < nf && !paired;) {
            uint32_t f1 = f0 + 1;
            while (f1 < nf && faces[f1].neighbour == faces[f0].neighbour) ++f1;
            const uint32_t m = f1 - f0;
            if (m == 2) {
                unite(faces[f0].local, faces[f0 + 1].local);
            } else {
                bool ok = false;
                if (m >= 4 && m % 2 == 0) {
                    ++st.multiCrossingFaces;
                    const Incidence& any = inc[faces[f0].local];
                    glm::uvec3 loA, loB;
                    uint32_t sizeA, sizeB;
                    ringBox(adf, *any.x, any.first, loA, sizeA);
                    ringBox(adf, *any.x, faces[f0].q, loB, sizeB);
                    s.faceXs.clear();
                    s.pairs.clear();
                    for (uint32_t f = f0; f < f1; ++f) s.faceXs.push_back(inc[faces[f].local].x);
                    ok = pairOnFace(loA, sizeA, loB, sizeB, s.faceXs, s.pairs);
                    if (ok) {
                        for (auto [e, l] : s.pairs) unite(faces[f0 + e].local, faces[f0 + l].local);
                        if (inc[0].cell < faces[f0].neighbour) {
                            MultiFace mf;
                            mf.cellA = inc[0].cell;
                            mf.cellB = faces[f0].neighbour;
                            auto end = [&](uint32_t e) {
                                const CellScratch::FaceEntry& fe = faces[f0 + e];
                                const Incidence& c = inc[fe.local];
                                const uint8_t qB = uint8_t(fe.q);
                                const uint8_t qA = qB == (c.first + 3) % 4 ? c.first : c.last;
                                return MultiFace::End{c.x, qA, qB};
                            };
                            for (auto [e, l] : s.pairs) mf.segments.emplace_back(end(e), end(l));
                            tm.multiFaces.push_back(std::move(mf));
                        }
                    }
                }
                if (!ok) {
                    ++st.oddFaces;
                    for (uint32_t f = f0 + 1; f < f1; ++f) unite(faces[f0].local, faces[f].local);
                }
            }
            f0 = f1;
        }
    }
    // One vertex per cycle, numbered by the cycle's first crossing (incidences are sorted).
    // The common single cycle needs no labels: every crossing is its own.
    uint32_t made[kSmall];
    std::vector<uint32_t>& madeMore = s.made;
    if (cycles > 1) {
        uint32_t next = 0;
        for (uint32_t j = 0; j < n; ++j) {
            const uint32_t r = find(j);
            cycleOf[j] = r == j ? next++ : cycleOf[r];
        }
        ++st.multiSheetCells;
    }
    uint32_t* madeAt = made;
    if (cycles > kSmall) {
        madeMore.resize(cycles);
        madeAt = madeMore.data();
    }
    for (uint32_t c = 0; c < cycles; ++c) madeAt[c] = tm.allocateVertex();
    st.verticesComputed += cycles;
    for (uint32_t c = 0; c < cycles; ++c) {
        const uint32_t vi = madeAt[c];
        Vertex& v = tm.vertices[vi];
        v.origin = origin;
        v.size = size;
        std::copy(corners, corners + 8, v.corners);
        v.nextInCell = c + 1 < cycles ? madeAt[c + 1] : UINT32_MAX;
        v.incBegin = uint32_t(tm.incidences.size());
        glm::vec3 mass(0.0f);
        for (uint32_t j = 0; j < n; ++j) {
            if (cycles > 1 && cycleOf[j] != c) continue;
            const Incidence& in = inc[j];
            tm.incidences.push_back({in.x, in.first, in.last});
            mass += in.x->point;
            for (uint8_t q = in.first;; q = uint8_t((q + 1) % 4)) {
                in.x->ringVertex[q] = {&tm, vi};
                if (q == in.last) break;
            }
        }
        v.incEnd = uint32_t(tm.incidences.size());
        mass /= float(v.incEnd - v.incBegin);
        tm.projected[vi].point = projectOnce(v, projectOnce(v, mass));
    }
    return madeAt[0];
}

/// Slot of the face between ring positions qA and qB (adjacent) in a crossing's split array.
inline int faceSlot(uint8_t qA, uint8_t qB) { return (qA + 1) % 4 == qB ? qA : qB; }

/// Where two segments of one face join the same two vertices, the dual mesh would use one edge
/// twice; every such segment but the first gets a vertex of its own, which the two polygons at
/// its ends include (they are then fanned around their centre). Needs the cycles of both cells.
void splitFaces(TileMesh& tm) {
    tm.splits.clear();
    for (const MultiFace& mf : tm.multiFaces) {
        std::vector<std::pair<uint64_t, uint64_t>> seen;
        for (const auto& [e, l] : mf.segments) {
            const VertexRef a = e.x->ringVertex[e.qA], b = e.x->ringVertex[e.qB];
            const std::pair<uint64_t, uint64_t> id{uint64_t(reinterpret_cast<uintptr_t>(a.tile)) ^ (uint64_t(a.index) << 1),
                                                   uint64_t(reinterpret_cast<uintptr_t>(b.tile)) ^ (uint64_t(b.index) << 1)};
            uint32_t split = Crossing::kNoSplit;
            if (std::find(seen.begin(), seen.end(), id) != seen.end()) {
                split = uint32_t(tm.splits.size());
                tm.splits.push_back({a, b});
            } else {
                seen.push_back(id);
            }
            e.x->split[faceSlot(e.qA, e.qB)] = split;
            l.x->split[faceSlot(l.qA, l.qB)] = split;
        }
    }
}

void relaxVertex(TileMesh& tm, uint32_t vi, UnmarkedNeighbours unmarked) {
    Vertex& v = tm.vertices[vi];
    auto projectedAt = [&](const VertexRef& r) -> const glm::vec3& {
        if (!r.tile) throw std::logic_error("surface nets: a neighbouring vertex was not computed");
        const Projected& w = r.tile->projected[r.index];
        if (unmarked.out && w.relaxStamp != unmarked.mark) unmarked.out->push_back(r);
        return w.point;
    };
    // The ring cells on both sides of each crossing's run (most neighbours come twice).
    glm::vec3 sum(0.0f);
    for (uint32_t i = v.incBegin; i < v.incEnd; ++i) {
        const VertexIncidence& c = tm.incidences[i];
        sum += projectedAt(c.x->ringVertex[(c.first + 3) % 4]);
        sum += projectedAt(c.x->ringVertex[(c.last + 1) % 4]);
    }
    const uint32_t count = 2 * (v.incEnd - v.incBegin);
    const glm::vec3 p = tm.projected[vi].point;
    const adf::Sample s = cellSample<true>(v, p);
    glm::vec3 moved = p;
    glm::vec3 gradient = s.gradient;  // the normal: gradient where the last projection started
    const float g = glm::length(s.gradient);
    if (count > 0 && g > 1e-12f) {
        const glm::vec3 n = s.gradient / g;
        const glm::vec3 d = sum / float(count) - p;
        moved = projectOnce<true>(v, clampToCell(p + 0.5f * (d - glm::dot(n, d) * n), v), &gradient);
    }
    Placed& out = tm.placed[vi];
    out.position = moved;
    const float ge = glm::length(gradient);
    if (ge > 1e-12f && std::isfinite(ge)) {
        out.normal = gradient / ge;
    } else {
        // The crossed edges' directions (whole numbers: the sum's order does not matter).
        glm::vec3 crossed(0.0f);
        for (uint32_t i = v.incBegin; i < v.incEnd; ++i) {
            const Crossing& x = *tm.incidences[i].x;
            glm::vec3 dir(0.0f);
            dir[x.axis] = x.startInside ? 1.0f : -1.0f;
            crossed += dir;
        }
        const float cn = glm::length(crossed);
        out.normal = cn > 0.0f ? crossed / cn : glm::vec3(0.0f, 0.0f, 1.0f);
    }
}

}  // namespace detail

namespace {

/// A build's `tm.border` (its crossings with a ring cell in another tile, by that tile's key)
/// and `tm.plainTriangles`, from its fresh crossings; the list is made in `scratch` and copied
/// once (grown in place, it was reallocated per tile as the leaves were).
void listBorder(const Adf& a, TileMesh& tm, std::vector<TileMesh::BorderRef>& scratch) {
    // A cell's slot, packed: its origin without the bits below a slot's size (masked to a
    // field's 20 bits: packLattice does not mask, and a wider value spills into the next field).
    const uint32_t slotShift = uint32_t(a.domain().maxLevel - a.domain().tileLevel());
    const uint64_t slotMask = packLattice(glm::uvec3((0xfffffu << slotShift) & 0xfffffu));
    // The tile of the last slot looked up: the cells beyond a tile's face mostly share one.
    uint64_t lastSlot = ~uint64_t(0), lastOwner = 0;
    const uint64_t tileKey = tm.key, outside = tm.outside;  // in locals: push_back may alias tm
    scratch.clear();
    uint32_t plain = 0;
    for (uint32_t j = 0; j < tm.crossings.size(); ++j) {
        const Crossing& x = tm.crossings[j];
        plain += plainTriangles(x);
        uint64_t owners[4];
        uint32_t n = 0;
        for (int q = 0; q < 4; ++q) {
            if (inTile(x.ringCell[q], tileKey, outside)) continue;
            const uint64_t slot = x.ringCell[q] & slotMask;
            if (slot != lastSlot) {
                lastSlot = slot;
                lastOwner = ownerKey(a, x.ringCell[q]);
            }
            if (std::find(owners, owners + n, lastOwner) != owners + n) continue;
            owners[n++] = lastOwner;
            scratch.push_back({lastOwner, j});
        }
    }
    tm.plainTriangles = plain;
    std::sort(scratch.begin(), scratch.end());
    tm.border.assign(scratch.begin(), scratch.end());
}

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

/// inHomes over tiles whose homes are set.
template <class Weight>
void inHomes(util::ThreadPool* pool, const std::vector<TileMesh*>& tiles, Weight weight,
             const std::function<void(std::size_t)>& fn) {
    inHomes(pool, tiles.size(), [&](std::size_t i) { return tiles[i]->home; }, weight, fn);
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
    // crossings, mostly share one) of about equal node counts. Each phase reads what the last
    // one wrote for the same tile, and from the other core such a read took 10-12 % of the
    // vertex and relaxation phases (docs/PERFORMANCE.md, "Twentieth session"). Within a
    // thread's share the largest tiles go first (one of a LOD's 8 tiles had ended phases alone;
    // "Thirteenth session"): the scan by nodes, the others by boundary leaves. A task writes
    // only its tile's records and its own quadrants of other tiles' crossings, so neither the
    // thread nor the order changes a result.
    // A scanned tile's TileMesh is made by its task (on its home thread, which uses it after).
    const std::size_t nScan = withSurface.size();
    std::vector<std::unique_ptr<TileMesh>> made(nScan);
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
        setTile(a, *withSurface[i], tm);
        tm.home = scanHome[i];
        // In walk order; walked into a warm per-thread buffer and copied once (grown in place,
        // the tile's vector was reallocated and copied seven times for 50 leaves).
        std::vector<BoundaryCell>& walked = vertexScratch().leaves;
        walked.clear();
        appendBoundaryCells(*tm.tile, a.domain().maxLevel, walked);
        tm.leaves.assign(walked.begin(), walked.end());
        scanStats[i].boundaryLeaves = tm.leaves.size();
        PoolAppender appender{tm.crossings};
        computeCrossings(a, *tm.tile, tm.leaves, appender, scanStats[i]);
        tm.liveCrossings = tm.crossings.size();
        listBorder(a, tm, vertexScratch().border);
        for (std::size_t b = 0; b < tm.border.size(); ++b) {
            if (b > 0 && tm.border[b].owner == tm.border[b - 1].owner) continue;
            const Tile& owner = *a.tileAtSlot(unpackLattice(tm.border[b].owner) >> slotShift);
            if (!mayEmit(owner)) unscannedOwners[i].push_back(tm.border[b].owner);
        }
    });
    mTiles.reserve(nScan + nScan / 8);
    std::vector<TileMesh*> scanTiles(nScan);
    for (std::size_t i = 0; i < nScan; ++i) {
        scanTiles[i] = made[i].get();
        mTiles.emplace(scanTiles[i]->key, std::move(made[i]));
    }
    st.tilesScanned = nScan;
    for (const SurfaceNetsStats& s : scanStats) {
        st.boundaryLeaves += s.boundaryLeaves;
        st.openCrossings += s.openCrossings;
        st.crossingsComputed += s.crossingsComputed;
    }

    const auto tPhase1 = std::chrono::steady_clock::now();
    // 2. Vertices of every tile owning a cell of a crossing (a tile with no boundary leaf can
    // still own one, figure 9B).
    TileIndex index;
    std::vector<TileMesh*>& meshTiles = index.tiles;
    meshTiles = scanTiles;
    for (const std::vector<uint64_t>& keys : unscannedOwners)
        for (uint64_t k : keys)
            if (!mTiles.count(k)) meshTiles.push_back(ensureTile(k));
    index.build(a);
    // A tile's boundary leaves: about its cells, so its vertices (taken now: relaxation drops them).
    std::vector<std::size_t> leaves(meshTiles.size());
    for (std::size_t i = 0; i < meshTiles.size(); ++i) leaves[i] = meshTiles[i]->leaves.size();
    auto byLeaves = [&](std::size_t i) { return leaves[i]; };
    std::vector<SurfaceNetsStats> meshStats(meshTiles.size());
    inHomes(mPool, meshTiles, byLeaves, [&](std::size_t i) {
        VertexScratch& s = vertexScratch();
        index.neighbours(a, *meshTiles[i], s.nbrMeshes, s.nbrs);
        computeVertices(a, *meshTiles[i], s.nbrMeshes, meshStats[i]);
    });
    st.tilesMeshed = meshTiles.size();
    for (const SurfaceNetsStats& s : meshStats) addVertexCounters(st, s);

    const auto tPhase2 = std::chrono::steady_clock::now();
    // 3. Relaxation reads neighbours' projected vertices.
    inHomes(mPool, meshTiles, byLeaves, [&](std::size_t i) {
        TileMesh& tm = *meshTiles[i];
        splitFaces(tm);
        relaxInOrder(tm.vertices.size(), [&](std::size_t k) { return VertexRef{&tm, uint32_t(k)}; });
        // What only a build needs.
        tm.leaves = {};
        tm.border = {};
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
}

SurfaceMesher::TileMesh* SurfaceMesher::ensureTile(uint64_t key) {
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

MeshBuffers meshAdf(adf::AdfPtr adf, util::ThreadPool* pool, SurfaceNetsStats* stats) {
    SurfaceMesher mesher(pool);
    mesher.build(std::move(adf));
    if (stats) *stats = mesher.stats();
    return mesher.mesh();
}

}  // namespace kizamu::mesh
