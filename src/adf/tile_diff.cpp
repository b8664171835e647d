// SPDX-License-Identifier: Apache-2.0
/// @file tile_diff.cpp
/// @brief appendChangedCells: a walk down both trees at once.
#include "adf/tile_diff.h"

#include <bit>
#include <cassert>
#include <cstring>

namespace kizamu::adf {

namespace {

/// A cell of a tile: a node (its word read once), or child `brickChild` of a brick (a leaf).
struct Cursor {
    const adf::Tile* tile;
    uint32_t word;
    int brickChild;  ///< -1: the node itself

    static Cursor node(const adf::Tile* t, uint32_t i) { return {t, t->node(i), -1}; }
    bool isLeaf() const { return brickChild >= 0 || adf::node::isLeaf(word); }
    bool isBrick() const { return brickChild < 0 && adf::node::isBrick(word); }
    Cursor child(int c) const {
        return adf::node::isInternal(word) ? node(tile, word + uint32_t(c)) : Cursor{tile, word, c};
    }
    /// The 27 quantised values of a brick node (narrow or wide: tile.h decodes either).
    void brickValues(int16_t out[27]) const { tile->brickValues(adf::node::brickIndex(word), out); }
    /// The 8 quantised corners of a leaf.
    void raw(int16_t out[8]) const {
        if (brickChild < 0) {
            tile->leafValues(adf::node::leafIndex(word), out);
        } else {
            const uint32_t brick = adf::node::brickIndex(word);
            for (int c = 0; c < 8; ++c) out[c] = tile->brickValue(brick, adf::brickPoint(brickChild, c));
        }
    }
};

/// Whether two leaves' corners differ, from their quantised values: with one scale decoding is
/// injective (16-bit integers times the same positive float), so the raw values are compared;
/// else the values decoded exactly as the mesher decodes them (float(q) * scale).
bool valuesDiffer(const int16_t qa[8], float sa, const int16_t qb[8], float sb, bool sameScale) {
    if (sameScale) return std::memcmp(qa, qb, 8 * sizeof(int16_t)) != 0;
    for (int c = 0; c < 8; ++c)
        if (std::bit_cast<uint32_t>(float(qa[c]) * sa) != std::bit_cast<uint32_t>(float(qb[c]) * sb)) return true;
    return false;
}

bool cornersDiffer(const Cursor& a, const Cursor& b, bool sameScale) {
    // Two lone leaves stored alike (a rebuilt tile's copies mostly are) read the same, undecoded.
    if (sameScale && a.brickChild < 0 && b.brickChild < 0 &&
        a.tile->storesLeafAs(adf::node::leafIndex(a.word), *b.tile, adf::node::leafIndex(b.word)))
        return false;
    int16_t qa[8], qb[8];
    a.raw(qa);
    b.raw(qb);
    return valuesDiffer(qa, a.tile->scale(), qb, b.tile->scale(), sameScale);
}

inline glm::uvec3 childOrigin(glm::uvec3 origin, int c, uint32_t half) {
    return origin + glm::uvec3(c & 1, (c >> 1) & 1, c >> 2) * half;
}

/// Where a walk records the changed cells (and, if asked, the old tile's words there).
struct Changed {
    std::vector<LatticeBox>& boxes;
    std::vector<uint32_t>* words;
    void add(const Cursor& a, glm::uvec3 origin, uint32_t size) {
        boxes.push_back({origin, size});
        if (words) words->push_back(a.brickChild >= 0 ? adf::node::kLeafBit : a.word);
    }
};

void walk(const Cursor& a, const Cursor& b, glm::uvec3 origin, uint32_t size, bool sameScale, Changed& out) {
    const bool leafA = a.isLeaf(), leafB = b.isLeaf();
    if (leafA != leafB) {
        out.add(a, origin, size);
        return;
    }
    if (leafA) {
        if (cornersDiffer(a, b, sameScale)) out.add(a, origin, size);
        return;
    }
    const uint32_t half = size >> 1;
    if (a.isBrick() && b.isBrick()) {
        // Each brick decoded once: equal values mean 8 equal children, else the children are
        // compared from the decoded values (not 8 lookups per corner and side).
        if (sameScale && a.tile->storesBrickAs(adf::node::brickIndex(a.word), *b.tile, adf::node::brickIndex(b.word))) return;
        int16_t qa[27], qb[27];
        a.brickValues(qa);
        b.brickValues(qb);
        if (sameScale && std::memcmp(qa, qb, sizeof qa) == 0) return;
        for (int c = 0; c < 8; ++c) {
            int16_t ca[8], cb[8];
            for (int k = 0; k < 8; ++k) {
                ca[k] = qa[adf::brickPoint(c, k)];
                cb[k] = qb[adf::brickPoint(c, k)];
            }
            if (valuesDiffer(ca, a.tile->scale(), cb, b.tile->scale(), sameScale)) out.add(a.child(c), childOrigin(origin, c, half), half);
        }
        return;
    }
    for (int c = 0; c < 8; ++c) walk(a.child(c), b.child(c), childOrigin(origin, c, half), half, sameScale, out);
}

}  // namespace

void appendChangedCells(const adf::Tile& before, const adf::Tile& after, int maxLevel, std::vector<LatticeBox>& out,
                        std::vector<uint32_t>* beforeWords) {
    assert(before.level() == after.level() && before.latticeOrigin() == after.latticeOrigin() &&
           "appendChangedCells compares two versions of one tile slot");
    Changed changed{out, beforeWords};
    walk(Cursor::node(&before, 0), Cursor::node(&after, 0), after.latticeOrigin(), 1u << uint32_t(maxLevel - after.level()),
         before.scale() == after.scale(), changed);
}

}  // namespace kizamu::adf
