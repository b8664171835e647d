// SPDX-License-Identifier: Apache-2.0
/// @file surface_nets.cpp
/// @brief Crossings per tile, cycles and vertices per tile, relaxation, splicing (surface_nets.h).
#include "mesh/surface_nets.h"

#include "mesh/boundary_cells.h"
#include "mesh/mesh_colours.h"
#include "util/thread_pool.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <chrono>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace kizamu::mesh {

using adf::Adf;
using adf::Tile;

namespace {

/// 20 bits per axis: lattice coordinates stay below 2^16 + 1.
inline uint64_t packLattice(glm::uvec3 p) {
    return uint64_t(p.x) | (uint64_t(p.y) << 20) | (uint64_t(p.z) << 40);
}
inline glm::uvec3 unpackLattice(uint64_t k) {
    return {uint32_t(k & 0xfffff), uint32_t((k >> 20) & 0xfffff), uint32_t((k >> 40) & 0xfffff)};
}


}  // namespace

/// A vertex's owner and index; filled in by the tile that owns the cell.
struct VertexRef {
    SurfaceMesher::TileMesh* tile = nullptr;
    uint32_t index = 0;
};

/// One sign-changing minimal edge and the leaves around it. Quadrants q0..q3 turn
/// counter-clockwise about +axis: (+a,+b), (-a,+b), (-a,-b), (+a,-b) with a, b the next axes.
struct Crossing {
    glm::uvec3 start{0};
    uint32_t length = 0;
    uint8_t axis = 0;
    uint8_t startInside = 0;  ///< start corner negative: the surface faces +axis
    uint8_t emitter = 0;      ///< quadrant of the smallest leaf (it emitted this record)
    uint8_t ringLevel[4] = {};
    uint64_t ringCell[4] = {};   ///< packed leaf origins
    uint64_t ringOwner[4] = {};  ///< packed origins of the tiles holding them
    glm::vec3 point{0.0f};       ///< zero crossing, lattice units
    VertexRef ringVertex[4];
    /// Extra vertex on the face between ring cells q and q+1, where that face carries two
    /// segments joining the same pair of vertices (set by the face's owner, see splitFaces).
    VertexRef split[4];

    uint64_t key() const { return packLattice(start) | (uint64_t(axis) << 60); }
    bool sameAs(const Crossing& o) const {
        return start == o.start && length == o.length && axis == o.axis && startInside == o.startInside &&
               emitter == o.emitter && std::equal(ringLevel, ringLevel + 4, o.ringLevel) &&
               std::equal(ringCell, ringCell + 4, o.ringCell) &&
               std::equal(ringOwner, ringOwner + 4, o.ringOwner) && point == o.point;
    }
};

namespace {

using BoundaryLeaf = BoundaryCell;

/// Quadrants a cell occupies around a crossing, as a cyclic run first..last.
struct Incidence {
    uint64_t cell;
    uint64_t crossingKey;
    Crossing* x;
    uint8_t first, last;
};

struct VertexIncidence {
    Crossing* x;
    uint8_t first, last;
};

struct Vertex {
    uint64_t cell = 0;
    glm::uvec3 origin{0};
    uint32_t size = 0;
    glm::vec3 projected{0.0f};  ///< after the first projection (what neighbours read)
    glm::vec3 position{0.0f};   ///< final, lattice units
    glm::vec3 normal{0.0f};
    glm::vec3 crossingNormal{0.0f};  ///< sum of the crossed edges' directions (fallback normal)
    float corners[8] = {};  ///< the cell's: projection reads the cell's own trilinear field
    uint32_t incBegin = 0, incEnd = 0;
};

struct CellLoc {
    const Tile* tile;
    glm::uvec3 origin;
    uint32_t size;
    int level;
};

/// The leaf containing a lattice point (like Adf::findLeaf, without decoding corners), with a
/// cached path: a query near the last one climbs only to their common cell.
class LeafLocator {
public:
    explicit LeafLocator(const Adf& adf)
        : mAdf(adf), mMaxLevel(adf.domain().maxLevel),
          mSlotShift(uint32_t(adf.domain().maxLevel - adf.domain().tileLevel())) {}

