// SPDX-License-Identifier: Apache-2.0
/// @file tile_diff.cpp
/// @brief appendChangedCells: a walk down both trees at once.
#include "mesh/tile_diff.h"

#include <cassert>
#include <cstring>

namespace kizamu::mesh {

namespace {

/// A cell of a tile: a node word, or child `brickChild` of a brick (a leaf).
struct Cursor {
    const adf::Tile* tile;
    uint32_t node;
    int brickChild;  ///< -1: the node word itself

    bool isLeaf() const {
        return brickChild >= 0 || adf::node::isLeaf(tile->nodes()[node]);
    }
    Cursor child(int c) const {
        const uint32_t w = tile->nodes()[node];
        return adf::node::isInternal(w) ? Cursor{tile, w + uint32_t(c), -1} : Cursor{tile, node, c};
    }
    /// Decoded exactly as the mesher decodes them (float(q) * scale).
    void corners(float out[8]) const {
        const uint32_t w = tile->nodes()[node];
        const float s = tile->scale();
        if (brickChild < 0) {
            const int16_t* q = tile->corners() + 8 * adf::node::leafIndex(w);
            for (int c = 0; c < 8; ++c) out[c] = float(q[c]) * s;
        } else {
            const int16_t* q = tile->bricks() + 27 * adf::node::brickIndex(w);
            for (int c = 0; c < 8; ++c) out[c] = float(q[adf::brickPoint(brickChild, c)]) * s;
        }
    }
};

void walk(const Cursor& a, const Cursor& b, glm::uvec3 origin, uint32_t size, std::vector<LatticeBox>& out) {
    const bool leafA = a.isLeaf(), leafB = b.isLeaf();
    if (leafA != leafB) {
        out.push_back({origin, size});
        return;
    }
    if (leafA) {
        float ca[8], cb[8];
        a.corners(ca);
        b.corners(cb);
        if (std::memcmp(ca, cb, sizeof ca) != 0) out.push_back({origin, size});
        return;
    }
    const uint32_t half = size >> 1;
    for (int c = 0; c < 8; ++c)
        walk(a.child(c), b.child(c), origin + glm::uvec3(c & 1, (c >> 1) & 1, c >> 2) * half, half, out);
}

}  // namespace

void appendChangedCells(const adf::Tile& before, const adf::Tile& after, int maxLevel, std::vector<LatticeBox>& out) {
    assert(before.level() == after.level() && before.latticeOrigin() == after.latticeOrigin() &&
           "appendChangedCells compares two versions of one tile slot");
    walk({&before, 0, -1}, {&after, 0, -1}, after.latticeOrigin(), 1u << uint32_t(maxLevel - after.level()), out);
}

}  // namespace kizamu::mesh
