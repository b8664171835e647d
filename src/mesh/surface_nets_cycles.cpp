// SPDX-License-Identifier: Apache-2.0
/// @file surface_nets_cycles.cpp
/// @brief A cell's crossings -> its cycles -> one vertex per cycle (meshCell), for the build and
/// the update alike.
///
/// Takes in: one cell's incidences (the crossings on its boundary and the quadrants it fills
/// around each), sorted by crossing key, and its 8 corner distances. Produces: the cell's
/// vertices in its tile (one per cycle, at the mean of its crossings' points, projected twice
/// onto the cell's trilinear field), their incidence lists, the vertex refs in the crossings'
/// quadrants of this cell, and the cell's multi-crossing faces.
/// Complexity: O(n) per cell with n crossings on the two fast ways (nearly every cell), O(n log n)
/// on the general one. Threading: one call per cell; a task meshes the cells of one tile.
#include "mesh/surface_nets_cycles.h"

#include "mesh/surface_nets_cell.h"
#include "mesh/surface_nets_tile.h"

#include <algorithm>
#include <array>
#include <bit>

namespace kizamu::mesh::detail {

namespace {

/// The edge of kCellEdges along `axis` that the cell fills quadrant q around.
constexpr auto kEdgeAt = [] {
    std::array<std::array<uint8_t, 4>, 3> t{};
    for (int i = 0; i < 12; ++i) t[kCellEdges[i].axis][kCellEdges[i].quadrant] = uint8_t(i);
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

/// Lattice box of a ring cell.
inline void ringBox(const adf::Adf& adf, const Crossing& x, int q, glm::uvec3& lo, uint32_t& size) {
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

}  // namespace

bool oneSheetByCornerSigns(const Incidence* inc, uint32_t n, uint32_t cellSize, uint32_t inside) {
    // A crossing as long as the cell, with the cell in one quadrant around it, lies on the
    // cell's edge at that quadrant (edges start at multiples of their length).
    const uint32_t edges = kSignChangingEdges[inside];
    bool oneSheet = n == kOneSheetEdges[inside];  // n > 0
    for (uint32_t j = 0, seen = 0; j < n && oneSheet; ++j) {
        const Incidence& in = inc[j];
        const uint32_t bit = 1u << kEdgeAt[in.x->axis][in.first];
        oneSheet = in.x->length == cellSize && in.first == in.last && (edges & ~seen & bit);
        seen |= bit;
    }
    return oneSheet;
}

void cyclesOfFaceGroups(const adf::Adf& adf, const Incidence* inc, uint32_t n, CellScratch::FaceEntry* faces,
                        CycleSets& sets, CellScratch& s, std::vector<MultiFace>& multiFaces, SurfaceNetsStats& st) {
    const uint32_t nf = 2 * n;
    sets.separate();
    for (uint32_t f = 0; f < nf; ++f) faces[f] = {inc[f / 2].x->ringCell[faceRing(inc, f)], faceRing(inc, f), f / 2};
    // Group the entries by face (stable: within a face they stay in crossing order).
    auto before = [](const CellScratch::FaceEntry& l, const CellScratch::FaceEntry& r) {
        return l.neighbour < r.neighbour;
    };
    if (nf > 32) {
        std::stable_sort(faces, faces + nf, before);
    } else {
        for (uint32_t i = 1; i < nf; ++i) {
            const CellScratch::FaceEntry v = faces[i];
            uint32_t j = i;
            for (; j > 0 && before(v, faces[j - 1]); --j) faces[j] = faces[j - 1];
            faces[j] = v;
        }
    }
    for (uint32_t f0 = 0; f0 < nf;) {
        uint32_t f1 = f0 + 1;
        while (f1 < nf && faces[f1].neighbour == faces[f0].neighbour) ++f1;
        const uint32_t m = f1 - f0;
        if (m == 2) {
            sets.unite(faces[f0].local, faces[f0 + 1].local);
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
                    for (auto [e, l] : s.pairs) sets.unite(faces[f0 + e].local, faces[f0 + l].local);
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
                        multiFaces.push_back(std::move(mf));
                    }
                }
            }
            if (!ok) {
                ++st.oddFaces;
                for (uint32_t f = f0 + 1; f < f1; ++f) sets.unite(faces[f0].local, faces[f].local);
            }
        }
        f0 = f1;
    }
}

uint32_t meshCell(const adf::Adf& adf, TileMesh& tm, const Incidence* inc, uint32_t n, const float corners[8],
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
    CycleSets sets{parent, n, n};
    // This cell owns the faces toward larger keys: their split vertices are decided again
    // (splitFaces), so forget old ones (the crossing may be kept unchanged).
    if (!s.freshCrossings)
        for (uint32_t j = 0; j < n; ++j) {
            const Incidence& c = inc[j];
            const int qa = faceRing(inc, 2 * j), qb = faceRing(inc, 2 * j + 1);
            if (c.cell < c.x->ringCell[qa]) c.x->split[qa] = Crossing::kNoSplit;
            if (c.cell < c.x->ringCell[qb]) c.x->split[c.last] = Crossing::kNoSplit;
        }
    // The three ways, fastest first (surface_nets_cycles.h).
    if (oneSheetByCornerSigns(inc, n, size, insideCorners(corners)))
        sets.count = 1;
    else if (!cyclesOfPairedFaces(inc, n, sets))
        cyclesOfFaceGroups(adf, inc, n, faces, sets, s, tm.multiFaces, st);
    const uint32_t cycles = sets.count;
    // One vertex per cycle, numbered by the cycle's first crossing (incidences are sorted).
    // The common single cycle needs no labels: every crossing is its own.
    uint32_t made[kSmall];
    std::vector<uint32_t>& madeMore = s.made;
    if (cycles > 1) {
        uint32_t next = 0;
        for (uint32_t j = 0; j < n; ++j) {
            const uint32_t r = sets.find(j);
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
    const bool signless = !isBoundary(corners);
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
        // A cell whose corners share one sign (figure 9B: its crossings are its smaller
        // neighbours') has no zero set to project onto: projecting would run to a corner, where
        // every sheet of every such cell there would meet. Its vertex stays at its crossings' mean.
        tm.projected[vi].point = signless ? mass : projectOnce(v, projectOnce(v, mass));
    }
    return madeAt[0];
}

}  // namespace kizamu::mesh::detail