    CellLoc locate(glm::uvec3 p) {
        while (mDepth > 0 && !contains(mPath[mDepth - 1], p)) --mDepth;
        if (mDepth == 0) {
            mTile = mAdf.tileAtSlot(p >> mSlotShift);
            mPath[0] = {mTile->latticeOrigin(), 1u << uint32_t(mMaxLevel - mTile->level()), 0, mTile->level()};
            mDepth = 1;
        }
        const uint32_t* nodes = mTile->nodes();
        Entry e = mPath[mDepth - 1];
        uint32_t w = nodes[e.node];
        // Sizes are powers of two: shifts and masks, no divisions.
        while (adf::node::isInternal(w)) {
            const uint32_t shift = uint32_t(mMaxLevel - e.level - 1), half = 1u << shift;
            const glm::uvec3 bit = ((p - e.origin) >> shift) & 1u;
            e = {e.origin + (bit << shift), half, w + (bit.x | (bit.y << 1) | (bit.z << 2)), e.level + 1};
            mPath[mDepth++] = e;
            w = nodes[e.node];
        }
        if (adf::node::isBrick(w)) {
            const uint32_t shift = uint32_t(mMaxLevel - e.level - 1);
            return {mTile, (p >> shift) << shift, 1u << shift, e.level + 1};
        }
        return {mTile, e.origin, e.size, e.level};
    }

private:
    struct Entry {
        glm::uvec3 origin;
        uint32_t size;
        uint32_t node;
        int level;
    };
    static bool contains(const Entry& e, glm::uvec3 p) {
        const glm::uvec3 r = p - e.origin;  // wraps below the origin
        return r.x < e.size && r.y < e.size && r.z < e.size;
    }
    const Adf& mAdf;
    int mMaxLevel;
    uint32_t mSlotShift;
    const Tile* mTile = nullptr;
    int mDepth = 0;
    Entry mPath[adf::kMaxSupportedLevel + 2];
};

inline bool isBoundary(const float* c) {
    bool anyIn = false, anyOut = false;
    for (int i = 0; i < 8; ++i) (c[i] < 0.0f ? anyIn : anyOut) = true;
    return anyIn && anyOut;
}

template <class T>
void sortUnique(std::vector<T>& v) {
    std::sort(v.begin(), v.end());
    v.erase(std::unique(v.begin(), v.end()), v.end());
}

/// Disjoint sets over a handful of crossings of one cell.
struct SmallUnionFind {
    std::vector<uint32_t> parent;
    void reset(std::size_t n) {
        parent.resize(n);
        std::iota(parent.begin(), parent.end(), 0u);
    }
    uint32_t find(uint32_t i) {
        while (parent[i] != i) i = parent[i] = parent[parent[i]];
        return i;
    }
    void unite(uint32_t a, uint32_t b) {
        a = find(a);
        b = find(b);
        if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
};

}  // namespace

/// A face with four or more crossings, recorded by the cell with the smaller key: its segments
/// (crossing pairs) and the ring positions of the two cells in each crossing.
struct MultiFace {
    uint64_t cellA = 0, cellB = 0;
    struct End {
        Crossing* x;
        uint8_t qA, qB;  ///< ring positions of A and B next to each other
    };
    std::vector<std::pair<End, End>> segments;
};

/// A vertex splitting a doubled dual edge: placed half-way between its two ends.
struct SplitVertex {
    VertexRef a, b;
};

struct SurfaceMesher::TileMesh {
    const Tile* tile = nullptr;
    uint64_t key = 0;
    glm::uvec3 slotMin{0}, slotEnd{0};  ///< slots covered
    bool leavesScanned = false;
    std::vector<BoundaryLeaf> leaves;
    std::vector<Crossing> crossings;  ///< emitted by this tile's leaves, in leaf order
    /// Crossings with a leaf owned by another tile, by that tile's key: a neighbour gathering
    /// its cells' crossings reads only its own range instead of every border crossing.
    struct BorderRef {
        uint64_t owner;
        uint32_t index;
        bool operator<(const BorderRef& o) const { return owner != o.owner ? owner < o.owner : index < o.index; }
    };
    std::vector<BorderRef> border;
    std::vector<Vertex> vertices;     ///< by cell key, then cycle
    std::vector<VertexIncidence> incidences;
    std::vector<MultiFace> multiFaces;
    std::vector<SplitVertex> splits;  ///< numbered after `vertices`
    uint32_t offset = 0;  ///< first vertex in the assembled mesh
};

namespace {

using TileMesh = SurfaceMesher::TileMesh;

/// What one tile's tasks need to read.
struct Context {
    const Adf* adf;
    const std::unordered_map<uint64_t, std::unique_ptr<TileMesh>>* tiles;
};

/// Distinct tile keys whose slots touch (closed) the slot box [lo, end).
void neighbourKeys(const Adf& adf, glm::uvec3 lo, glm::uvec3 end, std::vector<uint64_t>& out) {
    const uint32_t n = adf.domain().slotsPerAxis();
    const glm::uvec3 a(lo.x ? lo.x - 1 : 0, lo.y ? lo.y - 1 : 0, lo.z ? lo.z - 1 : 0);
    const glm::uvec3 b(std::min(end.x + 1, n), std::min(end.y + 1, n), std::min(end.z + 1, n));
    const Tile* last = nullptr;
    for (uint32_t z = a.z; z < b.z; ++z)
        for (uint32_t y = a.y; y < b.y; ++y)
            for (uint32_t x = a.x; x < b.x; ++x) {
                const Tile* t = adf.tileAtSlot({x, y, z});
                if (t == last) continue;
                last = t;
                out.push_back(packLattice(t->latticeOrigin()));
            }
}

void slotBox(const Adf& adf, const Tile& t, glm::uvec3& lo, glm::uvec3& end) {
    const uint32_t shift = uint32_t(adf.domain().maxLevel - adf.domain().tileLevel());
    lo = t.latticeOrigin() >> shift;
    end = lo + glm::uvec3(1u << uint32_t(adf.domain().tileLevel() - t.level()));
}

void scanLeaves(const Adf& adf, TileMesh& tm) {
    tm.leaves.clear();
    appendBoundaryCells(*tm.tile, adf.domain().maxLevel, tm.leaves);
    std::sort(tm.leaves.begin(), tm.leaves.end(), [](const BoundaryLeaf& l, const BoundaryLeaf& r) {
        return packLattice(l.origin) < packLattice(r.origin);
    });
}

/// The crossings emitted by `tm`'s boundary leaves.
void computeCrossings(const Adf& adf, const TileMesh& tm, std::vector<Crossing>& out, SurfaceNetsStats& st) {
    const uint32_t top = adf.domain().latticeSize();
    LeafLocator locator(adf);
    for (const BoundaryLeaf& leaf : tm.leaves) {
        for (int k = 0; k < 3; ++k) {
            const int a = (k + 1) % 3, b = (k + 2) % 3;
            for (int c0 = 0; c0 < 8; ++c0) {
                if ((c0 >> k) & 1) continue;
                const int c1 = c0 | (1 << k);
                const bool in0 = leaf.corners[c0] < 0.0f, in1 = leaf.corners[c1] < 0.0f;
                if (in0 == in1) continue;
                const glm::uvec3 corner(c0 & 1, (c0 >> 1) & 1, c0 >> 2);
                const glm::uvec3 p = leaf.origin + corner * leaf.size;
                const bool plusA = corner[a] == 0, plusB = corner[b] == 0;
                const int mine = plusA ? (plusB ? 0 : 3) : (plusB ? 1 : 2);
                // Leaf at each quadrant: the one holding the unit cube next to p there.
                bool open = false, skip = false;
                CellLoc ring[4];
                for (int q = 0; q < 4 && !skip; ++q) {
                    if (q == mine) continue;
                    const bool qa = (q == 0 || q == 3), qb = (q == 0 || q == 1);
                    glm::uvec3 s = p;
                    if (!qa) {
                        if (s[a] == 0) { open = true; break; }
                        s[a] -= 1;
                    }
                    if (!qb) {
                        if (s[b] == 0) { open = true; break; }
                        s[b] -= 1;
                    }
                    if (s[a] >= top || s[b] >= top) { open = true; break; }
                    const glm::uvec3 parent = leaf.origin & ~glm::uvec3(2 * leaf.size - 1);
                    if (leaf.brickChild && glm::all(glm::lessThan(s - parent, glm::uvec3(2 * leaf.size)))) {
                        // A sibling in the same brick: same size, same tile.
                        ring[q] = {nullptr, s & ~glm::uvec3(leaf.size - 1), leaf.size, 0};
                    } else {
                        ring[q] = locator.locate(s);
                    }
                    // Not minimal: a smaller leaf splits this edge. Not canonical: an equal
                    // leaf earlier in quadrant order emits it.
                    if (ring[q].size < leaf.size || (ring[q].size == leaf.size && q < mine)) skip = true;
                }
                if (open) {
                    ++st.openCrossings;
                    continue;
                }
                if (skip) continue;
                Crossing x;
                x.start = p;
                x.length = leaf.size;
                x.axis = uint8_t(k);
                x.startInside = in0;
                x.emitter = uint8_t(mine);
                for (int q = 0; q < 4; ++q) {
                    if (q == mine) {
                        x.ringCell[q] = packLattice(leaf.origin);
                        x.ringOwner[q] = tm.key;
                        x.ringLevel[q] = uint8_t(adf.domain().maxLevel - std::countr_zero(leaf.size));
                    } else if (!ring[q].tile) {  // brick sibling
                        x.ringCell[q] = packLattice(ring[q].origin);
                        x.ringOwner[q] = tm.key;
                        x.ringLevel[q] = uint8_t(adf.domain().maxLevel - std::countr_zero(leaf.size));
                    } else {
                        x.ringCell[q] = packLattice(ring[q].origin);
                        x.ringOwner[q] = packLattice(ring[q].tile->latticeOrigin());
                        x.ringLevel[q] = uint8_t(ring[q].level);
                    }
                }
                const float v0 = leaf.corners[c0], v1 = leaf.corners[c1];
                const float t = v0 / (v0 - v1);
                x.point = glm::vec3(p);
                x.point[k] += t * float(leaf.size);
                out.push_back(x);
            }
        }
    }
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
        glm::dvec3 mid(x.start);
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

/// One Newton step onto the zero set along the gradient, in lattice units, kept in the cell.
/// The cell's trilinear field at lattice point `p`: distance (m) and gradient (m per lattice unit).
inline adf::Sample cellSample(const Vertex& v, glm::vec3 p) {
    const float inv = 1.0f / float(v.size);
    adf::Sample s = adf::trilinear(v.corners, (p - glm::vec3(v.origin)) * inv);
    s.gradient *= inv;
    return s;
}

/// One Newton step onto the cell's zero set along its gradient, in lattice units, kept in the
/// cell. Reads only the cell's corners: inside its box that is the field itself.
inline glm::vec3 projectOnce(const Vertex& v, glm::vec3 p, glm::vec3* gradient = nullptr) {
    const adf::Sample s = cellSample(v, p);
    if (gradient) *gradient = s.gradient;
    const float g2 = glm::dot(s.gradient, s.gradient);
    if (!(g2 > 1e-20f) || !std::isfinite(s.distance)) return p;
    return clampToCell(p - (s.distance / g2) * s.gradient, v);
}

/// Incidences of cell-owner `tm`: crossings in its own list and its neighbours' border lists
/// that have a leaf owned by it.
void gatherIncidences(const Context& ctx, const TileMesh& tm, const std::vector<uint64_t>& nbrs,
                      std::vector<Incidence>& out) {
    auto take = [&](Crossing& x) {
        uint8_t done = 0;
        for (int q = 0; q < 4; ++q) {
            if (x.ringOwner[q] != tm.key || ((done >> q) & 1)) continue;
            uint8_t mask = 0;
            for (int r = 0; r < 4; ++r)
                if (x.ringCell[r] == x.ringCell[q]) mask |= uint8_t(1u << r);
            done |= mask;
            uint8_t first = 0;
            while (!((mask >> first) & 1) || ((mask >> ((first + 3) % 4)) & 1)) ++first;
            uint8_t last = first;
            while ((mask >> ((last + 1) % 4)) & 1) last = uint8_t((last + 1) % 4);
            out.push_back({x.ringCell[q], x.key(), &x, first, last});
        }
    };
    for (uint64_t k : nbrs) {
        auto it = ctx.tiles->find(k);
        if (it == ctx.tiles->end()) continue;
        TileMesh& src = *it->second;
        if (src.key == tm.key) {
            for (Crossing& x : src.crossings) take(x);
        } else {
            auto b = std::lower_bound(src.border.begin(), src.border.end(), TileMesh::BorderRef{tm.key, 0});
            for (; b != src.border.end() && b->owner == tm.key; ++b) take(src.crossings[b->index]);
        }
    }
    // Group by cell, keeping the gathering order inside a cell (it is the same in every run:
    // neighbour tiles in key order, their crossings in leaf order). Cells of a stored tile have
    // 8-bit local coordinates: three counting passes instead of a comparison sort.
    const uint32_t extent = 1u << uint32_t(ctx.adf->domain().maxLevel - tm.tile->level());
    if (extent > 256) {
        std::stable_sort(out.begin(), out.end(), [](const Incidence& l, const Incidence& r) { return l.cell < r.cell; });
        return;
    }
    const glm::uvec3 o = tm.tile->latticeOrigin();
    auto local = [&](uint64_t c) {
        const glm::uvec3 r = unpackLattice(c) - o;
        return r.x | (r.y << 8) | (r.z << 16);
    };
    std::vector<Incidence> tmp(out.size());
    for (int pass = 0; pass < 3; ++pass) {
        uint32_t count[257] = {};
        const int shift = 8 * pass;
        for (const Incidence& i : out) ++count[((local(i.cell) >> shift) & 255u) + 1];
        for (int b = 0; b < 256; ++b) count[b + 1] += count[b];
        for (const Incidence& i : out) tmp[count[(local(i.cell) >> shift) & 255u]++] = i;
        out.swap(tmp);
    }
}

/// Cycles and projected vertices of the cells `tm` owns; writes their refs into the crossings.
void computeVertices(const Context& ctx, TileMesh& tm, const std::vector<uint64_t>& nbrs, SurfaceNetsStats& st) {
    const Adf& adf = *ctx.adf;
    std::vector<Incidence> inc;
    gatherIncidences(ctx, tm, nbrs, inc);
    tm.vertices.clear();
    tm.incidences.clear();
    tm.multiFaces.clear();
    SmallUnionFind uf;
    std::size_t leafAt = 0;  // tm.leaves is sorted by cell key, like the incidences
    struct FaceEntry {
        uint64_t neighbour;
        int q;  ///< ring position of the neighbour
        uint32_t local;
    };
    std::vector<FaceEntry> faces;
    std::vector<const Crossing*> faceXs;
    std::vector<std::pair<uint32_t, uint32_t>> pairs;
    std::vector<uint32_t> cycleOf;
    for (std::size_t i0 = 0; i0 < inc.size();) {
        std::size_t i1 = i0;
        while (i1 < inc.size() && inc[i1].cell == inc[i0].cell) ++i1;
        const uint32_t n = uint32_t(i1 - i0);
        uf.reset(n);
        faces.clear();
        for (uint32_t j = 0; j < n; ++j) {
            const Incidence& c = inc[i0 + j];
            const int qa = (c.first + 3) % 4, qb = (c.last + 1) % 4;
            faces.push_back({c.x->ringCell[qa], qa, j});
            faces.push_back({c.x->ringCell[qb], qb, j});
            // This cell owns the faces toward larger keys: their split vertices are decided
            // again (splitFaces), so forget old ones (the crossing may be kept unchanged).
            if (c.cell < c.x->ringCell[qa]) c.x->split[qa] = {};
            if (c.cell < c.x->ringCell[qb]) c.x->split[c.last] = {};
        }
        // Most faces carry exactly two crossings: pair those directly, sort only the rest.
        {
            const std::size_t m = faces.size();
            uint32_t partner[64];
            const bool small = m <= 64;
            if (small) {
                for (std::size_t a = 0; a < m; ++a) {
                    std::size_t match = SIZE_MAX, matches = 0;
                    for (std::size_t b = 0; b < m; ++b)
                        if (b != a && faces[b].neighbour == faces[a].neighbour) {
                            match = b;
                            ++matches;
                        }
                    partner[a] = matches == 1 ? uint32_t(match) : UINT32_MAX;
                }
                std::size_t keep = 0;
                for (std::size_t a = 0; a < m; ++a) {
                    if (partner[a] == UINT32_MAX) {
                        faces[keep++] = faces[a];
                    } else if (partner[a] > a) {
                        uf.unite(faces[a].local, faces[partner[a]].local);
                    }
                }
                faces.resize(keep);
            }
        }
        std::sort(faces.begin(), faces.end(), [](const FaceEntry& l, const FaceEntry& r) {
            return l.neighbour != r.neighbour ? l.neighbour < r.neighbour : l.local < r.local;
        });
        for (std::size_t f0 = 0; f0 < faces.size();) {
            std::size_t f1 = f0;
            while (f1 < faces.size() && faces[f1].neighbour == faces[f0].neighbour) ++f1;
            const std::size_t m = f1 - f0;
            if (m == 2) {
                uf.unite(faces[f0].local, faces[f0 + 1].local);
            } else {
                bool ok = false;
                if (m >= 4 && m % 2 == 0) {
                    ++st.multiCrossingFaces;
                    const Incidence& any = inc[i0 + faces[f0].local];
                    glm::uvec3 loA, loB;
                    uint32_t sizeA, sizeB;
                    ringBox(adf, *any.x, any.first, loA, sizeA);
                    ringBox(adf, *any.x, faces[f0].q, loB, sizeB);
                    faceXs.clear();
                    pairs.clear();
                    for (std::size_t f = f0; f < f1; ++f) faceXs.push_back(inc[i0 + faces[f].local].x);
                    ok = pairOnFace(loA, sizeA, loB, sizeB, faceXs, pairs);
                    if (ok) {
                        for (auto [e, l] : pairs) uf.unite(faces[f0 + e].local, faces[f0 + l].local);
                        if (inc[i0].cell < faces[f0].neighbour) {
                            MultiFace mf;
                            mf.cellA = inc[i0].cell;
                            mf.cellB = faces[f0].neighbour;
                            auto end = [&](uint32_t e) {
                                const FaceEntry& fe = faces[f0 + e];
                                const Incidence& c = inc[i0 + fe.local];
                                const uint8_t qB = uint8_t(fe.q);
                                const uint8_t qA = qB == (c.first + 3) % 4 ? c.first : c.last;
                                return MultiFace::End{c.x, qA, qB};
                            };
                            for (auto [e, l] : pairs) mf.segments.emplace_back(end(e), end(l));
                            tm.multiFaces.push_back(std::move(mf));
                        }
                    }
                }
                if (!ok) {
                    ++st.oddFaces;
                    for (std::size_t f = f0 + 1; f < f1; ++f) uf.unite(faces[f0].local, faces[f].local);
                }
            }
            f0 = f1;
        }
        // One vertex per cycle, numbered by the cycle's first crossing (incidences are sorted).
        cycleOf.assign(n, UINT32_MAX);
        const uint32_t firstVertex = uint32_t(tm.vertices.size());
        for (uint32_t j = 0; j < n; ++j) {
            const uint32_t r = uf.find(j);
            if (cycleOf[r] == UINT32_MAX) {
                cycleOf[r] = uint32_t(tm.vertices.size());
                Vertex v;
                v.cell = inc[i0].cell;
                ringBox(adf, *inc[i0 + j].x, inc[i0 + j].first, v.origin, v.size);
                tm.vertices.push_back(v);
            }
        }
        // The cell's corners: a boundary leaf of this tile, or (figure 9B) looked up.
        while (leafAt < tm.leaves.size() && packLattice(tm.leaves[leafAt].origin) < inc[i0].cell) ++leafAt;
        const bool known = leafAt < tm.leaves.size() && packLattice(tm.leaves[leafAt].origin) == inc[i0].cell;
        float corners[8];
        if (known) {
            std::copy(tm.leaves[leafAt].corners, tm.leaves[leafAt].corners + 8, corners);
        } else {
            const adf::LeafRef r = adf.findLeaf(tm.vertices[firstVertex].origin);
            std::copy(r.corners, r.corners + 8, corners);
            if (!isBoundary(corners)) ++st.signlessCells;
        }
        for (uint32_t vi = firstVertex; vi < tm.vertices.size(); ++vi)
            std::copy(corners, corners + 8, tm.vertices[vi].corners);
        if (tm.vertices.size() - firstVertex > 1) ++st.multiSheetCells;
        for (uint32_t vi = firstVertex; vi < tm.vertices.size(); ++vi) {
            Vertex& v = tm.vertices[vi];
            v.incBegin = uint32_t(tm.incidences.size());
            glm::vec3 mass(0.0f);
            for (uint32_t j = 0; j < n; ++j) {
                if (cycleOf[uf.find(j)] != vi) continue;
                const Incidence& c = inc[i0 + j];
                tm.incidences.push_back({c.x, c.first, c.last});
                mass += c.x->point;
                glm::vec3 dir(0.0f);
                dir[c.x->axis] = c.x->startInside ? 1.0f : -1.0f;
                v.crossingNormal += dir;
                for (uint8_t q = c.first;; q = uint8_t((q + 1) % 4)) {
                    c.x->ringVertex[q] = {&tm, vi};
                    if (q == c.last) break;
                }
            }
            v.incEnd = uint32_t(tm.incidences.size());
            mass /= float(v.incEnd - v.incBegin);
            v.projected = projectOnce(v, projectOnce(v, mass));
        }
        i0 = i1;
    }
}

/// Slot of the face between ring positions qA and qB (adjacent) in a crossing's split array.
inline int faceSlot(uint8_t qA, uint8_t qB) { return (qA + 1) % 4 == qB ? qA : qB; }

/// Where two segments of one face join the same two vertices, the dual mesh would use one edge
/// twice; every such segment but the first gets a vertex of its own, which the two polygons at
/// its ends include (they are then fanned around their centre). Needs the cycles of both cells.
void splitFaces(TileMesh& tm) {
    tm.splits.clear();
    const uint32_t base = uint32_t(tm.vertices.size());
    for (const MultiFace& mf : tm.multiFaces) {
        std::vector<std::pair<uint64_t, uint64_t>> seen;
        for (const auto& [e, l] : mf.segments) {
            const VertexRef a = e.x->ringVertex[e.qA], b = e.x->ringVertex[e.qB];
            const std::pair<uint64_t, uint64_t> id{uint64_t(reinterpret_cast<uintptr_t>(a.tile)) ^ (uint64_t(a.index) << 1),
                                                   uint64_t(reinterpret_cast<uintptr_t>(b.tile)) ^ (uint64_t(b.index) << 1)};
            VertexRef split;
            if (std::find(seen.begin(), seen.end(), id) != seen.end()) {
                split = {&tm, base + uint32_t(tm.splits.size())};
                tm.splits.push_back({a, b});
            } else {
                seen.push_back(id);
            }
            e.x->split[faceSlot(e.qA, e.qB)] = split;
            l.x->split[faceSlot(l.qA, l.qB)] = split;
        }
    }
}

/// Tangential relaxation toward the neighbours' mean, projection, normals.
void relaxVertices(TileMesh& tm) {
    for (Vertex& v : tm.vertices) {
        glm::vec3 sum(0.0f);
        uint32_t count = 0;
        for (uint32_t i = v.incBegin; i < v.incEnd; ++i) {
            const VertexIncidence& c = tm.incidences[i];
            for (int q : {(c.first + 3) % 4, (c.last + 1) % 4}) {
                const VertexRef r = c.x->ringVertex[q];
                if (!r.tile) throw std::logic_error("surface nets: a neighbouring vertex was not computed");
                sum += r.tile->vertices[r.index].projected;
                ++count;
            }
        }
        const glm::vec3 p = v.projected;
        const adf::Sample s = cellSample(v, p);
        glm::vec3 moved = p;
        glm::vec3 gradient = s.gradient;  // the normal: gradient where the last projection started
        const float g = glm::length(s.gradient);
        if (count > 0 && g > 1e-12f) {
            const glm::vec3 n = s.gradient / g;
            const glm::vec3 d = sum / float(count) - p;
            moved = projectOnce(v, clampToCell(p + 0.5f * (d - glm::dot(n, d) * n), v), &gradient);
        }
        v.position = moved;
        const float ge = glm::length(gradient);
        if (ge > 1e-12f && std::isfinite(ge)) {
            v.normal = gradient / ge;
        } else {
            const float cn = glm::length(v.crossingNormal);
            v.normal = cn > 0.0f ? v.crossingNormal / cn : glm::vec3(0.0f, 0.0f, 1.0f);
        }
    }
}

}  // namespace

SurfaceMesher::SurfaceMesher(util::ThreadPool* pool) : mPool(pool) {}
SurfaceMesher::~SurfaceMesher() = default;

void SurfaceMesher::build(adf::AdfPtr adf) {
    if (!adf) throw std::invalid_argument("surface nets: no snapshot");
    mTiles.clear();
    mAdf = std::move(adf);
    rebuild({}, true);
}

void SurfaceMesher::update(adf::AdfPtr adf) {
    if (!adf) throw std::invalid_argument("surface nets: no snapshot");
    if (!mAdf || !(adf->domain() == mAdf->domain())) {
        build(std::move(adf));
        return;
    }
    // Tiles the new snapshot does not share with the old one, and old tiles that are gone.
    std::vector<uint64_t> dirty;
    const Adf& oldAdf = *mAdf;
    const uint32_t shift = uint32_t(adf->domain().maxLevel - adf->domain().tileLevel());
    adf->forEachTile([&](const Tile& t) {
        if (oldAdf.tileAtSlot(t.latticeOrigin() >> shift) != &t) dirty.push_back(packLattice(t.latticeOrigin()));
    });
    for (const auto& [key, tm] : mTiles) {
        const Tile* now = adf->tileAtSlot(tm->slotMin);
        if (now != tm->tile) dirty.push_back(key);
    }
    mAdf = std::move(adf);
    rebuild(dirty, false);
}

void SurfaceMesher::rebuild(const std::vector<uint64_t>& dirtyIn, bool everything) {
    const auto tStart = std::chrono::steady_clock::now();
    const Adf& adf = *mAdf;
    SurfaceNetsStats st;
    const uint32_t shift = uint32_t(adf.domain().maxLevel - adf.domain().tileLevel());
    auto tileOfKey = [&](uint64_t key) -> const Tile* {
        const Tile* t = adf.tileAtSlot(unpackLattice(key) >> shift);
        return packLattice(t->latticeOrigin()) == key ? t : nullptr;
    };
    auto neighbours = [&](uint64_t key, std::vector<uint64_t>& out) {
        glm::uvec3 lo, end;
        if (const Tile* t = tileOfKey(key)) {
            slotBox(adf, *t, lo, end);
        } else {
            const TileMesh& tm = *mTiles.at(key);  // a tile that is gone: its old slots
            lo = tm.slotMin;
            end = tm.slotEnd;
        }
        neighbourKeys(adf, lo, end, out);
    };
    auto ensure = [&](uint64_t key) -> TileMesh* {
        auto it = mTiles.find(key);
        if (it != mTiles.end()) return it->second.get();
        const Tile* t = tileOfKey(key);
        if (!t) return nullptr;
        auto tm = std::make_unique<TileMesh>();
        tm->key = key;
        tm->tile = t;
        slotBox(adf, *t, tm->slotMin, tm->slotEnd);
        TileMesh* raw = tm.get();
        mTiles.emplace(key, std::move(tm));
        return raw;
    };

    // 1. Crossings of the dirty tiles and their neighbours (their border edges read the dirty ones).
    std::vector<uint64_t> dirty = dirtyIn, scan;
    if (everything) {
        adf.forEachTile([&](const Tile& t) {
            if (!(t.singleLeaf() && t.rootType() != adf::CellType::Boundary)) scan.push_back(packLattice(t.latticeOrigin()));
        });
    } else {
        for (uint64_t k : dirty) neighbours(k, scan);
    }
    sortUnique(dirty);
    sortUnique(scan);
    const std::vector<uint64_t> dirtyNeighbours = scan;
    // Tiles that are gone are dropped; crossings that pointed at their cells are all rescanned.
    for (uint64_t k : dirty)
        if (!tileOfKey(k)) mTiles.erase(k);
    std::vector<TileMesh*> scanTiles;
    for (uint64_t k : scan) {
        const Tile* t = tileOfKey(k);
        if (!t) continue;
        auto it = mTiles.find(k);
        if (it == mTiles.end() && t->singleLeaf() && t->rootType() != adf::CellType::Boundary) continue;
        TileMesh* tm = ensure(k);
        if (tm->tile != t) {
            tm->tile = t;
            tm->leavesScanned = false;
            slotBox(adf, *t, tm->slotMin, tm->slotEnd);
        }
        scanTiles.push_back(tm);
    }
    std::vector<uint8_t> changed(scanTiles.size(), 0);
    std::vector<SurfaceNetsStats> scanStats(scanTiles.size());
    std::vector<std::vector<Crossing>> fresh(scanTiles.size());
    util::parallelFor(mPool, scanTiles.size(), [&](std::size_t i) {
        TileMesh& tm = *scanTiles[i];
        if (!tm.leavesScanned) {
            scanLeaves(adf, tm);
            tm.leavesScanned = true;
        }
        scanStats[i].boundaryLeaves = tm.leaves.size();
        computeCrossings(adf, tm, fresh[i], scanStats[i]);
        const bool same = !everything && fresh[i].size() == tm.crossings.size() &&
                          std::equal(fresh[i].begin(), fresh[i].end(), tm.crossings.begin(),
                                     [](const Crossing& l, const Crossing& r) { return l.sameAs(r); });
        if (!same) {
            tm.crossings.swap(fresh[i]);
            tm.border.clear();
            for (uint32_t j = 0; j < tm.crossings.size(); ++j) {
                const Crossing& x = tm.crossings[j];
                for (int q = 0; q < 4; ++q)
                    if (x.ringOwner[q] != tm.key && std::find(x.ringOwner, x.ringOwner + q, x.ringOwner[q]) == x.ringOwner + q)
                        tm.border.push_back({x.ringOwner[q], j});
            }
            std::sort(tm.border.begin(), tm.border.end());
            changed[i] = 1;
        }
        fresh[i] = {};
    });
    st.tilesScanned = scanTiles.size();
    for (const SurfaceNetsStats& s : scanStats) {
        st.boundaryLeaves += s.boundaryLeaves;
        st.openCrossings += s.openCrossings;
    }

    const auto tPhase1 = std::chrono::steady_clock::now();
    // 2. Vertices of every tile that owns a cell of a changed crossing, or whose field changed.
    std::vector<uint64_t> meshKeys = dirtyNeighbours, owners;
    for (std::size_t i = 0; i < scanTiles.size(); ++i) {
        if (!changed[i]) continue;
        owners.push_back(scanTiles[i]->key);
        for (const TileMesh::BorderRef& b : scanTiles[i]->border)
            if (owners.back() != b.owner) owners.push_back(b.owner);
        if (!everything) neighbours(scanTiles[i]->key, meshKeys);
    }
    sortUnique(owners);
    std::vector<TileMesh*> meshTiles;
    if (everything) {
        // Every tile is new: mesh all of them (owners first get their entries).
        for (uint64_t k : owners) ensure(k);
        for (const auto& [key, tm] : mTiles) meshTiles.push_back(tm.get());
        std::sort(meshTiles.begin(), meshTiles.end(), [](const TileMesh* l, const TileMesh* r) { return l->key < r->key; });
    } else {
        meshKeys.insert(meshKeys.end(), owners.begin(), owners.end());
        sortUnique(meshKeys);
        for (uint64_t k : meshKeys) {
            auto it = mTiles.find(k);
            TileMesh* tm = it != mTiles.end() ? it->second.get() : nullptr;
            // A tile with no boundary leaf can still own a cell that crossings touch (figure 9B).
            if (!tm && std::binary_search(owners.begin(), owners.end(), k)) tm = ensure(k);
            if (tm) meshTiles.push_back(tm);
        }
    }
    const Context ctx{&adf, &mTiles};
    std::vector<SurfaceNetsStats> meshStats(meshTiles.size());
    util::parallelFor(mPool, meshTiles.size(), [&](std::size_t i) {
        std::vector<uint64_t> nbrs;
        neighbourKeys(adf, meshTiles[i]->slotMin, meshTiles[i]->slotEnd, nbrs);
        sortUnique(nbrs);  // a coarse tile covers several slots
        computeVertices(ctx, *meshTiles[i], nbrs, meshStats[i]);
    });
    st.tilesMeshed = meshTiles.size();
    for (const SurfaceNetsStats& s : meshStats) {
        st.multiSheetCells += s.multiSheetCells;
        st.multiCrossingFaces += s.multiCrossingFaces;
        st.oddFaces += s.oddFaces;
        st.signlessCells += s.signlessCells;
    }

    const auto tPhase2 = std::chrono::steady_clock::now();
    // 3. Relaxation reads neighbours' projected vertices: the meshed tiles and their neighbours.
    std::vector<TileMesh*> relaxTiles;
    if (everything) {
        for (TileMesh* tm : meshTiles)
            if (!tm->vertices.empty()) relaxTiles.push_back(tm);
    } else {
        std::vector<uint64_t> relaxKeys;
        for (TileMesh* tm : meshTiles) neighbourKeys(adf, tm->slotMin, tm->slotEnd, relaxKeys);
        sortUnique(relaxKeys);
        for (uint64_t k : relaxKeys) {
            auto it = mTiles.find(k);
            if (it != mTiles.end() && !it->second->vertices.empty()) relaxTiles.push_back(it->second.get());
        }
    }
    util::parallelFor(mPool, relaxTiles.size(), [&](std::size_t i) {
        splitFaces(*relaxTiles[i]);
        relaxVertices(*relaxTiles[i]);
    });

    const auto tPhase3 = std::chrono::steady_clock::now();
    auto ms = [](auto from, auto to) { return std::chrono::duration<double, std::milli>(to - from).count(); };
    st.crossingMs = ms(tStart, tPhase1);
    st.vertexMs = ms(tPhase1, tPhase2);
    st.relaxMs = ms(tPhase2, tPhase3);
    // Drop tiles left with nothing.
    for (auto it = mTiles.begin(); it != mTiles.end();) {
        if (it->second->crossings.empty() && it->second->vertices.empty())
            it = mTiles.erase(it);
        else
            ++it;
    }
    for (const auto& [key, tm] : mTiles) {
        st.crossings += tm->crossings.size();
        st.vertices += tm->vertices.size();
        st.splitEdges += tm->splits.size();
    }
    mStats = st;
}

MeshBuffers SurfaceMesher::mesh() const {
    MeshBuffers m;
    if (!mAdf) return m;
    std::vector<TileMesh*> order;
    order.reserve(mTiles.size());
    for (const auto& [key, tm] : mTiles) order.push_back(tm.get());
    std::sort(order.begin(), order.end(), [](const TileMesh* l, const TileMesh* r) { return l->key < r->key; });
    std::size_t vertices = 0, crossings = 0;
    for (TileMesh* tm : order) {
        tm->offset = uint32_t(vertices);
        vertices += tm->vertices.size() + tm->splits.size();
        crossings += tm->crossings.size();
    }
    m.positions.reserve(vertices);
    m.normals.reserve(vertices);
    m.indices.reserve(crossings * 6);
    const glm::dvec3 origin = mAdf->domain().originWorld;
    const double h = mAdf->domain().finestCellSize();
    auto world = [&](const glm::vec3& lattice) { return glm::vec3(origin + glm::dvec3(lattice) * h); };
    for (const TileMesh* tm : order) {
        for (const Vertex& v : tm->vertices) {
            m.positions.push_back(world(v.position));
            m.normals.push_back(v.normal);
        }
        for (const SplitVertex& sv : tm->splits) {
            const Vertex& a = sv.a.tile->vertices[sv.a.index];
            const Vertex& b = sv.b.tile->vertices[sv.b.index];
            m.positions.push_back(world(0.5f * (a.position + b.position)));
            const glm::vec3 n = a.normal + b.normal;
            m.normals.push_back(glm::dot(n, n) > 0.0f ? glm::normalize(n) : a.normal);
        }
    }
    auto index = [](const VertexRef& r) {
        if (!r.tile) throw std::logic_error("surface nets: a crossing has no vertex");
        return r.tile->offset + r.index;
    };
    std::vector<uint32_t> polygon;
    for (const TileMesh* tm : order)
        for (const Crossing& x : tm->crossings) {
            auto emit = [&](uint32_t a, uint32_t b, uint32_t c) {
                if (x.startInside) {
                    m.indices.insert(m.indices.end(), {a, b, c});
                } else {
                    m.indices.insert(m.indices.end(), {a, c, b});
                }
            };
            // The dual polygon in ring order, with any split vertices on its sides.
            polygon.clear();
            bool split = false;
            for (int q = 0; q < 4; ++q) {
                if (x.ringCell[q] != x.ringCell[(q + 3) % 4]) polygon.push_back(index(x.ringVertex[q]));
                if (x.split[q].tile && x.ringCell[q] != x.ringCell[(q + 1) % 4]) {
                    polygon.push_back(index(x.split[q]));
                    split = true;
                }
            }
            if (split) {
                // Fan around a new centre: its edges cannot coincide with any other.
                glm::vec3 c(0.0f), n(0.0f);
                for (uint32_t v : polygon) {
                    c += m.positions[v];
                    n += m.normals[v];
                }
                const uint32_t centre = uint32_t(m.positions.size());
                m.positions.push_back(c / float(polygon.size()));
                m.normals.push_back(glm::dot(n, n) > 0.0f ? glm::normalize(n) : glm::vec3(0.0f, 0.0f, 1.0f));
                for (std::size_t i = 0; i < polygon.size(); ++i)
                    emit(centre, polygon[i], polygon[(i + 1) % polygon.size()]);
            } else if (polygon.size() == 3) {
                emit(polygon[0], polygon[1], polygon[2]);
            } else {
                // Split along the diagonal through the smallest leaf (the emitter).
                const int e = x.emitter;
                const uint32_t i0 = index(x.ringVertex[e]), i1 = index(x.ringVertex[(e + 1) % 4]),
                               i2 = index(x.ringVertex[(e + 2) % 4]), i3 = index(x.ringVertex[(e + 3) % 4]);
                emit(i0, i1, i2);
                emit(i0, i2, i3);
            }
        }
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
