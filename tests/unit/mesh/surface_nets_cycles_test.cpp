// SPDX-License-Identifier: Apache-2.0
// meshCell's three ways of finding a cell's cycles (surface_nets_cycles.h): where a fast way
// answers, it gives the partition the general way gives, on every cell of many random shapes.
#include "mesh/surface_nets_cell.h"
#include "mesh/surface_nets_cycles.h"
#include "mesh/surface_nets_internal.h"

#include "adf/adf_source.h"
#include "adf/generate.h"
#include "tests/util/random_shape.h"

#include <glm/gtc/quaternion.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <deque>
#include <map>
#include <random>
#include <string>

namespace kizamu {
namespace {

using namespace adf;
using namespace mesh::detail;

/// Every cell of `a` with crossings: its incidences sorted by crossing key, as a build gathers
/// them (the crossings are kept in `store`, which must outlive the result).
std::map<uint64_t, std::vector<Incidence>> cellIncidences(const Adf& a, std::deque<std::vector<Crossing>>& store) {
    std::map<uint64_t, std::vector<Incidence>> cells;
    mesh::SurfaceNetsStats st;
    a.forEachTile([&](const Tile& t) {
        if (!mayEmit(t)) return;
        std::vector<BoundaryCell> leaves;
        appendBoundaryCells(t, a.domain().maxLevel, leaves);
        std::vector<Crossing>& xs = store.emplace_back();
        computeCrossings(a, t, leaves, xs, st);
    });
    for (std::vector<Crossing>& xs : store)
        for (Crossing& x : xs) {
            uint8_t done = 0;
            for (int q = 0; q < 4; ++q) {
                if ((done >> q) & 1) continue;
                uint8_t first, last;
                incidenceRun(x, q, first, last);
                for (uint8_t r = first;; r = uint8_t((r + 1) % 4)) {
                    done |= uint8_t(1u << r);
                    if (r == last) break;
                }
                cells[x.ringCell[q]].push_back({x.ringCell[q], x.key(), &x, first, last});
            }
        }
    for (auto& [cell, inc] : cells)
        std::sort(inc.begin(), inc.end(), [](const Incidence& l, const Incidence& r) { return l.crossingKey < r.crossingKey; });
    return cells;
}

/// What each way answered on the corpus, and every disagreement with the general way.
struct Agreement {
    std::size_t cells = 0, oneSheet = 0, paired = 0, pairedSeveral = 0, general = 0, generalSeveral = 0;
    std::vector<std::string> oneSheetFailures, pairedFailures;
};

/// Runs the three ways on every cell of 160 random shapes (levels 5 to 7, two tile spans); once.
const Agreement& agreement() {
    static const Agreement result = [] {
        Agreement r;
        for (int i = 0; i < 160; ++i) {
            std::mt19937_64 rng(7000 + i);
            Domain d;
            d.maxLevel = 5 + i % 3;
            d.tileSpanLevels = 2 + i % 2;
            const AdfPtr a = generate(*test::randomShape(rng), d, GenerationSettings{});
            std::deque<std::vector<Crossing>> store;
            for (auto& [cell, inc] : cellIncidences(*a, store)) {
                ++r.cells;
                const uint32_t n = uint32_t(inc.size());
                const LeafRef leaf = a->findLeaf(unpackLattice(cell));
                const uint32_t size = 1u << uint32_t(d.maxLevel - inc[0].x->ringLevel[inc[0].first]);
                // The general way.
                std::vector<uint32_t> generalParent(n), pairedParent(n);
                std::vector<CellScratch::FaceEntry> faces(2 * std::size_t(n));
                CellScratch scratch;
                std::vector<MultiFace> multiFaces;
                mesh::SurfaceNetsStats st;
                CycleSets all{generalParent.data(), n, n};
                cyclesOfFaceGroups(*a, inc.data(), n, faces.data(), all, scratch, multiFaces, st);
                const std::string where = "shape " + std::to_string(i) + ", cell at " + std::to_string(cell) + ", " +
                                          std::to_string(n) + " crossings";
                if (oneSheetByCornerSigns(inc.data(), n, size, insideCorners(leaf.corners))) {
                    ++r.oneSheet;
                    if (all.count != 1)
                        r.oneSheetFailures.push_back(where + ": one sheet by its corners, " + std::to_string(all.count) + " cycles");
                    if (st.multiCrossingFaces + st.oddFaces != 0)
                        r.oneSheetFailures.push_back(where + ": one sheet by its corners, yet a face of 4 or an odd one");
                }
                CycleSets byPairs{pairedParent.data(), n, n};
                if (cyclesOfPairedFaces(inc.data(), n, byPairs)) {
                    ++r.paired;
                    if (byPairs.count != all.count) {
                        r.pairedFailures.push_back(where + ": paired faces give " + std::to_string(byPairs.count) +
                                                   " cycles, the general way " + std::to_string(all.count));
                    } else if (byPairs.count > 1) {
                        ++r.pairedSeveral;
                        for (uint32_t j = 0; j < n; ++j)
                            if (byPairs.find(j) != all.find(j))
                                r.pairedFailures.push_back(where + ": paired faces put crossing " + std::to_string(j) + " elsewhere");
                    }
                } else {
                    ++r.general;
                    r.generalSeveral += all.count > 1;
                }
            }
        }
        std::printf("%zu cells: %zu one sheet by corner signs, %zu by paired faces (%zu with several cycles), %zu by face "
                    "groups only (%zu with several cycles)\n",
                    r.cells, r.oneSheet, r.paired, r.pairedSeveral, r.general, r.generalSeveral);
        return r;
    }();
    return result;
}

void expectNone(const std::vector<std::string>& failures) {
    for (std::size_t k = 0; k < std::min<std::size_t>(failures.size(), 10); ++k) ADD_FAILURE() << failures[k];
    EXPECT_TRUE(failures.empty()) << failures.size() << " disagreements";
}

TEST(SurfaceNetsCycles, OneSheetByCornerSignsAgreesWithTheGeneralWayOnEveryCellOfRandomShapes) {
    const Agreement& r = agreement();
    expectNone(r.oneSheetFailures);
    EXPECT_GT(r.oneSheet, r.cells / 2);  // nearly every cell
}

TEST(SurfaceNetsCycles, PairedFacesAgreeWithTheGeneralWayOnEveryCellOfRandomShapes) {
    const Agreement& r = agreement();
    expectNone(r.pairedFailures);
    // The corpus reaches the cases where the answer is not one cycle, and cells only the
    // general way answers.
    EXPECT_GT(r.paired, 0u);
    EXPECT_GT(r.pairedSeveral, 0u);
    EXPECT_GT(r.general, 0u);
    EXPECT_GT(r.generalSeveral, 0u);
}

}  // namespace
}  // namespace kizamu
