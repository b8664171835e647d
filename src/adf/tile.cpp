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
/// Node words (8-aligned), then the 16-bit arrays (wide own leaves' corners, narrow own
/// leaves' corner 0, packed bricks' and groups' centres), then the steps (7 bytes per narrow
/// own leaf; per packed brick, then per packed group: the narrow ones' 7-bit fields, then the
/// coarse-narrow and far ones' bytes), then wide bricks and wide groups, 2-aligned.
struct Layout {
    std::size_t nodes, wideLeaves, leafBases, brickBases, groupBases, leafDeltas, brickDeltas, groupDeltas, wideBricks,
        wideGroups, total;
};
Layout layoutOf(const Tile::Counts& n) {
    Layout l;
    l.nodes = kHeaderBytes;
    l.wideLeaves = l.nodes + alignUp(std::size_t(n.nodes) * (n.narrowNodes ? 2 : 4), 8);
    l.leafBases = l.wideLeaves + std::size_t(n.wideLeaves) * Tile::kWideLeafBytes;
    l.brickBases = l.leafBases + std::size_t(n.narrowLeaves) * 2;
    const std::size_t packedBricks = std::size_t(n.narrowBricks) + n.coarseBricks + n.farBricks;
    const std::size_t packedGroups = std::size_t(n.narrowGroups) + n.coarseGroups + n.farGroups;
    l.groupBases = l.brickBases + packedBricks * 2;
    l.leafDeltas = l.groupBases + packedGroups * 2;
    l.brickDeltas = l.leafDeltas + std::size_t(n.narrowLeaves) * 7;
    l.groupDeltas = l.brickDeltas + Tile::gridStepsOffset(n.narrowBricks, packedBricks);
    l.wideBricks = alignUp(l.groupDeltas + Tile::gridStepsOffset(n.narrowGroups, packedGroups), 2);
    l.wideGroups = l.wideBricks + std::size_t(n.wideBricks) * Tile::kWideGridBytes;
    l.total = l.wideGroups + std::size_t(n.wideGroups) * Tile::kWideGridBytes;
    return l;
}
}  // namespace

Tile* Tile::allocate(const Counts& n) {
    const Layout l = layoutOf(n);
    if (l.total > UINT32_MAX) throw std::bad_alloc();  // offsets are 32-bit
    void* mem = ::operator new(l.total);
    std::memset(static_cast<unsigned char*>(mem) + kHeaderBytes, 0, l.total - kHeaderBytes);  // padding too: checksummed
    Tile* t = new (mem) Tile();
    t->mNarrowNodes = n.narrowNodes;
    t->mNodesAt = uint32_t(l.nodes);
    t->mWideLeavesAt = uint32_t(l.wideLeaves);
    t->mLeafBasesAt = uint32_t(l.leafBases);
    t->mLeafDeltasAt = uint32_t(l.leafDeltas);
    t->mBrickBasesAt = uint32_t(l.brickBases);
    t->mBrickDeltasAt = uint32_t(l.brickDeltas);
    t->mWideBricksAt = uint32_t(l.wideBricks);
    t->mGroupBasesAt = uint32_t(l.groupBases);
    t->mGroupDeltasAt = uint32_t(l.groupDeltas);
    t->mWideGroupsAt = uint32_t(l.wideGroups);
    t->mNodeCount = n.nodes;
    t->mGroupCount = n.narrowGroups + n.coarseGroups + n.farGroups + n.wideGroups;
    t->mNarrowGroupCount = n.narrowGroups;
    t->mCoarseGroupEnd = n.narrowGroups + n.coarseGroups;
    t->mPackedGroupCount = n.narrowGroups + n.coarseGroups + n.farGroups;
    t->mGroupedLeafCount = n.groupedLeaves;
    t->mLeafCount = 8 * t->mGroupCount + n.narrowLeaves + n.wideLeaves;
    t->mNarrowLeafCount = n.narrowLeaves;
    t->mBrickCount = n.narrowBricks + n.coarseBricks + n.farBricks + n.wideBricks;
    t->mNarrowCount = n.narrowBricks;
    t->mCoarseEnd = n.narrowBricks + n.coarseBricks;
    t->mPackedCount = n.narrowBricks + n.coarseBricks + n.farBricks;
    return t;
}

