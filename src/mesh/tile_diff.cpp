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
        return brickChild >= 0 || adf::node::isLeaf(tile->node(node));
    }
    Cursor child(int c) const {
        const uint32_t w = tile->node(node);
        return adf::node::isInternal(w) ? Cursor{tile, w + uint32_t(c), -1} : Cursor{tile, node, c};
    }
    bool isBrick() const { return brickChild < 0 && adf::node::isBrick(tile->node(node)); }
    /// The 27 quantised values of a brick node (narrow or wide: tile.h decodes either).
    void brickValues(int16_t out[27]) const {
        const uint32_t brick = adf::node::brickIndex(tile->node(node));
        for (int g = 0; g < 27; ++g) out[g] = tile->brickValue(brick, g);
    }
    /// The 8 quantised corners of a leaf.
    void raw(int16_t out[8]) const {
        const uint32_t w = tile->node(node);
        if (brickChild < 0) {
            tile->leafValues(adf::node::leafIndex(w), out);
        } else {
            const uint32_t brick = adf::node::brickIndex(w);
            for (int c = 0; c < 8; ++c) out[c] = tile->brickValue(brick, adf::brickPoint(brickChild, c));
        }
    }
    /// Decoded exactly as the mesher decodes them (float(q) * scale).
    void corners(float out[8]) const {
        const uint32_t w = tile->node(node);
        const float s = tile->scale();
        if (brickChild < 0) {
            tile->leafCorners(adf::node::leafIndex(w), out);
        } else {
            const uint32_t brick = adf::node::brickIndex(w);
            for (int c = 0; c < 8; ++c) out[c] = float(tile->brickValue(brick, adf::brickPoint(brickChild, c))) * s;
        }
    }
};

/// Whether two leaves' corners differ. With one scale, decoding is injective (16-bit integers
/// times the same positive float), so the raw values are compared instead.
bool cornersDiffer(const Cursor& a, const Cursor& b, bool sameScale) {
    if (sameScale) {
        int16_t qa[8], qb[8];
        a.raw(qa);
        b.raw(qb);
        return std::memcmp(qa, qb, sizeof qa) != 0;
    }
    float ca[8], cb[8];
    a.corners(ca);
    b.corners(cb);
    return std::memcmp(ca, cb, sizeof ca) != 0;
}

void walk(const Cursor& a, const Cursor& b, glm::uvec3 origin, uint32_t size, bool sameScale, std::vector<LatticeBox>& out) {
    const bool leafA = a.isLeaf(), leafB = b.isLeaf();
    if (leafA != leafB) {
        out.push_back({origin, size});
        return;
    }
    if (leafA) {
        if (cornersDiffer(a, b, sameScale)) out.push_back({origin, size});
        return;
    }
    if (sameScale && a.isBrick() && b.isBrick()) {
        int16_t qa[27], qb[27];
        a.brickValues(qa);
        b.brickValues(qb);
        if (std::memcmp(qa, qb, sizeof qa) == 0) return;  // the 8 children share these values
    }
    const uint32_t half = size >> 1;
    for (int c = 0; c < 8; ++c)
        walk(a.child(c), b.child(c), origin + glm::uvec3(c & 1, (c >> 1) & 1, c >> 2) * half, half, sameScale, out);
}

}  // namespace

void appendChangedCells(const adf::Tile& before, const adf::Tile& after, int maxLevel, std::vector<LatticeBox>& out) {
    assert(before.level() == after.level() && before.latticeOrigin() == after.latticeOrigin() &&
           "appendChangedCells compares two versions of one tile slot");
    walk({&before, 0, -1}, {&after, 0, -1}, after.latticeOrigin(), 1u << uint32_t(maxLevel - after.level()),
         before.scale() == after.scale(), out);
}

}  // namespace kizamu::mesh
