// SPDX-License-Identifier: Apache-2.0
/// @file adf.cpp
/// @brief Snapshot lookup, trilinear reconstruction, copy-on-write building and the accessor.
#include "adf/adf.h"

#include "adf/colour_layer.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cassert>
#include <stdexcept>
#include <unordered_set>

namespace kizamu::adf {

namespace {

/// Lattice coordinates of `pWorld`, clamped into the domain; `outside` gets the clamped-off
/// distance in lattice units.
inline glm::vec3 toLattice(const Adf& adf, const glm::vec3& pWorld, float& outside) {
    const glm::vec3 u = (pWorld - adf.originWorldF()) * adf.latticePerMetre();
    const glm::vec3 c = clampToLattice(u, adf.latticeTop());
    outside = (c == u) ? 0.0f : glm::length(u - c);
    return c;
}

}  // namespace

LeafRef Adf::findLeaf(glm::uvec3 p) const noexcept {
    const LeafCell c = locateLeaf(p);
    LeafRef r;
    r.tile = c.tile;
    r.latticeOrigin = c.origin;
    r.latticeSize = c.size;
    r.level = c.level;
    r.brickChild = c.brickChild;
    c.corners(r.corners);
    return r;
}

Sample Adf::sample(const glm::vec3& pWorld) const noexcept {
    float outside;
    const glm::vec3 u = toLattice(*this, pWorld, outside);
    const LeafRef leaf = findLeaf(glm::uvec3(u));
    const float inv = 1.0f / float(leaf.latticeSize);
    Sample s = trilinear(leaf.corners, (u - glm::vec3(leaf.latticeOrigin)) * inv);
    s.gradient *= inv * mLatticePerMetre;
    s.distance += outside * mMetresPerLattice;
    return s;
}

namespace {

/// latticeDistance's answer once the leaf holding the point (clamped into the domain) is known.
[[gnu::always_inline]] inline float latticeValue(const LeafCell& leaf, glm::uvec3 p) {
    const int c = leaf.cornerIndex(p);
    if (c >= 0) return leaf.corner(c);
    float v[8];
    leaf.corners(v);
    return trilinear(v, glm::vec3(p - leaf.origin) / float(leaf.size)).distance;
}

}  // namespace

float Adf::latticeDistance(glm::uvec3 p) const noexcept {
    assert(p.x <= mDomain.latticeSize() && p.y <= mDomain.latticeSize() && p.z <= mDomain.latticeSize() &&
           "latticeDistance needs a point of the domain's lattice");
    // A point on the domain's far faces is a corner of the cell below it.
    return latticeValue(locateLeaf(glm::min(p, glm::uvec3(mDomain.latticeSize() - 1))), p);
}

void Adf::latticeDistances(std::span<const glm::uvec3> points, std::span<float> out) const noexcept {
    assert(points.size() == out.size() && "latticeDistances writes one value per point");
    // As many as a LOD's batch (AdfSampler's kBatch, mesh/lod.cpp): all of its points side by
    // side overlap more loads than fewer lanes (docs/decisions/0023-lod-coarse-lattice.md).
    constexpr std::size_t kLanes = 64;
    const glm::uvec3 last(mDomain.latticeSize() - 1);
    for (std::size_t first = 0; first < points.size(); first += kLanes) {
        const std::size_t n = std::min(kLanes, points.size() - first);
        glm::uvec3 q[kLanes];
        const Tile* tile[kLanes];
        uint32_t w[kLanes];
        int shift[kLanes];
        for (std::size_t i = 0; i < n; ++i) {
            q[i] = glm::min(points[first + i], last);
            tile[i] = tileAtSlot(q[i] >> uint32_t(mDomain.tileSpan()));
        }
        for (std::size_t i = 0; i < n; ++i) {
            shift[i] = mDomain.maxLevel - tile[i]->level();
            w[i] = tile[i]->node(0);
        }
        // A level of every lane's descent at a time: the loads of different lanes are
        // independent, so the core overlaps them. Each pass visits only the lanes still
        // descending (they end at depths up to a tile's span apart).
        uint8_t active[kLanes];
        std::size_t m = 0;
        for (std::size_t i = 0; i < n; ++i)
            if (node::isInternal(w[i])) active[m++] = uint8_t(i);
        while (m > 0) {
            std::size_t still = 0;
            for (std::size_t j = 0; j < m; ++j) {
                const std::size_t i = active[j];
                w[i] = tile[i]->node(w[i] + uint32_t(childAt(q[i], shift[i]--)));
                if (node::isInternal(w[i])) active[still++] = uint8_t(i);
            }
            m = still;
        }
        for (std::size_t i = 0; i < n; ++i) out[first + i] = latticeValue(leafOfWord(tile[i], w[i], shift[i], q[i]), points[first + i]);
    }
}

void AdfAccessor::descend(glm::uvec3 p) noexcept {
    // Climb to the smallest cached cell that still contains p.
    while (mDepth > 0) {
        const PathCell& cell = mPath[mDepth - 1];
        const glm::uvec3 rel = p - cell.origin;
        if (rel.x < cell.size && rel.y < cell.size && rel.z < cell.size) break;
        --mDepth;
    }
    const Domain& d = mAdf->domain();
    if (mDepth == 0) {
        mTile = mAdf->tileAtSlot(p >> uint32_t(d.tileSpan()));
        mPath[0] = {mTile->latticeOrigin(), d.cellLattice(mTile->level()), mTile->node(0)};
        mDepth = 1;
    }
    for (;;) {
        const PathCell cell = mPath[mDepth - 1];
        const uint32_t half = cell.size >> 1;
        const glm::uvec3 rel = p - cell.origin;
        const uint32_t cx = rel.x >= half, cy = rel.y >= half, cz = rel.z >= half;
        const int child = int(cx | (cy << 1) | (cz << 2));
        const glm::uvec3 childOrigin = cell.origin + glm::uvec3(cx, cy, cz) * half;
        if (node::isInternal(cell.word)) {
            mPath[mDepth++] = {childOrigin, half, mTile->node(cell.word + uint32_t(child))};
            continue;
        }
        const float scale = mTile->scale();
        if (node::isLeaf(cell.word)) {
            mTile->leafCorners(node::leafIndex(cell.word), mCorners);
            mOrigin = cell.origin;
            mSize = cell.size;
        } else {
            const uint32_t brick = node::brickIndex(cell.word);
            for (int k = 0; k < 8; ++k) mCorners[k] = float(mTile->brickValue(brick, brickPoint(child, k))) * scale;
            mOrigin = childOrigin;
            mSize = half;
        }
        mInvSize = 1.0f / float(mSize);
        mGradientScale = mInvSize * mLatticePerMetre;
        return;
    }
}

void Adf::forEachTile(const std::function<void(const Tile&)>& fn) const {
    const uint32_t n = mDomain.slotsPerAxis();
    for (uint32_t z = 0; z < n; ++z)
        for (uint32_t y = 0; y < n; ++y)
            for (uint32_t x = 0; x < n; ++x) {
                const Tile* t = tileAtSlot({x, y, z});
                // A tile is visited at the slot of its own origin only.
                const glm::uvec3 first = t->latticeOrigin() >> uint32_t(mDomain.tileSpan());
                if (first == glm::uvec3(x, y, z)) fn(*t);
            }
}

Adf::Stats Adf::computeStats() const {
    Stats s;
    glm::uvec3 lo(~0u), hi(0u);
    forEachTile([&](const Tile& t) {
        forEachLeaf(t, mDomain.maxLevel, [&](const LeafRef& leaf) {
            if (leaf.type() != CellType::Boundary) return;
            ++s.boundaryCells;
            lo = glm::min(lo, leaf.latticeOrigin);
            hi = glm::max(hi, leaf.latticeOrigin + leaf.latticeSize);
        });
        ++s.tiles;
        if (t.level() < mDomain.tileLevel()) ++s.coarseTiles;
        s.cells += t.cellCount();
        s.bricks += t.brickCount();
        s.narrowBricks += t.narrowBrickCount();
        s.coarseBricks += t.coarseBrickCount();
        s.farBricks += t.farBrickCount();
        s.narrowLeaves += t.narrowLeafCount();
        s.groupedLeaves += t.groupedLeafCount();
        for (uint32_t i = 0; i < t.nodeCount(); ++i) {
            const uint32_t w = t.node(i);
            s.packedGroupedLeaves += node::isLeaf(w) && node::leafIndex(w) < 8 * t.packedGroupCount();
        }
        s.nodes += t.nodeCount();
        s.tileBytes += t.bytes();
    });
    s.tableBytes = mRoot.size() * (sizeof(uintptr_t) + sizeof(ChunkPtr) + sizeof(TilePtr));
    std::unordered_set<const void*> chunks;
    for (const auto& c : mChunkOwners)
        if (c && chunks.insert(c.get()).second) s.tableBytes += sizeof(Chunk) + c->owners.capacity() * sizeof(TilePtr);
    if (mColours) {
        s.paintedPoints = mColours->pointCount();
        s.colourBytes = mColours->bytes();
    }
    if (s.boundaryCells > 0) {
        const double h = mDomain.finestCellSize();
        s.surfaceBounds = {mDomain.originWorld + glm::dvec3(lo) * h, mDomain.originWorld + glm::dvec3(hi) * h};
    }
    return s;
}

// ---- builder ----

AdfBuilder::AdfBuilder(const Domain& domain, const GenerationSettings& settings)
    : mAdf(new Adf()) {
    if (!domain.valid()) throw std::invalid_argument("invalid ADF domain");
    Adf& a = *mAdf;
    a.mDomain = domain;
    a.mSettings = settings;
    a.mChunkLevels = std::min(3, domain.tileLevel());
    a.mChunkDim = 1u << a.mChunkLevels;
    a.mRootDim = 1u << (domain.tileLevel() - a.mChunkLevels);
    const std::size_t rootSize = std::size_t(a.mRootDim) * a.mRootDim * a.mRootDim;
    a.mRoot.assign(rootSize, 0);
    a.mChunkOwners.resize(rootSize);
    a.mRootTileOwners.resize(rootSize);
    a.mOriginF = glm::vec3(domain.originWorld);
    a.mLatticePerMetre = float(double(domain.latticeSize()) / domain.sizeWorld);
    a.mMetresPerLattice = float(domain.finestCellSize());
}

AdfBuilder::AdfBuilder(const Adf& base) : mAdf(new Adf(base)) {
    mOwnChunks.resize(mAdf->mRoot.size());
}

void AdfBuilder::setTile(TilePtr tile) {
    Adf& a = *mAdf;
    if (mOwnChunks.size() != a.mRoot.size()) mOwnChunks.resize(a.mRoot.size());
    const Domain& d = a.mDomain;
    assert(tile->level() <= d.tileLevel());
    const int span = d.tileSpan();
    const glm::uvec3 slot0 = tile->latticeOrigin() >> uint32_t(span);
    const uint32_t slots = 1u << (d.tileLevel() - tile->level());
    const uint32_t cd = a.mChunkDim;
    if (slots >= cd) {
        // The tile covers whole chunks: tag the root entries.
        const glm::uvec3 r0 = slot0 / cd;
        const uint32_t rn = slots / cd;
        for (uint32_t z = r0.z; z < r0.z + rn; ++z)
            for (uint32_t y = r0.y; y < r0.y + rn; ++y)
                for (uint32_t x = r0.x; x < r0.x + rn; ++x) {
                    const std::size_t i = (std::size_t(z) * a.mRootDim + y) * a.mRootDim + x;
                    a.mRoot[i] = reinterpret_cast<uintptr_t>(tile.get()) | 1u;
                    a.mRootTileOwners[i] = tile;
                    a.mChunkOwners[i] = nullptr;
                    mOwnChunks[i] = {};
                }
        return;
    }
    // Inside one chunk: copy it on first write.
    const glm::uvec3 r = slot0 / cd;
    const std::size_t ri = (std::size_t(r.z) * a.mRootDim + r.y) * a.mRootDim + r.x;
    OwnChunk& own = mOwnChunks[ri];
    Chunk* chunk = own.chunk.get();
    if (!chunk) {
        auto fresh = std::make_shared<Chunk>();
        const uintptr_t e = a.mRoot[ri];
        if (e & 1u) {
            const TilePtr& owner = a.mRootTileOwners[ri];
            fresh->tiles.fill(owner.get());
            fresh->owners.assign(1, owner);
        } else if (e != 0) {
            *fresh = *reinterpret_cast<const Chunk*>(e);
        }
        chunk = fresh.get();
        own.chunk = fresh;
        own.kept = fresh->owners.size();
        own.replaced.clear();
        a.mRoot[ri] = reinterpret_cast<uintptr_t>(chunk);
        a.mChunkOwners[ri] = fresh;
        a.mRootTileOwners[ri] = nullptr;
    }
    const glm::uvec3 c0 = slot0 % cd;
    for (uint32_t z = c0.z; z < c0.z + slots; ++z)
        for (uint32_t y = c0.y; y < c0.y + slots; ++y)
            for (uint32_t x = c0.x; x < c0.x + slots; ++x) {
                const std::size_t i = (std::size_t(z) * cd + y) * cd + x;
                if (chunk->tiles[i] && chunk->tiles[i] != tile.get()) own.replaced.push_back(chunk->tiles[i]);
                chunk->tiles[i] = tile.get();
            }
    chunk->owners.push_back(std::move(tile));  // duplicates and replaced tiles go in build()
}

void AdfBuilder::setColours(std::shared_ptr<const ColourLayer> colours) {
    if (colours && !(colours->domain() == mAdf->mDomain)) throw std::invalid_argument("colour layer made for another domain");
    mAdf->mColours = std::move(colours);
}

const Tile* AdfBuilder::tileAtSlot(glm::uvec3 slot) const {
    // An unassigned root entry answers null here; a chunk being filled answers null for its
    // unassigned slots through the snapshot's own lookup.
    const Adf& a = *mAdf;
    const glm::uvec3 r = slot >> uint32_t(a.mChunkLevels);
    if (a.mRoot[(r.z * a.mRootDim + r.y) * a.mRootDim + r.x] == 0) return nullptr;
    return a.tileAtSlot(slot);
}

AdfPtr AdfBuilder::build(uint64_t version) {
    Adf& a = *mAdf;
    for (uintptr_t e : a.mRoot)
        if (e == 0) throw std::logic_error("ADF builder: a chunk was never assigned");
    // Only a chunk this builder wrote can hold an unassigned slot (a shared one was checked when
    // its builder published it): an edit checks the chunks it touched, not every slot (262k at
    // level 12). Each written chunk keeps one owner per tile it still shows, sorted: only the
    // tiles this builder appended need sorting, and only the ones it overwrote can have gone,
    // so an edit never sorts all of a chunk's slots (docs/decisions/0008-two-level-tile-table.md).
    auto byTile = [](const TilePtr& x, const TilePtr& y) { return x.get() < y.get(); };
    for (OwnChunk& own : mOwnChunks) {
        Chunk* chunk = own.chunk.get();
        if (!chunk) continue;
        const auto used = chunk->tiles.begin() + std::ptrdiff_t(a.mChunkDim) * a.mChunkDim * a.mChunkDim;
        if (std::find(chunk->tiles.begin(), used, nullptr) != used)
            throw std::logic_error("ADF builder: a tile slot was never assigned");
        auto& owners = chunk->owners;
        const auto kept = owners.begin() + std::ptrdiff_t(own.kept);
        std::sort(kept, owners.end(), byTile);
        std::inplace_merge(owners.begin(), kept, owners.end(), byTile);
        owners.erase(std::unique(owners.begin(), owners.end()), owners.end());
        std::vector<const Tile*>& gone = own.replaced;  // overwritten and shown nowhere any more
        std::sort(gone.begin(), gone.end());
        gone.erase(std::unique(gone.begin(), gone.end()), gone.end());
        if (!gone.empty()) {
            for (auto slot = chunk->tiles.begin(); slot != used && !gone.empty(); ++slot)
                if (const auto at = std::lower_bound(gone.begin(), gone.end(), *slot); at != gone.end() && *at == *slot) gone.erase(at);
            std::erase_if(owners, [&](const TilePtr& t) { return std::binary_search(gone.begin(), gone.end(), t.get()); });
        }
        owners.shrink_to_fit();
    }
    a.mVersion = version;
    mOwnChunks.clear();
    AdfPtr out = std::move(mAdf);
    mAdf.reset();
    return out;
}

}  // namespace kizamu::adf