Tile::Counts Tile::counts() const {
    Counts n;
    n.nodes = mNodeCount;
    n.narrowNodes = mNarrowNodes;
    n.narrowLeaves = mNarrowLeafCount;
    n.wideLeaves = ownLeafCount() - mNarrowLeafCount;
    n.narrowBricks = mNarrowCount;
    n.coarseBricks = mCoarseEnd - mNarrowCount;
    n.farBricks = mPackedCount - mCoarseEnd;
    n.wideBricks = mBrickCount - mPackedCount;
    n.narrowGroups = mNarrowGroupCount;
    n.coarseGroups = mCoarseGroupEnd - mNarrowGroupCount;
    n.farGroups = mPackedGroupCount - mCoarseGroupEnd;
    n.wideGroups = mGroupCount - mPackedGroupCount;
    n.groupedLeaves = mGroupedLeafCount;
    return n;
}

std::size_t Tile::valueBytes(const Counts& n) {
    const std::size_t packedBricks = std::size_t(n.narrowBricks) + n.coarseBricks + n.farBricks;
    const std::size_t packedGroups = std::size_t(n.narrowGroups) + n.coarseGroups + n.farGroups;
    return std::size_t(n.narrowLeaves) * kNarrowLeafBytes + std::size_t(n.wideLeaves) * kWideLeafBytes +
           gridBytes(n.narrowBricks, packedBricks, packedBricks + n.wideBricks) +
           gridBytes(n.narrowGroups, packedGroups, packedGroups + n.wideGroups);
}

void Tile::Deleter::operator()(const Tile* t) const {
    t->~Tile();
    ::operator delete(const_cast<Tile*>(t));
}

Tile::~Tile() { mMagic = 0xdeadbeefdeadbeefull; }

std::size_t Tile::bytes() const { return layoutOf(counts()).total; }

std::vector<uint32_t> Tile::nodeWords() const {
    std::vector<uint32_t> out(mNodeCount);
    for (uint32_t i = 0; i < mNodeCount; ++i) out[i] = node(i);
    return out;
}

Tile::Quantised Tile::quantised() const {
    Quantised q;
    q.nodes = nodeWords();
    constexpr uint32_t kUnused = ~0u;
    std::vector<uint32_t> dense(mLeafCount, kUnused);
    for (uint32_t w : q.nodes)
        if (node::isLeaf(w)) dense[node::leafIndex(w)] = 0;
    uint32_t leaves = 0;
    for (uint32_t& number : dense)
        if (number != kUnused) number = leaves++;
    for (uint32_t& w : q.nodes)
        if (node::isLeaf(w)) w = node::makeLeaf(dense[node::leafIndex(w)], node::leafType(w));
    q.leafCorners.resize(std::size_t(leaves) * 8);
    for (uint32_t l = 0; l < mLeafCount; ++l)
        if (dense[l] != kUnused) leafValues(l, q.leafCorners.data() + 8 * std::size_t(dense[l]));
    q.brickValues.resize(std::size_t(mBrickCount) * 27);
    for (uint32_t b = 0; b < mBrickCount; ++b) brickValues(b, q.brickValues.data() + 27 * std::size_t(b));
    return q;
}

