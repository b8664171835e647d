// SPDX-License-Identifier: Apache-2.0
/// @file tile.cpp
/// @brief Tile allocation, quantisation and checksums.
#include "adf/tile.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstring>
#include <new>

namespace kizamu::adf {

CellType cellTypeOf(std::span<const float, 8> corners) {
    bool anyInside = false, anyOutside = false;
    for (float v : corners) (v < 0.0f ? anyInside : anyOutside) = true;
    if (anyInside && anyOutside) return CellType::Boundary;
    return anyInside ? CellType::Interior : CellType::Exterior;
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
std::size_t blockBytes(uint32_t nodeCount, uint32_t leafCount, uint32_t brickCount) {
    return kHeaderBytes + alignUp(std::size_t(nodeCount) * 4, 8) + std::size_t(leafCount) * 16 +
           std::size_t(brickCount) * 54;
}
}  // namespace

Tile* Tile::allocate(uint32_t nodeCount, uint32_t leafCount, uint32_t brickCount) {
    void* mem = ::operator new(blockBytes(nodeCount, leafCount, brickCount));
    Tile* t = new (mem) Tile();
    auto* base = static_cast<unsigned char*>(mem);
    const std::size_t cornersAt = kHeaderBytes + alignUp(std::size_t(nodeCount) * 4, 8);
    t->mNodes = reinterpret_cast<const uint32_t*>(base + kHeaderBytes);
    t->mCorners = reinterpret_cast<const int16_t*>(base + cornersAt);
    t->mBricks = reinterpret_cast<const int16_t*>(base + cornersAt + std::size_t(leafCount) * 16);
    t->mNodeCount = nodeCount;
    t->mLeafCount = leafCount;
    t->mBrickCount = brickCount;
    return t;
}

void Tile::Deleter::operator()(const Tile* t) const {
    t->~Tile();
    ::operator delete(const_cast<Tile*>(t));
}

Tile::~Tile() { mMagic = 0xdeadbeefdeadbeefull; }

std::size_t Tile::bytes() const { return blockBytes(mNodeCount, mLeafCount, mBrickCount); }

uint64_t Tile::computeChecksum() const {
    uint64_t h = 0xcbf29ce484222325ull;
    h = fnv1a(h, &mLevel, sizeof mLevel);
    h = fnv1a(h, &mOrigin, sizeof mOrigin);
    h = fnv1a(h, &mScale, sizeof mScale);
    h = fnv1a(h, mNodes, std::size_t(mNodeCount) * 4);
    h = fnv1a(h, mCorners, std::size_t(mLeafCount) * 16);
    h = fnv1a(h, mBricks, std::size_t(mBrickCount) * 54);
    return h;
}

namespace {
/// memcpy that accepts the null data() of an empty span.
void copyBytes(const void* dst, const void* src, std::size_t n) {
    if (n) std::memcpy(const_cast<void*>(dst), src, n);
}

/// Round half away from zero into [-32767, 32767], keeping negative values negative (inside
/// stays inside even when a tiny distance rounds to zero).
int16_t quantise(float v, float scale) {
    const float x = v / scale;
    long r = long(x + (x >= 0.0f ? 0.5f : -0.5f));
    r = std::clamp(r, -32767l, 32767l);
    if (v < 0.0f && r == 0) r = -1;
    return int16_t(r);
}
}  // namespace

TilePtr Tile::create(int level, glm::uvec3 latticeOrigin, std::span<const uint32_t> nodes,
                     std::span<const float> leafCorners, std::span<const float> brickValues,
                     uint64_t version, float keepScale) {
    assert(leafCorners.size() % 8 == 0 && brickValues.size() % 27 == 0);
    float maxAbs = 0.0f;
    for (float v : leafCorners) maxAbs = std::max(maxAbs, std::abs(v));
    for (float v : brickValues) maxAbs = std::max(maxAbs, std::abs(v));
    // One scale per tile: a tile spans at most 2^span finest cells, so its surface cells keep
    // a step of about diagonal/32767 (under 0.01 finest cell at span 6).
    // A kept scale may be coarser than this tile needs, but never coarser than the tile it
    // replaces had: the same block of space, the same bound on the step.
    const float scale = keepScale > 0.0f && maxAbs <= keepScale * 32767.0f ? keepScale
                        : maxAbs > 0.0f                                  ? maxAbs / 32767.0f
                                                                         : 1.0f;
    Tile* t = allocate(uint32_t(nodes.size()), uint32_t(leafCorners.size() / 8),
                       uint32_t(brickValues.size() / 27));
    copyBytes(t->mNodes, nodes.data(), nodes.size() * 4);
    auto* q = const_cast<int16_t*>(t->mCorners);
    for (std::size_t i = 0; i < leafCorners.size(); ++i) q[i] = quantise(leafCorners[i], scale);
    auto* b = const_cast<int16_t*>(t->mBricks);
    for (std::size_t i = 0; i < brickValues.size(); ++i) b[i] = quantise(brickValues[i], scale);
    return finish(t, level, latticeOrigin, scale, version);
}

TilePtr Tile::createQuantised(int level, glm::uvec3 latticeOrigin, std::span<const uint32_t> nodes,
                              std::span<const int16_t> leafCorners, std::span<const int16_t> brickValues,
                              float scale, uint64_t version) {
    assert(leafCorners.size() % 8 == 0 && brickValues.size() % 27 == 0);
    Tile* t = allocate(uint32_t(nodes.size()), uint32_t(leafCorners.size() / 8),
                       uint32_t(brickValues.size() / 27));
    copyBytes(t->mNodes, nodes.data(), nodes.size() * 4);
    copyBytes(t->mCorners, leafCorners.data(), leafCorners.size() * 2);
    copyBytes(t->mBricks, brickValues.data(), brickValues.size() * 2);
    return finish(t, level, latticeOrigin, scale, version);
}

TilePtr Tile::finish(Tile* t, int level, glm::uvec3 latticeOrigin, float scale, uint64_t version) {
    t->mLevel = level;
    t->mOrigin = latticeOrigin;
    t->mScale = scale;
    t->mVersion = version;
    t->mChecksum = t->computeChecksum();
    t->mMagic = kAlive;
    return TilePtr(t, Deleter{});
}

}  // namespace kizamu::adf
