// SPDX-License-Identifier: Apache-2.0
/// @file surface_nets_cycles.h
/// @brief A cell's crossings -> its cycles -> its vertices (meshCell), with the three ways of
/// finding the cycles (internal to src/mesh/surface_nets*; defined in surface_nets_cycles.cpp).
///
/// A cell's crossings lie on its faces; two crossings on the face toward one neighbour are
/// joined by a segment of the surface, and the cycles are the classes of that relation, one
/// vertex each. Three ways find them, fastest first; each answers only where it applies and
/// gives the same partition as the general one there (tests/unit/mesh/surface_nets_cycles_test.cpp):
/// - oneSheetByCornerSigns: the crossings are exactly the cell's own sign-changing edges, so
///   the corner signs alone decide (a table), no face pairing at all. Nearly every cell.
/// - cyclesOfPairedFaces: every face carries exactly two crossings (at most 8 crossings):
///   the pairs come from a small open-addressed table, no sort and no search, and a walk
///   around them tells a single cycle without disjoint sets.
/// - cyclesOfFaceGroups: any cell. Entries sorted by neighbour; a face with four or more
///   crossings pairs them by their order around the face (pairOnFace) and is recorded as a
///   MultiFace (its segments may need split vertices).
/// Threading: a call writes the cell owner's tile and the cell's quadrants of its crossings.
#pragma once

#include "adf/adf.h"
#include "mesh/surface_nets.h"
#include "mesh/surface_nets_records.h"

#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

namespace kizamu::mesh::detail {

/// Reusable buffers of meshCell (beyond its stack buffers, for cells with many crossings).
struct CellScratch {
    /// A crossing's side toward one neighbour of the cell: entry 2j (2j + 1) is crossing j's
    /// face toward the ring cell before (after) its run.
    struct FaceEntry {
        uint64_t neighbour;
        int q;  ///< ring position of the neighbour
        uint32_t local;  ///< the crossing's index among the cell's
    };
    std::vector<FaceEntry> faces;
    std::vector<const Crossing*> faceXs;
    std::vector<std::pair<uint32_t, uint32_t>> pairs;
    std::vector<uint32_t> cycleOf, parent, made;
    /// The crossings hold no split vertices yet (a build: fresh records), so meshCell need not
    /// forget them (it would write a cache line of each crossing that is read nowhere else).
    bool freshCrossings = false;
};

/// Disjoint sets of a cell's n crossings (the cycles depend only on the partition). `parent`
/// has n entries and is set up only by separate(): where one way finds a single cycle it sets
/// `count` to 1 and leaves the sets alone. A set's root is its smallest index.
struct CycleSets {
    uint32_t* parent;
    uint32_t n;
    uint32_t count;

    void separate() {
        for (uint32_t j = 0; j < n; ++j) parent[j] = j;
        count = n;
    }
    uint32_t find(uint32_t i) {
        while (parent[i] != i) i = parent[i] = parent[parent[i]];
        return i;
    }
    void unite(uint32_t a, uint32_t b) {
        a = find(a);
        b = find(b);
        if (a == b) return;
        parent[std::max(a, b)] = std::min(a, b);
        --count;
    }
};

/// Ring position of the neighbour behind face entry f (CellScratch::FaceEntry's numbering).
inline int faceRing(const Incidence* inc, uint32_t f) {
    const Incidence& c = inc[f / 2];
    return f % 2 ? (c.last + 1) % 4 : (c.first + 3) % 4;
}

/// Whether the cell's n > 0 crossings (sorted by key) form one cycle that its corner signs
/// alone tell: they are exactly the cell's own sign-changing edges (each as long as the cell,
/// the cell in one quadrant), and those edges' pattern makes one cycle with no face carrying
/// four. Then a face carrying two has one leaf behind it (a smaller one would split the face's
/// edges, and their crossings would be shorter than the cell), so the cycles are the cube's.
/// False says nothing (another way decides). Complexity: O(n), no pairing.
bool oneSheetByCornerSigns(const Incidence* inc, uint32_t n, uint32_t cellSize, uint32_t insideCorners);

/// The cycles where every face of the cell carries exactly two of its n crossings (2n <= 16
/// face entries): into `sets` (count 1 and no sets where a walk closes one cycle through all).
/// Returns false, `sets` untouched, where a face carries another count or n > 8.
/// Complexity: O(n), no sort, no allocation. Always inlined: meshCell's second fastest way
/// (called out of line, its table and the sets would go through memory).
[[gnu::always_inline]] inline bool cyclesOfPairedFaces(const Incidence* inc, uint32_t n, CycleSets& sets) {
    const uint32_t nf = 2 * n;
    // The entries paired by neighbour through a small open-addressed table (no sort, no search).
    constexpr uint32_t kTable = 32;  // twice the most entries taken here
    uint64_t tableKey[kTable];
    uint32_t tableEntry[kTable], partner[kTable / 2];  // partner: the other entry on the face
    uint32_t used = 0, closed = 0;  // bit t: slot t holds a neighbour; its second entry came
    bool paired = nf <= kTable / 2;
    for (uint32_t f = 0; f < nf && paired; ++f) {
        const uint64_t neighbour = inc[f / 2].x->ringCell[faceRing(inc, f)];
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
    if (!paired) return false;
    // One cycle when the walk from crossing 0, across a face to the partner entry and out
    // through its crossing's other face, meets every crossing before it is back.
    uint32_t met = 1;
    for (uint32_t f = partner[1]; f / 2 != 0; f = partner[f ^ 1]) ++met;
    if (met == n) {
        sets.count = 1;
    } else {
        sets.separate();
        for (uint32_t f = 0; f < nf; ++f)
            if (f < partner[f]) sets.unite(f / 2, partner[f] / 2);
    }
    return true;
}

/// The cycles of any cell (the general way): sets separated, then united through each face.
/// A face with four or more (even) crossings is paired by pairOnFace, counted in
/// st.multiCrossingFaces and, where this cell has the smaller key, appended to `multiFaces`; a
/// face whose crossings cannot be paired (odd, or signs not alternating) joins them all and
/// counts in st.oddFaces. `faces` has room for 2n entries. Complexity: O(n log n).
void cyclesOfFaceGroups(const adf::Adf& adf, const Incidence* inc, uint32_t n, CellScratch::FaceEntry* faces,
                        CycleSets& sets, CellScratch& s, std::vector<MultiFace>& multiFaces, SurfaceNetsStats& st);

/// Cycles and projected vertices of one cell owned by `tm`, from all its incidences `inc[0..n)`
/// sorted by crossing key (the order fixes every float sum, so a build and an update agree bit
/// for bit) and its 8 corners. Takes vertex slots from `tm` (released ones first), appends
/// their incidences and the cell's multi-crossing faces, writes the vertex refs into the
/// crossings' slots of this cell and forgets split vertices on faces toward larger keys.
/// Returns the first vertex (UINT32_MAX if n == 0); the others follow through nextInCell.
uint32_t meshCell(const adf::Adf& adf, TileMesh& tm, const Incidence* inc, uint32_t n, const float corners[8],
                  CellScratch& s, SurfaceNetsStats& st);

}  // namespace kizamu::mesh::detail