uint64_t Tile::computeChecksum() const {
    const Counts n = counts();
    const Layout l = layoutOf(n);
    uint64_t h = 0xcbf29ce484222325ull;
    h = fnv1a(h, &mLevel, sizeof mLevel);
    h = fnv1a(h, &mOrigin, sizeof mOrigin);
    h = fnv1a(h, &mScale, sizeof mScale);
    h = fnv1a(h, &mStep, sizeof mStep);
    h = fnv1a(h, &n.nodes, sizeof n.nodes);
    h = fnv1a(h, &n.narrowNodes, sizeof n.narrowNodes);
    const uint32_t items[] = {n.narrowLeaves, n.wideLeaves,   n.narrowBricks, n.coarseBricks, n.farBricks, n.wideBricks,
                              n.narrowGroups, n.coarseGroups, n.farGroups,    n.wideGroups,   n.groupedLeaves};
    h = fnv1a(h, items, sizeof items);
    // Every array, padding between them included (allocate leaves none uninitialised: build
    // writes each byte; alignment gaps are zeroed there).
    return fnv1a(h, at<unsigned char>(uint32_t(l.nodes)), l.total - l.nodes);
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

/// Quantisation steps per leaf step (Tile::leafStep): twice the whole number of them that 127
/// fill two finest cells, so 127 leaf steps span at least four finest cells (every corner of a
/// leaf of two finest cells in a 1-Lipschitz field) and 63 about two (every value of a brick of
/// finest cells, at most sqrt(3) cells from its centre). Depends only on the scale and the cell
/// size, never on the values, so a decoded tile re-encodes to the same bits.
int32_t leafStepOf(float scale, double finestCell) {
    const double steps = 2.0 * std::ceil(2.0 * finestCell / (127.0 * double(scale)));
    return steps >= 2.0 ? int32_t(std::min(steps, 32767.0)) : 2;
}

/// Division by a step (1 to 65535) of a numerator below 2^17 as one multiply: with
/// m = floor(2^40 / step) + 1, a * m / 2^40 exceeds a / step by under 2^-23, less than the
/// 1 / step that lies between a / step and the next whole number, so the floor is exact. An
/// integer division per value would dominate packing a tile's values
/// (docs/decisions/0003-bricks-and-packed-forms.md).
struct StepDivision {
    int32_t step;
    uint64_t magic;
    explicit StepDivision(int32_t s) : step(s), magic((uint64_t(1) << 40) / uint64_t(s) + 1) {}
    int32_t quotient(int32_t a) const { return int32_t((uint64_t(a) * magic) >> 40); }  ///< a / step, a in [0, 2^17)
};

/// Steps from `base` to the value nearest `q` with q's sign (inside stays inside), or false
/// when that needs more than 127 steps or leaves the 16-bit range.
inline bool narrowDelta(int32_t q, int32_t base, const StepDivision& d, int8_t& out) {
    const int32_t step = d.step;
    const int32_t diff = q - base;  // |diff| + step / 2 < 2^17: 16-bit values, steps below 2^16
    int32_t k = diff >= 0 ? d.quotient(diff + step / 2) : -d.quotient(-diff + step / 2);
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
/// (Inlined: every brick, group and leaf of every tile built asks.)
[[gnu::always_inline]] inline bool packs(const int16_t* q, int n, int32_t base, int32_t step, int8_t* out) {
    const StepDivision d(step);
    for (int i = 0; i < n; ++i)
        if (!narrowDelta(q[i], base, d, out[i])) return false;
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

namespace {
/// The forms a half grid (brick or leaf group) can take, in their numbering order.
enum GridForm : uint8_t { kNarrow, kCoarse, kFar, kWide };
constexpr std::size_t kGridForms = 4;

/// Packs the 27 values `q` of a half grid as steps from its centre (out[13] = 0) and says which
/// form holds them: leaf steps all within 63 (7 bits) or 127 (a byte), else far steps (two leaf
/// steps) within 127 where each value rounds to within a leaf step (no sign kept a step away),
/// else none (wide). Idempotent: a decoded value lies on its step, which it rounds to again; a
/// coarse-narrow grid keeps the step beyond 63 that made it one, and a far one a value beyond
/// 127 leaf steps (it was within one of the value that missed them, and even).
uint8_t packGrid(const int16_t* q, int32_t leafStep, int8_t* out) {
    if (packs(q, 27, q[13], leafStep, out)) {
        for (int g = 0; g < 27; ++g)
            if (out[g] < -63 || out[g] > 63) return kCoarse;
        return kNarrow;
    }
    if (!packs(q, 27, q[13], 2 * leafStep, out)) return kWide;
    for (int g = 0; g < 27; ++g)
        if (std::abs(int32_t(q[13]) + int32_t(out[g]) * 2 * leafStep - int32_t(q[g])) > leafStep) return kWide;
    return kFar;
}

/// Lone-leaf children of one cell: their leaves and which child each is.
struct Siblings {
    std::array<uint32_t, 8> leaf;
    std::array<uint8_t, 8> child;
    int count = 0;
};

/// Whether the siblings' corners (`corners(m)`: member m's 8 quantised values) agree wherever
/// two of them share a point; fills `grid` with them (half-grid order; other points untouched).
template <class Corners>
bool cornersAgree(const Siblings& s, const Corners& corners, std::array<int16_t, 27>& grid, std::array<bool, 27>& covered) {
    for (int m = 0; m < s.count; ++m) {
        const int16_t* v = corners(m);
        for (int c = 0; c < 8; ++c) {
            const auto p = std::size_t(brickPoint(s.child[std::size_t(m)], c));
            if (covered[p] && grid[p] != v[c]) return false;
            grid[p] = v[c];
            covered[p] = true;
        }
    }
    return true;
}

/// The leaf groups of a tile being built (Tile::build): for every cell with at least
/// Tile::kMinGroupLeaves lone-leaf children whose shared corners agree, one half grid holding
/// all their corners. Points no member covers take the centre's value (every child has the
/// centre as a corner), so decoding and building again gives the same grid.
struct LeafGroups {
    static constexpr uint32_t kNone = ~0u;
    std::vector<uint32_t> of;        ///< per leaf: its group, or kNone
    std::vector<uint8_t> child;      ///< per grouped leaf: which child of the group's cell it is
    std::vector<Siblings> apart;     ///< cells with enough lone leaves whose shared corners disagree
    std::vector<uint8_t> form;       ///< per group: packGrid's form
    std::vector<int16_t> values;     ///< 27 per group, half-grid order
    std::vector<int8_t> deltas;      ///< 27 per group, leaf steps from the centre (packed ones)
};

LeafGroups findLeafGroups(std::span<const uint32_t> nodes, std::span<const int16_t> leafCorners, int32_t leafStep) {
    const std::size_t leafCount = leafCorners.size() / 8;
    LeafGroups g;
    g.of.assign(leafCount, LeafGroups::kNone);
    g.child.assign(leafCount, 0);
    // Leaves referenced by exactly one word (a damaged file may share one; the file check
    // rejects it, and grouping must not hide it).
    std::vector<uint8_t> refs(leafCount, 0);
    for (uint32_t w : nodes)
        if (node::isLeaf(w) && node::leafIndex(w) < leafCount) refs[node::leafIndex(w)] = uint8_t(std::min(2, refs[node::leafIndex(w)] + 1));
    for (std::size_t i = 0; i < nodes.size(); ++i) {
        const uint32_t first = nodes[i];
        if (!node::isInternal(first) || first <= i || std::size_t(first) + 8 > nodes.size()) continue;
        Siblings sib;
        for (int c = 0; c < 8; ++c) {
            const uint32_t w = nodes[first + uint32_t(c)];
            if (!node::isLeaf(w)) continue;
            const uint32_t l = node::leafIndex(w);
            if (l >= leafCount || refs[l] != 1 || g.of[l] != LeafGroups::kNone) continue;
            sib.leaf[std::size_t(sib.count)] = l;
            sib.child[std::size_t(sib.count++)] = uint8_t(c);
        }
        if (sib.count < Tile::kMinGroupLeaves) continue;
        std::array<int16_t, 27> grid{};
        std::array<bool, 27> covered{};
        if (!cornersAgree(sib, [&](int m) { return leafCorners.data() + 8 * std::size_t(sib.leaf[std::size_t(m)]); }, grid, covered)) {
            g.apart.push_back(sib);
            continue;
        }
        for (std::size_t p = 0; p < 27; ++p)
            if (!covered[p]) grid[p] = grid[13];
        const auto id = uint32_t(g.form.size());
        for (int m = 0; m < sib.count; ++m) {
            g.of[sib.leaf[std::size_t(m)]] = id;
            g.child[sib.leaf[std::size_t(m)]] = sib.child[std::size_t(m)];
        }
        g.values.insert(g.values.end(), grid.begin(), grid.end());
        g.deltas.resize(g.deltas.size() + 27);
        g.form.push_back(packGrid(grid.data(), leafStep, g.deltas.data() + 27 * std::size_t(id)));
    }
    return g;
}

/// How an own lone leaf is stored; own leaves are numbered narrow, then wide.
enum OwnLeafForm : uint8_t { kLeafNarrow, kLeafWide, kGrouped };

}  // namespace

/// The parts of Tile::build that pack one kind of item, with access to the tile's layout.
struct Tile::Packing {
    /// Each lone leaf's form (leafForm) and, for narrow ones, its 7 steps (leafDeltas, 7 per leaf):
    /// grouped leaves are marked kGrouped; a copied narrow own leaf keeps its source's steps; the
    /// others are packed narrow where they fit. Then siblings left apart that would agree once
    /// decoded are made wide (see below).
    /// `from`, `copied`: the tile copied from (or null) and per leaf the one it copies (TileCopies).
    static void ownLeaves(std::span<const int16_t> leafCorners, const LeafGroups& groups, const Tile* from,
                          std::span<const uint32_t> copied, int32_t leafStep, std::vector<uint8_t>& leafForm,
                          std::vector<int8_t>& leafDeltas) {
        const auto leafCount = uint32_t(leafCorners.size() / 8);
        for (uint32_t l = 0; l < leafCount; ++l) {
            const int16_t* q = leafCorners.data() + 8 * std::size_t(l);
            if (groups.of[l] != LeafGroups::kNone) {
                leafForm[l] = kGrouped;
                continue;
            }
            // A copied narrow own leaf keeps its packing (the values alone decide it); a wide one
            // is packed again, since it may have been wide only for siblings it no longer has.
            if (from && copied[l] != TileCopies::kNotCopied && copied[l] >= 8 * from->mGroupCount &&
                copied[l] - 8 * from->mGroupCount < from->mNarrowLeafCount) {
                const uint32_t i = copied[l] - 8 * from->mGroupCount;
                std::memcpy(leafDeltas.data() + 7 * std::size_t(l), from->at<int8_t>(from->mLeafDeltasAt) + 7 * std::size_t(i), 7);
                leafForm[l] = kLeafNarrow;
                continue;
            }
            leafForm[l] = packs(q + 1, 7, q[0], leafStep, leafDeltas.data() + 7 * std::size_t(l)) ? kLeafNarrow : kLeafWide;
        }
        // Siblings left apart (their shared corners differ) must still differ once decoded, or
        // building the tile again would group them: where their packed corners would agree (rare:
        // each rounds from its own corner 0), they stay wide, whose values are exact.
        for (const Siblings& sib : groups.apart) {
            std::array<std::array<int16_t, 8>, 8> decoded;
            for (int m = 0; m < sib.count; ++m) {
                const uint32_t l = sib.leaf[std::size_t(m)];
                const int16_t* q = leafCorners.data() + 8 * std::size_t(l);
                auto& v = decoded[std::size_t(m)];
                if (leafForm[l] == kLeafNarrow)
                    unpackLeaf(q[0], leafDeltas.data() + 7 * std::size_t(l), leafStep, v.data());
                else
                    std::copy(q, q + 8, v.begin());
            }
            std::array<int16_t, 27> grid{};
            std::array<bool, 27> covered{};
            if (cornersAgree(sib, [&](int m) { return decoded[std::size_t(m)].data(); }, grid, covered))
                for (int m = 0; m < sib.count; ++m)
                    if (leafForm[sib.leaf[std::size_t(m)]] != kGrouped) leafForm[sib.leaf[std::size_t(m)]] = kLeafWide;  // (a damaged tree can group it elsewhere)
        }
    }

    /// Half grids (bricks, or leaf groups) written into tile `t`'s arrays: packed ones as centre and
    /// steps (7-bit fields or bytes, the centre's 0 left out) at `basesAt`/`stepsAt`, wide ones as
    /// they are at `wideAt`. `number`: each one's number in the tile; `narrow`, `packed`: the counts
    /// of narrow and of packed ones. `copied`: per item, the bytes of its steps in the tile it was
    /// copied from, or null (may be shorter than `forms`).
    static void writeGrids(Tile* t, std::span<const int16_t> values, const std::vector<uint8_t>& forms,
                           std::span<const int8_t> steps, const std::vector<uint32_t>& number, uint32_t narrow,
                           uint32_t packed, uint32_t basesAt, uint32_t stepsAt, uint32_t wideAt,
                           const std::vector<const unsigned char*>& copied) {
        auto* bases = const_cast<int16_t*>(t->at<int16_t>(basesAt));
        auto* packedSteps = const_cast<unsigned char*>(t->at<unsigned char>(stepsAt));
        auto* wide = const_cast<int16_t*>(t->at<int16_t>(wideAt));
        for (std::size_t k = 0; k < forms.size(); ++k) {
            const int16_t* q = values.data() + 27 * k;
            const int8_t* d = steps.data() + 27 * k;
            const uint32_t i = number[k];
            if (forms[k] == kWide) {
                std::memcpy(wide + 27 * std::size_t(i - packed), q, 54);
                continue;
            }
            bases[i] = q[13];
            unsigned char* p = packedSteps + gridStepsOffset(narrow, i);  // zeroed by allocate
            if (k < copied.size() && copied[k]) {
                std::memcpy(p, copied[k], forms[k] == kNarrow ? kNarrowGridSteps : kCoarseGridSteps);
                continue;
            }
            for (int j = 0; j < 26; ++j) {
                const auto field = uint8_t(d[gridPointOf(j)]);
                if (forms[k] != kNarrow) {
                    p[j] = field;
                    continue;
                }
                const unsigned bit = 7u * unsigned(j), bits = field & 0x7fu;  // 7-bit fields, little-endian
                p[bit >> 3] = uint8_t(p[bit >> 3] | (bits << (bit & 7u)));
                if ((bit & 7u) > 1u) p[(bit >> 3) + 1] = uint8_t(p[(bit >> 3) + 1] | (bits >> (8u - (bit & 7u))));
            }
        }
    }
};

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
    // gives it back) and, in build, bricks and narrow own leaves their packing.
    const Tile* from = copies.from && scale == copies.from->mScale && leafStepOf(scale, finestCell) == copies.from->mStep
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
            // A packed copy takes its steps' bytes from `from` (build): only its centre is read.
            const uint32_t i = copies.bricks[b];
            if (i < from->mPackedCount)
                bricks[27 * b + 13] = from->brickValue(i, 13);
            else
                from->brickValues(i, &bricks[27 * b]);
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
    const int32_t leafStep = leafStepOf(scale, finestCell);
    // Which form each brick takes (packGrid: narrow, coarse-narrow, far or wide), and their new
    // numbers (in that order, each form's bricks in their order).
    std::vector<int8_t> deltas(std::size_t(brickCount) * 27);
    std::vector<uint8_t> form(brickCount);
    // A copied brick's form and steps are its source's: packing its decoded values again would
    // find the same (the encoding is idempotent), at the price of every value. Its steps' bytes
    // are copied as they are (the same layout per form), so only its centre was decoded
    // (create). (Narrow own leaves likewise below; wide own leaves and grouped ones are packed
    // again.)
    const Tile* from = copies.from;
    std::vector<const unsigned char*> copiedSteps(from ? brickCount : 0, nullptr);
    for (uint32_t b = 0; b < brickCount; ++b) {
        const int16_t* q = brickValues.data() + 27 * std::size_t(b);
        int8_t* d = deltas.data() + 27 * std::size_t(b);
        if (from && copies.bricks[b] != TileCopies::kNotCopied) {
            const uint32_t i = copies.bricks[b];
            form[b] = uint8_t(from->brickForm(i));
            if (form[b] != kWide) copiedSteps[b] = from->at<unsigned char>(from->mBrickDeltasAt) + gridStepsOffset(from->mNarrowCount, i);
            continue;
        }
        form[b] = packGrid(q, leafStep, d);
    }
    std::array<uint32_t, kGridForms> brickForms;
    const std::vector<uint32_t> renumber = numberByForm(form, brickForms);
    const uint32_t narrowCount = brickForms[kNarrow];
    const uint32_t packedCount = narrowCount + brickForms[kCoarse] + brickForms[kFar];

    // Leaf groups: the lone-leaf children of one cell share corners, so when a cell has at
    // least kMinGroupLeaves of them they are stored as its half grid, packed in the forms of a
    // brick.
    const auto leafCount = uint32_t(leafCorners.size() / 8);
    const LeafGroups groups = findLeafGroups(nodes, leafCorners, leafStep);
    std::array<uint32_t, kGridForms> groupForms;
    const std::vector<uint32_t> renumberGroup = numberByForm(groups.form, groupForms);
    const auto groupCount = uint32_t(groups.form.size());
    const uint32_t packedGroups = groupForms[kNarrow] + groupForms[kCoarse] + groupForms[kFar];

    // Own lone leaves: corner 0 exact, the others in leaf steps from it.
    std::vector<int8_t> leafDeltas(std::size_t(leafCount) * 7);
    std::vector<uint8_t> leafForm(leafCount);
    Packing::ownLeaves(leafCorners, groups, from, copies.leaves, leafStep, leafForm, leafDeltas);
    std::array<uint32_t, 3> leafForms;
    const std::vector<uint32_t> renumberLeaf = numberByForm(leafForm, leafForms);
    const uint32_t narrowLeafCount = leafForms[kLeafNarrow], ownLeafCount = leafForms[kLeafNarrow] + leafForms[kLeafWide];
    // Leaf indices: 8 per group (slot 8g + child), then the own leaves.
    auto leafSlot = [&](uint32_t l) {
        return groups.of[l] != LeafGroups::kNone ? 8 * renumberGroup[groups.of[l]] + groups.child[l]
                                                : 8 * groupCount + renumberLeaf[l];
    };

    // Node words with the new numbers; 16 bits each when every one fits (node::narrow).
    std::vector<uint32_t> words(nodes.size());
    bool narrowNodes = true;
    for (std::size_t i = 0; i < nodes.size(); ++i) {
        const uint32_t w = nodes[i];
        if (node::isBrick(w) && node::brickIndex(w) < brickCount)
            words[i] = node::makeBrick(renumber[node::brickIndex(w)]);
        else if (node::isLeaf(w) && node::leafIndex(w) < leafCount)
            words[i] = node::makeLeaf(leafSlot(node::leafIndex(w)), node::leafType(w));
        else
            words[i] = w;
        narrowNodes = narrowNodes && node::fitsNarrow(words[i]);
    }

    Counts n;
    n.nodes = uint32_t(nodes.size());
    n.narrowNodes = narrowNodes;
    n.narrowLeaves = narrowLeafCount;
    n.wideLeaves = ownLeafCount - narrowLeafCount;
    n.narrowBricks = narrowCount;
    n.coarseBricks = brickForms[kCoarse];
    n.farBricks = brickForms[kFar];
    n.wideBricks = brickCount - packedCount;
    n.narrowGroups = groupForms[kNarrow];
    n.coarseGroups = groupForms[kCoarse];
    n.farGroups = groupForms[kFar];
    n.wideGroups = groupCount - packedGroups;
    n.groupedLeaves = leafCount - ownLeafCount;
    Tile* t = allocate(n);
    t->mStep = int16_t(leafStep);
    if (narrowNodes) {
        auto* out = const_cast<uint16_t*>(t->at<uint16_t>(t->mNodesAt));
        for (std::size_t i = 0; i < words.size(); ++i) out[i] = node::narrow(words[i]);
    } else {
        std::copy(words.begin(), words.end(), const_cast<uint32_t*>(t->at<uint32_t>(t->mNodesAt)));
    }
    auto* leafBases = const_cast<int16_t*>(t->at<int16_t>(t->mLeafBasesAt));
    auto* leafPacked = const_cast<int8_t*>(t->at<int8_t>(t->mLeafDeltasAt));
    auto* wideLeaves = const_cast<int16_t*>(t->at<int16_t>(t->mWideLeavesAt));
    for (uint32_t l = 0; l < leafCount; ++l) {
        if (leafForm[l] == kGrouped) continue;
        const int16_t* q = leafCorners.data() + 8 * std::size_t(l);
        const uint32_t i = renumberLeaf[l];
        if (leafForm[l] == kLeafNarrow) {
            leafBases[i] = q[0];
            std::memcpy(leafPacked + 7 * std::size_t(i), leafDeltas.data() + 7 * std::size_t(l), 7);
        } else {
            std::memcpy(wideLeaves + 8 * std::size_t(i - narrowLeafCount), q, 16);
        }
    }
    // Bricks and groups alike (Packing::writeGrids).
    Packing::writeGrids(t, brickValues, form, deltas, renumber, narrowCount, packedCount, t->mBrickBasesAt,
                        t->mBrickDeltasAt, t->mWideBricksAt, copiedSteps);
    Packing::writeGrids(t, groups.values, groups.form, groups.deltas, renumberGroup, groupForms[kNarrow], packedGroups,
                        t->mGroupBasesAt, t->mGroupDeltasAt, t->mWideGroupsAt, {});
    return finish(t, level, latticeOrigin, scale, version);
}

TilePtr Tile::finish(Tile* t, int level, glm::uvec3 latticeOrigin, float scale, uint64_t version) {
    t->mLevel = int8_t(level);
    for (int a = 0; a < 3; ++a) t->mOrigin[a] = uint16_t(latticeOrigin[a]);
    t->mScale = scale;
    t->mVersion = version;
    t->mChecksum = t->computeChecksum();
    t->mMagic = kAlive;
    return TilePtr(t, Deleter{});
}

}  // namespace kizamu::adf
