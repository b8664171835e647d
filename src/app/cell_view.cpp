// SPDX-License-Identifier: Apache-2.0
/// @file cell_view.cpp
/// @brief Boundary leaf cells to boxes (see cell_view.h).
#include "app/cell_view.h"

#include <bit>

namespace kizamu::app {

std::size_t collectBoundaryCellBoxes(const adf::Adf& adf, std::size_t cap,
                                     std::vector<render::CellBox>& out) {
    out.clear();
    const adf::Domain& d = adf.domain();
    const double h = d.finestCellSize();
    adf.forEachTile([&](const adf::Tile& t) {
        adf::forEachLeaf(t, d.maxLevel, [&](const adf::LeafRef& leaf) {
            if (leaf.type() != adf::CellType::Boundary) return;
            render::CellBox b;
            b.minWorld = glm::vec3(d.originWorld + glm::dvec3(leaf.latticeOrigin) * h);
            b.sizeWorld = float(double(leaf.latticeSize) * h);
            b.level = d.maxLevel - std::countr_zero(leaf.latticeSize);
            out.push_back(b);
        });
    });
    const std::size_t count = out.size();
    if (count > cap) {
        const std::size_t stride = cap == 0 ? count : (count + cap - 1) / cap;
        std::size_t kept = 0;
        for (std::size_t i = 0; i < count; i += stride) out[kept++] = out[i];
        out.resize(kept);
    }
    return count;
}

}  // namespace kizamu::app
