// SPDX-License-Identifier: Apache-2.0
/// @file generate_border.cpp
/// @brief The border exchange between tiles: the samples one tile evaluated on a face or edge
/// it shares, handed to the neighbours generated after it.
///
/// Takes the border points a tile evaluated itself (recorded as it samples, in evaluation
/// order) and produces its BorderSamples, grouped by the face or edge they lie on; a
/// neighbour of a higher colour imports the lists on its side into its scratch volume before it
/// subdivides, so no point of a shared face or edge is evaluated twice in a colour-phased run.
/// Complexity: O(border points) per tile. Threading: a tile writes its own BorderSamples once,
/// when done; neighbours read it only after its done flag is set (Run::generateTiles).
#include "adf/generate_tile.h"

#include <algorithm>

namespace kizamu::adf::detail {

namespace {

/// The border lists (BorderSamples) a tile reads from the neighbour at offset n from it: those
/// of the neighbour's face or edge at -n, and for a face the 4 edges around it.
struct BorderLists {
    int count = 0;
    std::array<int, 5> lists{};
};
constexpr std::array<BorderLists, kNeighbours> kBorderLists = [] {
    auto nonzero = [](glm::ivec3 o) { return (o.x != 0) + (o.y != 0) + (o.z != 0); };
    std::array<BorderLists, kNeighbours> t{};
    for (int n = 0; n < kNeighbours; ++n) {
        const glm::ivec3 back = -kNeighbourOffsets[n];
        for (int m = 0; m < kNeighbours; ++m) {
            const glm::ivec3 e = kNeighbourOffsets[m];
            const bool edgeOfFace =
                nonzero(back) == 1 && nonzero(e) == 2 && e.x * back.x + e.y * back.y + e.z * back.z == 1;
            if (e == back || edgeOfFace) t[n].lists[t[n].count++] = m;
        }
    }
    return t;
}();

}  // namespace

void TileGenerator::importFrom(const BorderSamples& n, int neighbour) {
    const glm::ivec3 shift = kNeighbourOffsets[neighbour] * int(mSpan);
    const BorderLists& from = kBorderLists[neighbour];
    for (int l = 0; l < from.count; ++l)
        for (const auto& [key, v] : n.on(from.lists[l])) {
            const uint32_t i = index(glm::uvec3(glm::ivec3(unpackLocal(key)) + shift));
            if (!valid(i)) set(i, v);
        }
}

void TileGenerator::groupBorder(BorderSamples& border) const {
    border.begin.fill(0);
    for (const BorderRecord& r : mRecorded) ++border.begin[std::size_t(r.list) + 1];
    for (int n = 0; n < kNeighbours; ++n) border.begin[n + 1] += border.begin[n];
    border.entries.resize(mRecorded.size());
    std::array<uint32_t, kNeighbours> at;
    std::copy(border.begin.begin(), border.begin.end() - 1, at.begin());
    for (const BorderRecord& r : mRecorded) border.entries[at[r.list]++] = {r.key, r.value};
}

}  // namespace kizamu::adf::detail
