// SPDX-License-Identifier: Apache-2.0
/// @file colour_layer.cpp
/// @brief ColourTile and ColourLayer lookups, copy-on-write replacement, ColourAccessor.
#include "adf/colour_layer.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <functional>
#include <stdexcept>

namespace kizamu::adf {

namespace {

/// Lattice coordinates of `pWorld`, clamped into [0, top] per axis (NaN to 0).
glm::vec3 latticeOf(const glm::vec3& pWorld, const glm::vec3& origin, float perMetre, float top) {
    const glm::vec3 u = (pWorld - origin) * perMetre;
    auto c = [top](float x) { return x > 0.0f ? (x < top ? x : top) : 0.0f; };
    return {c(u.x), c(u.y), c(u.z)};
}

/// Slot key and local point index of lattice point `p` (already below latticeSize()).
inline void split(const Domain& d, glm::uvec3 p, uint32_t& key, uint32_t& local) {
    const uint32_t span = uint32_t(d.tileSpan()), mask = (1u << span) - 1u, n = d.slotsPerAxis();
    const glm::uvec3 s = p >> span;
    key = (s.z * n + s.y) * n + s.x;
    local = ((p.z & mask) << (2 * span)) | ((p.y & mask) << span) | (p.x & mask);
}

inline glm::uvec3 clampPoint(glm::uvec3 p, uint32_t last) { return glm::min(p, glm::uvec3(last)); }

}  // namespace

// ---- ColourTile ----

ColourTile::ColourTile(std::vector<uint32_t> points, std::vector<Rgb8> colours)
    : mPoints(std::move(points)), mColours(std::move(colours)) {
    assert(!mPoints.empty() && mPoints.size() == mColours.size() && "a colour tile needs one colour per point");
    assert(std::adjacent_find(mPoints.begin(), mPoints.end(), std::greater_equal<>()) == mPoints.end() &&
           "colour tile points must be strictly increasing");
}

const Rgb8* ColourTile::find(uint32_t point) const noexcept {
    const auto it = std::lower_bound(mPoints.begin(), mPoints.end(), point);
    if (it == mPoints.end() || *it != point) return nullptr;
    return &mColours[std::size_t(it - mPoints.begin())];
}

// ---- ColourLayer ----

ColourLayer::ColourLayer(const Domain& domain, Rgb8 base) : mDomain(domain), mBase(base) {}

std::size_t ColourLayer::pointCount() const {
    std::size_t n = 0;
    for (const ColourTilePtr& t : mTiles) n += t->size();
    return n;
}

std::size_t ColourLayer::bytes() const {
    std::size_t n = mSlots.size() * (sizeof(uint32_t) + sizeof(ColourTilePtr));
    for (const ColourTilePtr& t : mTiles) n += t->bytes();
    return n;
}

const ColourTile* ColourLayer::tileAt(uint32_t key) const noexcept {
    const auto it = std::lower_bound(mSlots.begin(), mSlots.end(), key);
    if (it == mSlots.end() || *it != key) return nullptr;
    return mTiles[std::size_t(it - mSlots.begin())].get();
}

Rgb8 ColourLayer::colourAtLattice(glm::uvec3 p) const noexcept {
    uint32_t key, local;
    split(mDomain, clampPoint(p, mDomain.latticeSize() - 1), key, local);
    const ColourTile* t = tileAt(key);
    const Rgb8* c = t ? t->find(local) : nullptr;
    return c ? *c : mBase;
}

Rgb8 ColourLayer::colourAt(const glm::vec3& pWorld) const noexcept {
    ColourAccessor acc(*this);
    return acc.colourAt(pWorld);
}

ColourLayerPtr ColourLayer::withTiles(std::vector<std::pair<uint32_t, ColourTilePtr>> changes) const {
    std::sort(changes.begin(), changes.end(), [](const auto& l, const auto& r) { return l.first < r.first; });
    auto out = std::make_shared<ColourLayer>(mDomain, mBase);
    out->mSlots.reserve(mSlots.size() + changes.size());
    out->mTiles.reserve(mSlots.size() + changes.size());
    // Merge two sorted lists; a change wins over the old tile and a null change erases it.
    std::size_t i = 0, j = 0;
    while (i < mSlots.size() || j < changes.size()) {
        if (j == changes.size() || (i < mSlots.size() && mSlots[i] < changes[j].first)) {
            out->mSlots.push_back(mSlots[i]);
            out->mTiles.push_back(mTiles[i]);
            ++i;
            continue;
        }
        assert((j + 1 == changes.size() || changes[j].first != changes[j + 1].first) && "duplicate colour slot change");
        assert(uint64_t(changes[j].first) < uint64_t(mDomain.slotsPerAxis()) * mDomain.slotsPerAxis() * mDomain.slotsPerAxis() &&
               "colour slot key outside the domain");
        if (i < mSlots.size() && mSlots[i] == changes[j].first) ++i;
        if (changes[j].second) {
            out->mSlots.push_back(changes[j].first);
            out->mTiles.push_back(std::move(changes[j].second));
        }
        ++j;
    }
    return out;
}

ColourLayerPtr ColourLayer::create(const Domain& domain, Rgb8 base, std::vector<uint32_t> keys,
                                   std::vector<ColourTilePtr> tiles) {
    const uint64_t n = domain.slotsPerAxis();
    if (keys.size() != tiles.size()) throw std::invalid_argument("colour layer: one tile per slot key");
    for (std::size_t i = 0; i < keys.size(); ++i) {
        if (keys[i] >= n * n * n) throw std::invalid_argument("colour layer: slot key outside the domain");
        if (i > 0 && keys[i] <= keys[i - 1]) throw std::invalid_argument("colour layer: slot keys not increasing");
        if (!tiles[i]) throw std::invalid_argument("colour layer: a painted slot has no tile");
    }
    auto out = std::make_shared<ColourLayer>(domain, base);
    out->mSlots = std::move(keys);
    out->mTiles = std::move(tiles);
    return out;
}

// ---- blending and the accessor ----

Rgb8 blendColours(const Rgb8 (&c)[8], const glm::vec3& f) noexcept {
    bool same = true;
    for (int k = 1; k < 8; ++k) same = same && c[k] == c[0];
    if (same) return c[0];  // exact, and the common case (all unpainted)
    glm::vec3 sum(0.0f);
    for (int k = 0; k < 8; ++k) {
        const float w = ((k & 1) ? f.x : 1.0f - f.x) * ((k & 2) ? f.y : 1.0f - f.y) * ((k & 4) ? f.z : 1.0f - f.z);
        sum += w * glm::vec3(c[k]);
    }
    auto byte = [](float v) { return uint8_t(std::clamp(std::floor(v + 0.5f), 0.0f, 255.0f)); };
    return {byte(sum.x), byte(sum.y), byte(sum.z)};
}

ColourAccessor::ColourAccessor(const ColourLayer& layer)
    : mLayer(&layer), mOriginWorld(glm::vec3(layer.domain().originWorld)),
      mLatticePerMetre(float(double(layer.domain().latticeSize()) / layer.domain().sizeWorld)),
      mTop(float(layer.domain().latticeSize()) * (1.0f - 1e-7f)) {}

const ColourTile* ColourAccessor::tileOf(uint32_t key) noexcept {
    if (key != mLast) {
        mLast = key;
        mLastTile = mLayer->tileAt(key);
    }
    return mLastTile;
}

Rgb8 ColourAccessor::colourAt(const glm::vec3& pWorld) noexcept {
    const Rgb8 base = mLayer->baseColour();
    if (mLayer->slotCount() == 0) return base;
    const Domain& d = mLayer->domain();
    const glm::vec3 u = latticeOf(pWorld, mOriginWorld, mLatticePerMetre, mTop);
    const glm::uvec3 p0(u);
    const uint32_t last = d.latticeSize() - 1;
    Rgb8 c[8];
    for (int k = 0; k < 8; ++k) {
        uint32_t key, local;
        split(d, clampPoint(p0 + glm::uvec3(k & 1, (k >> 1) & 1, k >> 2), last), key, local);
        const ColourTile* t = tileOf(key);
        const Rgb8* hit = t ? t->find(local) : nullptr;
        c[k] = hit ? *hit : base;
    }
    return blendColours(c, u - glm::vec3(p0));
}

}  // namespace kizamu::adf
