// SPDX-License-Identifier: Apache-2.0
/// @file tile.cpp
/// @brief Tile allocation, quantisation and checksums.
#include "adf/tile.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <cstring>
#include <new>
#include <vector>

namespace kizamu::adf {

CellType cellTypeOf(std::span<const float, 8> corners) {
    int inside = 0;  // counted without a branch per corner: every cell of every tile asks
    for (float v : corners) inside += v < 0.0f;
    return inside == 0 ? CellType::Exterior : inside == 8 ? CellType::Interior : CellType::Boundary;
}

namespace {

constexpr std::size_t alignUp(std::size_t n, std::size_t a) { return (n + a - 1) / a * a; }
constexpr std::size_t kHeaderBytes = alignUp(sizeof(Tile), 8);

/// FNV-1a over 64-bit words (the tail byte by byte): fast enough to run on every tile.
uint64_t fnv1a(uint64_t h, const void* data, std::size_t n) {
    const auto* p = static_cast<const unsigned char*>(data);
    std::size_t i = 0;
    for (; i + 8 <= n; i += 8) {
        uint64_t w;
        std::memcpy(&w, p + i, 8);
        h ^= w;
        h *= 0x100000001b3ull;
    }
    for (; i < n; ++i) {
        h ^= p[i];
        h *= 0x100000001b3ull;
    }
    return h;
}

}  // namespace

namespace {
/// 16-bit arrays first (wide leaves' corners, narrow leaves' corner 0, narrow bricks' centres),
/// then the signed bytes (7 per narrow leaf, 27 per narrow or coarse-narrow brick), then wide
/// bricks, 2-aligned. `packedCount`: narrow and coarse-narrow bricks (one layout).
struct Layout {
    std::size_t wideLeaves, leafBases, brickBases, leafDeltas, brickDeltas, wide, total;
};
Layout layoutOf(uint32_t nodeCount, bool narrowNodes, uint32_t narrowLeafCount, uint32_t wideLeafCount,
                uint32_t packedCount, uint32_t wideCount) {
    Layout l;
    l.wideLeaves = kHeaderBytes + alignUp(std::size_t(nodeCount) * (narrowNodes ? 2 : 4), 8);
    l.leafBases = l.wideLeaves + std::size_t(wideLeafCount) * Tile::kWideLeafBytes;
    l.brickBases = l.leafBases + std::size_t(narrowLeafCount) * 2;
    l.leafDeltas = l.brickBases + std::size_t(packedCount) * 2;
    l.brickDeltas = l.leafDeltas + std::size_t(narrowLeafCount) * 7;
    l.wide = alignUp(l.brickDeltas + std::size_t(packedCount) * 27, 2);
    l.total = l.wide + std::size_t(wideCount) * Tile::kWideBrickBytes;
    return l;
}
}  // namespace

Tile* Tile::allocate(uint32_t nodeCount, bool narrowNodes, uint32_t narrowLeafCount, uint32_t wideLeafCount,
                     uint32_t narrowCount, uint32_t coarseCount, uint32_t wideCount) {
    const Layout l = layoutOf(nodeCount, narrowNodes, narrowLeafCount, wideLeafCount, narrowCount + coarseCount, wideCount);
    void* mem = ::operator new(l.total);
    Tile* t = new (mem) Tile();
    auto* base = static_cast<unsigned char*>(mem);
    t->mNarrowNodes = narrowNodes;
    if (narrowNodes)
        t->mNarrowNodeWords = reinterpret_cast<const uint16_t*>(base + kHeaderBytes);
    else
        t->mNodes = reinterpret_cast<const uint32_t*>(base + kHeaderBytes);
    t->mWideLeaves = reinterpret_cast<const int16_t*>(base + l.wideLeaves);
    t->mLeafBases = reinterpret_cast<const int16_t*>(base + l.leafBases);
    t->mLeafDeltas = reinterpret_cast<const int8_t*>(base + l.leafDeltas);
    t->mBrickBases = reinterpret_cast<const int16_t*>(base + l.brickBases);
    t->mBrickDeltas = reinterpret_cast<const int8_t*>(base + l.brickDeltas);
    t->mWideBricks = reinterpret_cast<const int16_t*>(base + l.wide);
    t->mNodeCount = nodeCount;
    t->mLeafCount = narrowLeafCount + wideLeafCount;
    t->mNarrowLeafCount = narrowLeafCount;
    t->mBrickCount = narrowCount + coarseCount + wideCount;
    t->mNarrowCount = narrowCount;
    t->mPackedCount = narrowCount + coarseCount;
    return t;
}

void Tile::Deleter::operator()(const Tile* t) const {
    t->~Tile();
    ::operator delete(const_cast<Tile*>(t));
}

Tile::~Tile() { mMagic = 0xdeadbeefdeadbeefull; }

std::size_t Tile::bytes() const {
    return layoutOf(mNodeCount, mNarrowNodes, mNarrowLeafCount, mLeafCount - mNarrowLeafCount, mPackedCount,
                    mBrickCount - mPackedCount)
        .total;
}

std::vector<uint32_t> Tile::nodeWords() const {
    std::vector<uint32_t> out(mNodeCount);
    for (uint32_t i = 0; i < mNodeCount; ++i) out[i] = node(i);
    return out;
}

uint64_t Tile::computeChecksum() const {
    uint64_t h = 0xcbf29ce484222325ull;
    h = fnv1a(h, &mLevel, sizeof mLevel);
    h = fnv1a(h, &mOrigin, sizeof mOrigin);
    h = fnv1a(h, &mScale, sizeof mScale);
    h = fnv1a(h, &mNarrowNodes, sizeof mNarrowNodes);
    h = fnv1a(h, mNarrowNodes ? static_cast<const void*>(mNarrowNodeWords) : mNodes, nodeBytes());
    h = fnv1a(h, &mStep, sizeof mStep);
    h = fnv1a(h, &mNarrowLeafCount, sizeof mNarrowLeafCount);
    h = fnv1a(h, mLeafBases, std::size_t(mNarrowLeafCount) * 2);
    h = fnv1a(h, mLeafDeltas, std::size_t(mNarrowLeafCount) * 7);
    h = fnv1a(h, mWideLeaves, std::size_t(mLeafCount - mNarrowLeafCount) * 16);
    h = fnv1a(h, &mNarrowCount, sizeof mNarrowCount);
    h = fnv1a(h, &mPackedCount, sizeof mPackedCount);
    h = fnv1a(h, mBrickBases, std::size_t(mPackedCount) * 2);
    h = fnv1a(h, mBrickDeltas, std::size_t(mPackedCount) * 27);
    h = fnv1a(h, mWideBricks, std::size_t(mBrickCount - mPackedCount) * 54);
    return h;
}

namespace {
/// Round half away from zero into [-32767, 32767], keeping negative values negative (inside
/// stays inside even when a tiny distance rounds to zero).
inline int16_t quantise(float v, float scale) {
    const float x = v / scale;
    long r = long(x + (x >= 0.0f ? 0.5f : -0.5f));
    r = std::clamp(r, -32767l, 32767l);
    if (v < 0.0f && r == 0) r = -1;
    return int16_t(r);
}

/// Quantisation steps per narrow-brick step: 127 of them span twice a finest cell, which holds
/// every value of a brick of finest cells (at most sqrt(3) cells from its centre) in a
/// 1-Lipschitz field. Depends only on the scale and the cell size, never on the values, so a
/// decoded tile re-encodes to the same bits. Lone leaves and coarse-narrow bricks use twice this
/// step (Tile::leafStep).
int32_t narrowStep(float scale, double finestCell) {
    const double steps = std::ceil(2.0 * finestCell / (127.0 * double(scale)));
    return steps >= 1.0 ? int32_t(std::min(steps, 32767.0)) : 1;
}

/// Steps from `base` to the value nearest `q` with q's sign (inside stays inside), or false
/// when that needs more than 127 steps or leaves the 16-bit range.
inline bool narrowDelta(int32_t q, int32_t base, int32_t step, int8_t& out) {
    const int32_t diff = q - base;
    int32_t k = diff >= 0 ? (diff + step / 2) / step : -((-diff + step / 2) / step);
    const int32_t v = base + k * step;
    if (q < 0 && v >= 0) --k;
    if (q >= 0 && v < 0) ++k;
    if (base + k * step > 32767) --k;  // rounded past the tile's extreme value: the step below
    if (base + k * step < -32767) ++k;
    const int32_t decoded = base + k * step;
    if (k < -127 || k > 127 || decoded < -32767 || decoded > 32767) return false;
    out = int8_t(k);
    return true;
}

/// Packs `n` values as signed-byte steps from `base` (narrowDelta each); false if one misses.
bool packs(const int16_t* q, int n, int32_t base, int32_t step, int8_t* out) {
    for (int i = 0; i < n; ++i)
        if (!narrowDelta(q[i], base, step, out[i])) return false;
    return true;
}

/// New numbers that put the items of form 0 first, then form 1, and so on, each form in its old
/// order; `counts[f]` gets the number of items of form f.
template <std::size_t kForms>
std::vector<uint32_t> numberByForm(const std::vector<uint8_t>& form, std::array<uint32_t, kForms>& counts) {
    counts.fill(0);
    for (uint8_t f : form) ++counts[f];
    std::array<uint32_t, kForms> next{};
    for (std::size_t f = 1; f < kForms; ++f) next[f] = next[f - 1] + counts[f - 1];
    std::vector<uint32_t> number(form.size());
    for (std::size_t i = 0; i < form.size(); ++i) number[i] = next[form[i]]++;
    return number;
}
}  // namespace

TilePtr Tile::create(int level, glm::uvec3 latticeOrigin, std::span<const uint32_t> nodes,
                     std::span<const float> leafCorners, std::span<const float> brickValues,
                     uint64_t version, double finestCell, float keepScale, const TileCopies& copies) {
    assert(leafCorners.size() % 8 == 0 && brickValues.size() % 27 == 0);
    assert(!copies.from || (copies.leaves.size() == leafCorners.size() / 8 && copies.bricks.size() == brickValues.size() / 27));
    float maxAbs = 0.0f;
    for (float v : leafCorners) maxAbs = std::max(maxAbs, std::abs(v));
    for (float v : brickValues) maxAbs = std::max(maxAbs, std::abs(v));
    // One scale per tile: a tile spans at most 2^span finest cells, so its surface cells keep
    // a step of about diagonal/32767 (under 0.01 finest cell at span 6).
    // A kept scale may be up to twice as coarse as this tile needs (so it never drifts far
    // from what the values ask for); otherwise the tile gets its own.
    const float own = maxAbs / 32767.0f;
    const float scale = keepScale > 0.0f && maxAbs > 0.0f && own <= keepScale && keepScale <= 2.0f * own ? keepScale
                        : maxAbs > 0.0f                                                            ? own
                                                                                                   : 1.0f;
    // Copied items keep their quantised values (quantising a decoded value at its own scale
    // gives it back) and, in build, their packing.
    const Tile* from = copies.from && scale == copies.from->mScale && narrowStep(scale, finestCell) == copies.from->mStep
                           ? copies.from
                           : nullptr;
    std::vector<int16_t> corners(leafCorners.size()), bricks(brickValues.size());
    for (std::size_t l = 0; l < leafCorners.size() / 8; ++l) {
        if (from && copies.leaves[l] != TileCopies::kNotCopied) {
            from->leafValues(copies.leaves[l], &corners[8 * l]);
            continue;
        }
        for (std::size_t i = 8 * l; i < 8 * l + 8; ++i) corners[i] = quantise(leafCorners[i], scale);
    }
    for (std::size_t b = 0; b < brickValues.size() / 27; ++b) {
        if (from && copies.bricks[b] != TileCopies::kNotCopied) {
            from->brickValues(copies.bricks[b], &bricks[27 * b]);
            continue;
        }
        for (std::size_t i = 27 * b; i < 27 * b + 27; ++i) bricks[i] = quantise(brickValues[i], scale);
    }
    return build(level, latticeOrigin, nodes, corners, bricks, scale, version, finestCell, from ? copies : TileCopies{});
}

TilePtr Tile::createQuantised(int level, glm::uvec3 latticeOrigin, std::span<const uint32_t> nodes,
                              std::span<const int16_t> leafCorners, std::span<const int16_t> brickValues,
                              float scale, uint64_t version, double finestCell) {
    assert(leafCorners.size() % 8 == 0 && brickValues.size() % 27 == 0);
    return build(level, latticeOrigin, nodes, leafCorners, brickValues, scale, version, finestCell);
}

TilePtr Tile::build(int level, glm::uvec3 latticeOrigin, std::span<const uint32_t> nodes,
                    std::span<const int16_t> leafCorners, std::span<const int16_t> brickValues, float scale,
                    uint64_t version, double finestCell, const TileCopies& copies) {
    const auto brickCount = uint32_t(brickValues.size() / 27);
    const int32_t step = narrowStep(scale, finestCell), leafStep = 2 * step;
    // Which form each brick takes (the brick step, else the leaf step, else wide), and their new
    // numbers (narrow first, then coarse-narrow, then wide, each group in order).
    // Idempotent: a coarse-narrow brick decodes to centre + k leaf steps = centre + 2k brick
    // steps, which the brick step takes back exactly, so it would re-encode narrow only if every
    // |k| were at most 63. The value q that missed the brick step rules that out: it lies beyond
    // centre +-127 brick steps (within them, the nearest brick-step point with q's sign is too),
    // say above. The nearest leaf-step point to it is then centre + 128 brick steps or higher,
    // and so is the one taken unless centre + 128 has the other sign (q < 0 <= centre + 128);
    // but then centre + 127 brick steps lies in [q - step, q) with q's sign, and the brick step
    // would have taken it. Below likewise. (tile_test checks this over every 16-bit value.)
    enum : uint8_t { kNarrow, kCoarse, kWide };
    std::vector<int8_t> deltas(std::size_t(brickCount) * 27);
    std::vector<uint8_t> form(brickCount);
    // A copied item's form and steps are its source's: packing its decoded values again would
    // find the same (the encoding is idempotent), at the price of every value.
    const Tile* from = copies.from;
    for (uint32_t b = 0; b < brickCount; ++b) {
        const int16_t* q = brickValues.data() + 27 * std::size_t(b);
        int8_t* d = deltas.data() + 27 * std::size_t(b);
        if (from && copies.bricks[b] != TileCopies::kNotCopied) {
            const uint32_t i = copies.bricks[b];
            if (i < from->mPackedCount) std::memcpy(d, from->mBrickDeltas + 27 * std::size_t(i), 27);
            form[b] = i < from->mNarrowCount ? kNarrow : i < from->mPackedCount ? kCoarse : kWide;
            continue;
        }
        form[b] = packs(q, 27, q[13], step, d) ? kNarrow : packs(q, 27, q[13], leafStep, d) ? kCoarse : kWide;
    }
    std::array<uint32_t, 3> brickForms;
    const std::vector<uint32_t> renumber = numberByForm(form, brickForms);
    const uint32_t narrowCount = brickForms[kNarrow], coarseCount = brickForms[kCoarse];
    const uint32_t packedCount = narrowCount + coarseCount;

    // Lone leaves likewise: corner 0 exact, the others in leaf steps from it.
    const auto leafCount = uint32_t(leafCorners.size() / 8);
    std::vector<int8_t> leafDeltas(std::size_t(leafCount) * 7);
    std::vector<uint8_t> leafForm(leafCount);
    for (uint32_t l = 0; l < leafCount; ++l) {
        const int16_t* q = leafCorners.data() + 8 * std::size_t(l);
        if (from && copies.leaves[l] != TileCopies::kNotCopied) {
            const uint32_t i = copies.leaves[l];
            if (i < from->mNarrowLeafCount) std::memcpy(leafDeltas.data() + 7 * std::size_t(l), from->mLeafDeltas + 7 * std::size_t(i), 7);
            leafForm[l] = i < from->mNarrowLeafCount ? kNarrow : kWide;
            continue;
        }
        leafForm[l] = packs(q + 1, 7, q[0], leafStep, leafDeltas.data() + 7 * std::size_t(l)) ? kNarrow : kWide;
    }
    std::array<uint32_t, 3> leafForms;
    const std::vector<uint32_t> renumberLeaf = numberByForm(leafForm, leafForms);
    const uint32_t narrowLeafCount = leafForms[kNarrow];

    // Node words with the new numbers; 16 bits each when every one fits (node::narrow).
    std::vector<uint32_t> words(nodes.size());
    bool narrowNodes = true;
    for (std::size_t i = 0; i < nodes.size(); ++i) {
        const uint32_t w = nodes[i];
        if (node::isBrick(w) && node::brickIndex(w) < brickCount)
            words[i] = node::makeBrick(renumber[node::brickIndex(w)]);
        else if (node::isLeaf(w) && node::leafIndex(w) < leafCount)
            words[i] = node::makeLeaf(renumberLeaf[node::leafIndex(w)], node::leafType(w));
        else
            words[i] = w;
        narrowNodes = narrowNodes && node::fitsNarrow(words[i]);
    }

    Tile* t = allocate(uint32_t(nodes.size()), narrowNodes, narrowLeafCount, leafCount - narrowLeafCount, narrowCount,
                       coarseCount, brickCount - packedCount);
    t->mStep = step;
    if (narrowNodes) {
        auto* out = const_cast<uint16_t*>(t->mNarrowNodeWords);
        for (std::size_t i = 0; i < words.size(); ++i) out[i] = node::narrow(words[i]);
    } else {
        std::copy(words.begin(), words.end(), const_cast<uint32_t*>(t->mNodes));
    }
    auto* leafBases = const_cast<int16_t*>(t->mLeafBases);
    auto* leafPacked = const_cast<int8_t*>(t->mLeafDeltas);
    auto* wideLeaves = const_cast<int16_t*>(t->mWideLeaves);
    for (uint32_t l = 0; l < leafCount; ++l) {
        const int16_t* q = leafCorners.data() + 8 * std::size_t(l);
        const uint32_t n = renumberLeaf[l];
        if (leafForm[l] == kNarrow) {
            leafBases[n] = q[0];
            std::memcpy(leafPacked + 7 * std::size_t(n), leafDeltas.data() + 7 * std::size_t(l), 7);
        } else {
            std::memcpy(wideLeaves + 8 * std::size_t(n - narrowLeafCount), q, 16);
        }
    }
    auto* bases = const_cast<int16_t*>(t->mBrickBases);
    auto* packed = const_cast<int8_t*>(t->mBrickDeltas);
    auto* wide = const_cast<int16_t*>(t->mWideBricks);
    for (uint32_t b = 0; b < brickCount; ++b) {
        const int16_t* q = brickValues.data() + 27 * std::size_t(b);
        const uint32_t n = renumber[b];
        if (form[b] != kWide) {
            bases[n] = q[13];
            std::memcpy(packed + 27 * std::size_t(n), deltas.data() + 27 * std::size_t(b), 27);
        } else {
            std::memcpy(wide + 27 * std::size_t(n - packedCount), q, 54);
        }
    }
    return finish(t, level, latticeOrigin, scale, version);
}

TilePtr Tile::finish(Tile* t, int level, glm::uvec3 latticeOrigin, float scale, uint64_t version) {
    t->mLevel = int16_t(level);
    t->mOrigin = latticeOrigin;
    t->mScale = scale;
    t->mVersion = version;
    t->mChecksum = t->computeChecksum();
    t->mMagic = kAlive;
    return TilePtr(t, Deleter{});
}

}  // namespace kizamu::adf
