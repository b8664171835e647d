// SPDX-License-Identifier: Apache-2.0
/// @file tiled_gpu_mesh.cpp
/// @brief Mesh deltas to per-tile ranges of shared GL buffers (see tiled_gpu_mesh.h).
///
/// The vertices repeat MeshMirror::flatten's float operations (mesh_delta.cpp): the world
/// transform in double, split vertices at the lattice mid-point of their ends, fan centres at
/// the float mean of their corners' world positions in corner order; so the GPU holds the same
/// bits as an upload of the flattened mirror.
#include "render/tiled_gpu_mesh.h"

#include "render/gpu_mesh.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cassert>
#include <stdexcept>
#include <utility>

namespace kizamu::render {

namespace {

enum VertexBuffer : std::size_t { kPositions = 0, kNormals = 1, kColours = 2, kSpacings = 3 };

/// Vertices to reserve for `count`: a quarter more, so small growth stays in place (a vertex
/// range that moves makes every tile naming it re-emit).
std::size_t vertexSlack(std::size_t count) {
    return count == 0 ? 0 : count + count / 4 + 4;
}
/// Indices to reserve for `count` (a multiple of 3): an eighth more, whole triangles.
std::size_t indexSlack(std::size_t count) {
    return count == 0 ? 0 : count + 3 * (count / 24 + 2);
}

void sortUnique(std::vector<uint64_t>& keys) {
    std::sort(keys.begin(), keys.end());
    keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
}

void addTo(std::unordered_map<uint64_t, std::vector<uint64_t>>& map, uint64_t from, uint64_t to) {
    map[from].push_back(to);
}

void removeFrom(std::unordered_map<uint64_t, std::vector<uint64_t>>& map, uint64_t from,
                uint64_t to) {
    auto it = map.find(from);
    if (it == map.end()) return;
    std::vector<uint64_t>& users = it->second;
    if (auto u = std::find(users.begin(), users.end(), to); u != users.end()) {
        *u = users.back();
        users.pop_back();
    }
    if (users.empty()) map.erase(it);
}

}  // namespace

TiledGpuMesh::TiledGpuMesh()
    : mVertexArena({sizeof(glm::vec3), sizeof(glm::vec3), sizeof(glm::u8vec4), sizeof(float)}),
      mIndexArena({sizeof(uint32_t)}) {}

TiledGpuMesh::TiledGpuMesh(TiledGpuMesh&& other) noexcept : TiledGpuMesh() {
    *this = std::move(other);
}

TiledGpuMesh& TiledGpuMesh::operator=(TiledGpuMesh&& other) noexcept {
    if (this != &other) {
        if (mVao) glDeleteVertexArrays(1, &mVao);
        mTiles = std::move(other.mTiles);
        mReferencedBy = std::move(other.mReferencedBy);
        mSplitUsers = std::move(other.mSplitUsers);
        mVertexArena = std::move(other.mVertexArena);
        mIndexArena = std::move(other.mIndexArena);
        mVao = std::exchange(other.mVao, 0);
        mBoundPositions = std::exchange(other.mBoundPositions, 0);
        mBoundIndices = std::exchange(other.mBoundIndices, 0);
        mDrawCounts = std::move(other.mDrawCounts);
        mDrawOffsets = std::move(other.mDrawOffsets);
        mPointFirsts = std::move(other.mPointFirsts);
        mPointCounts = std::move(other.mPointCounts);
        mGeneration = other.mGeneration;
        mSynced = std::exchange(other.mSynced, false);
        mOriginWorld = other.mOriginWorld;
        mCellSize = other.mCellSize;
        mTriangles = std::exchange(other.mTriangles, 0);
        mVertices = std::exchange(other.mVertices, 0);
        mBoundsMin = other.mBoundsMin;
        mBoundsMax = other.mBoundsMax;
        mLastApply = other.mLastApply;
        other.mTiles.clear();
        other.mDrawCounts.clear();
        other.mDrawOffsets.clear();
        other.mPointFirsts.clear();
        other.mPointCounts.clear();
    }
    return *this;
}

TiledGpuMesh::~TiledGpuMesh() {
    if (mVao) glDeleteVertexArrays(1, &mVao);
}

void TiledGpuMesh::link(uint64_t key, const Tile& t) {
    for (uint64_t k : t.references) addTo(mReferencedBy, k, key);
    for (uint64_t k : t.splitOwners) addTo(mSplitUsers, k, key);
}

void TiledGpuMesh::unlink(uint64_t key, const Tile& t) {
    for (uint64_t k : t.references) removeFrom(mReferencedBy, k, key);
    for (uint64_t k : t.splitOwners) removeFrom(mSplitUsers, k, key);
}

void TiledGpuMesh::freeRanges(Tile& t) {
    if (t.vertices.capacity) mVertexArena.release(t.vertices.offset, t.vertices.capacity);
    if (t.indices.capacity) mIndexArena.release(t.indices.offset, t.indices.capacity);
    t.vertices = t.indices = Range{};
}

const TiledGpuMesh::Tile& TiledGpuMesh::tileOf(const mesh::VertexAddress& a) const {
    auto it = mTiles.find(a.tile);
    if (it == mTiles.end())
        throw std::logic_error("tiled GPU mesh: an address names a tile the mesh lacks");
    return it->second;
}

uint32_t TiledGpuMesh::numberOf(const mesh::VertexAddress& a) const {
    const Tile& t = tileOf(a);
    const std::size_t i =
        a.isSplit() ? t.share.alive.size() + (a.slot - mesh::VertexAddress::kSplitSlot) : a.slot;
    if (i >= t.number.size() || t.number[i] == UINT32_MAX)
        throw std::logic_error("tiled GPU mesh: an address names a free or missing slot");
    return uint32_t(t.vertices.offset) + t.number[i];
}

glm::vec3 TiledGpuMesh::latticeOf(const mesh::VertexAddress& a) const {
    const Tile& t = tileOf(a);
    if (!a.isSplit()) {
        if (a.slot >= t.share.alive.size() || !t.share.alive[a.slot])
            throw std::logic_error("tiled GPU mesh: an address names a free or missing slot");
        return t.share.positions[a.slot];
    }
    const std::size_t s = a.slot - mesh::VertexAddress::kSplitSlot;
    if (s >= t.share.splits.size())
        throw std::logic_error("tiled GPU mesh: an address names a missing split vertex");
    const auto& [ea, eb] = t.share.splits[s];
    if (ea.isSplit() || eb.isSplit())
        throw std::logic_error("tiled GPU mesh: a split vertex's end is no live vertex");
    return 0.5f * (latticeOf(ea) + latticeOf(eb));
}

glm::vec3 TiledGpuMesh::normalOf(const mesh::VertexAddress& a) const {
    const Tile& t = tileOf(a);
    if (!a.isSplit()) return t.share.normals[a.slot];
    const auto& [ea, eb] = t.share.splits[a.slot - mesh::VertexAddress::kSplitSlot];
    const glm::vec3 na = normalOf(ea), n = na + normalOf(eb);
    return glm::dot(n, n) > 0.0f ? glm::normalize(n) : na;
}

glm::vec3 TiledGpuMesh::world(const glm::vec3& lattice) const {
    return glm::vec3(mOriginWorld + glm::dvec3(lattice) * mCellSize);
}

void TiledGpuMesh::stageVertices(Tile& t) {
    const mesh::MeshTileShare& s = t.share;
    const std::size_t first = mStagePositions.size();
    for (std::size_t i = 0; i < s.alive.size(); ++i) {
        if (!s.alive[i]) continue;
        mStagePositions.push_back(world(s.positions[i]));
        mStageNormals.push_back(s.normals[i]);
    }
    for (std::size_t i = 0; i < s.splits.size(); ++i) {
        const mesh::VertexAddress self{s.key, mesh::VertexAddress::kSplitSlot + uint32_t(i)};
        mStagePositions.push_back(world(latticeOf(self)));
        mStageNormals.push_back(normalOf(self));
    }
    for (const mesh::MeshFan& f : s.fans) {
        glm::vec3 c(0.0f), nsum(0.0f);
        for (uint32_t i = 0; i < f.count; ++i) {
            c += world(latticeOf(f.corners[i]));
            nsum += normalOf(f.corners[i]);
        }
        mStagePositions.push_back(c / float(f.count));
        mStageNormals.push_back(glm::dot(nsum, nsum) > 0.0f ? glm::normalize(nsum)
                                                            : glm::vec3(0.0f, 0.0f, 1.0f));
    }
    t.vertices.used = mStagePositions.size() - first;
    assert(t.vertices.used <= t.vertices.capacity &&
           "TiledGpuMesh: a tile's vertices outgrew its range");
    t.boundsMin = t.boundsMax = t.vertices.used ? mStagePositions[first] : glm::vec3(0.0f);
    for (std::size_t i = first; i < mStagePositions.size(); ++i) {
        t.boundsMin = glm::min(t.boundsMin, mStagePositions[i]);
        t.boundsMax = glm::max(t.boundsMax, mStagePositions[i]);
    }
}

void TiledGpuMesh::stageIndices(Tile& t, std::size_t firstVertex) {
    const mesh::MeshTileShare& s = t.share;
    // Spacing: per vertex of this tile, the longest edge of this tile's triangles on it; its
    // vertex slack gets 0 (points mode culls those), so the whole range can be drawn.
    const std::size_t firstSpacing = mStageSpacings.size();
    mStageSpacings.resize(firstSpacing + t.vertices.capacity, 0.0f);
    float* spacing = mStageSpacings.data() + firstSpacing;
    const uint32_t base = uint32_t(t.vertices.offset);
    auto positionOf = [&](const mesh::VertexAddress& a, uint32_t number) {
        return a.tile == s.key ? mStagePositions[firstVertex + (number - base)]
                               : world(latticeOf(a));
    };
    auto spread = [&](const uint32_t(&v)[3], const glm::vec3(&p)[3], const bool(&local)[3]) {
        const float longest = std::max(
            {glm::distance(p[0], p[1]), glm::distance(p[1], p[2]), glm::distance(p[2], p[0])});
        for (int i = 0; i < 3; ++i)
            if (local[i]) spacing[v[i] - base] = std::max(spacing[v[i] - base], longest);
    };
    const std::size_t count = 3 * (s.triangles.size() + t.fanTriangles);
    if (count > t.indices.capacity) {
        if (t.indices.capacity) mIndexArena.release(t.indices.offset, t.indices.capacity);
        t.indices.capacity = indexSlack(count);
        t.indices.offset = mIndexArena.allocate(t.indices.capacity);
    }
    t.indices.used = count;
    for (const auto& tri : s.triangles) {
        uint32_t v[3];
        glm::vec3 p[3];
        bool local[3];
        for (int i = 0; i < 3; ++i) {
            v[i] = numberOf(tri[std::size_t(i)]);
            p[i] = positionOf(tri[std::size_t(i)], v[i]);
            local[i] = tri[std::size_t(i)].tile == s.key;
        }
        mStageIndices.insert(mStageIndices.end(), {v[0], v[1], v[2]});
        spread(v, p, local);
    }
    uint32_t centre = uint32_t(t.vertices.offset + t.plainVertices + s.splits.size());
    for (const mesh::MeshFan& f : s.fans) {
        uint32_t polygon[8];
        glm::vec3 corner[8];
        for (uint32_t i = 0; i < f.count; ++i) {
            polygon[i] = numberOf(f.corners[i]);
            corner[i] = positionOf(f.corners[i], polygon[i]);
        }
        const glm::vec3 centrePosition = mStagePositions[firstVertex + (centre - base)];
        for (uint32_t i = 0; i < f.count; ++i) {
            const uint32_t j = (i + 1) % f.count, a = polygon[i], b = polygon[j];
            mStageIndices.insert(mStageIndices.end(), {centre, f.flip ? b : a, f.flip ? a : b});
            spread({centre, a, b}, {centrePosition, corner[i], corner[j]},
                   {true, f.corners[i].tile == s.key, f.corners[j].tile == s.key});
        }
        ++centre;
    }
    // A vertex on none of this tile's triangles (they are its neighbours'): the tile's largest.
    if (t.vertices.used == 0) return;
    const float fallback =
        std::max(*std::max_element(spacing, spacing + t.vertices.used), float(2.0 * mCellSize));
    for (std::size_t i = 0; i < t.vertices.used; ++i)
        if (spacing[i] == 0.0f) spacing[i] = fallback;
    // The slack as degenerate triangles: the whole range is drawn, so tiles that lie back to
    // back in the buffer are drawn as one range.
    mStageIndices.insert(mStageIndices.end(), t.indices.capacity - count, 0u);
}

bool TiledGpuMesh::setShare(uint64_t key, Tile& t, mesh::MeshTileShare&& share) {
    t.share = std::move(share);
    const mesh::MeshTileShare& s = t.share;
    t.number.assign(s.alive.size() + s.splits.size(), UINT32_MAX);
    uint32_t next = 0;
    for (std::size_t i = 0; i < s.alive.size(); ++i)
        if (s.alive[i]) t.number[i] = next++;
    t.plainVertices = next;
    for (std::size_t i = 0; i < s.splits.size(); ++i) t.number[s.alive.size() + i] = next++;
    t.fanTriangles = 0;
    for (const mesh::MeshFan& f : s.fans) t.fanTriangles += f.count;
    const std::size_t vertices = next + s.fans.size();
    const bool moves = vertices > t.vertices.capacity;
    if (moves) {  // every tile naming its vertices is re-emitted
        if (t.vertices.capacity) mVertexArena.release(t.vertices.offset, t.vertices.capacity);
        t.vertices.capacity = vertexSlack(vertices);
        t.vertices.offset = mVertexArena.allocate(t.vertices.capacity);
    }
    t.references.clear();
    t.splitOwners.clear();
    auto name = [&](const mesh::VertexAddress& a) {
        if (a.tile != key) t.references.push_back(a.tile);
    };
    for (const auto& split : s.splits)
        for (const mesh::VertexAddress& a : split) name(a);
    for (const auto& tri : s.triangles)
        for (const mesh::VertexAddress& a : tri) name(a);
    for (const mesh::MeshFan& f : s.fans)
        for (uint32_t i = 0; i < f.count; ++i) {
            name(f.corners[i]);
            if (f.corners[i].isSplit() && f.corners[i].tile != key)
                t.splitOwners.push_back(f.corners[i].tile);
        }
    sortUnique(t.references);
    sortUnique(t.splitOwners);
    return moves;
}

bool TiledGpuMesh::apply(mesh::MeshDelta&& delta, const VertexColourFunction& colour) {
    if (!delta.reset && (!mSynced || delta.base != mGeneration)) return false;
    mLastApply = TiledUploadStats{};
    mLastApply.tilesInDelta = delta.tiles.size() + delta.removed.size();
    mVertexArena.resetCounters();
    mIndexArena.resetCounters();
    if (delta.reset) {
        mTiles.clear();
        mReferencedBy.clear();
        mSplitUsers.clear();
        mVertexArena.clear();
        mIndexArena.clear();
        mSynced = true;
    }
    mGeneration = delta.generation;
    mOriginWorld = delta.originWorld;
    mCellSize = delta.cellSize;

    // The tiles to re-emit: the delta's, and those naming a tile of the delta or a removed one.
    std::vector<uint64_t> reEmit;
    auto addReferencersOf = [&](uint64_t key) {
        if (auto it = mReferencedBy.find(key); it != mReferencedBy.end())
            reEmit.insert(reEmit.end(), it->second.begin(), it->second.end());
    };
    for (uint64_t key : delta.removed) {
        auto it = mTiles.find(key);
        if (it == mTiles.end()) continue;
        addReferencersOf(key);
        unlink(key, it->second);
        freeRanges(it->second);
        mTiles.erase(it);
    }
    std::vector<uint64_t> shared;
    shared.reserve(delta.tiles.size());
    for (mesh::MeshTileShare& share : delta.tiles) {
        const uint64_t key = share.key;
        shared.push_back(key);
        auto [it, made] = mTiles.try_emplace(key);
        if (!made) unlink(key, it->second);
        mLastApply.tilesMoved += setShare(key, it->second, std::move(share)) && !made ? 1 : 0;
        link(key, it->second);
    }
    // After every share is linked: the referencers of the old shares and of the new ones.
    for (uint64_t key : shared) {
        reEmit.push_back(key);
        addReferencersOf(key);
    }
    // Fan centres lie among split vertices, which lie between other tiles' vertices: a tile
    // whose fans use a re-emitted tile's split vertices is re-emitted too.
    for (std::size_t i = 0, n = reEmit.size(); i < n; ++i)
        if (auto it = mSplitUsers.find(reEmit[i]); it != mSplitUsers.end())
            reEmit.insert(reEmit.end(), it->second.begin(), it->second.end());
    sortUnique(reEmit);

    // Vertices of every re-emitted tile back to back, painted in one call, then written.
    mStagePositions.clear();
    mStageNormals.clear();
    mStageIndices.clear();
    mStageSpacings.clear();
    struct Staged {
        Tile* tile;
        std::size_t firstVertex, firstIndex, firstSpacing;
    };
    std::vector<Staged> staged;
    staged.reserve(reEmit.size());
    for (uint64_t key : reEmit) {
        auto it = mTiles.find(key);
        if (it == mTiles.end()) continue;  // a removed tile that named another removed one
        Tile& t = it->second;
        staged.push_back({&t, mStagePositions.size(), mStageIndices.size(), mStageSpacings.size()});
        stageVertices(t);
        stageIndices(t, staged.back().firstVertex);
    }
    mStageColours.assign(mStagePositions.size(), glm::u8vec4(0));
    if (colour) colour(mStagePositions, mStageColours);
    std::size_t bytes = 0;
    for (const Staged& s : staged) {
        const Tile& t = *s.tile;
        const std::size_t v = t.vertices.offset, n = t.vertices.used;
        bytes += mVertexArena.write(kPositions, v, mStagePositions.data() + s.firstVertex, n);
        bytes += mVertexArena.write(kNormals, v, mStageNormals.data() + s.firstVertex, n);
        bytes += mVertexArena.write(kColours, v, mStageColours.data() + s.firstVertex, n);
        bytes += mVertexArena.write(kSpacings, v, mStageSpacings.data() + s.firstSpacing,
                                    t.vertices.capacity);
        bytes += mIndexArena.write(0, t.indices.offset, mStageIndices.data() + s.firstIndex,
                                   t.indices.capacity);
    }
    mLastApply.tilesReEmitted = staged.size();
    mLastApply.verticesWritten = mStagePositions.size();
    mLastApply.bytesUploaded = bytes;
    mLastApply.bytesCopied = mVertexArena.bytesCopied() + mIndexArena.bytesCopied();
    bindVertexArray();
    refreshDrawList();
    return true;
}

void TiledGpuMesh::recolour(const VertexColourFunction& colour) {
    mStagePositions.clear();
    mStageNormals.clear();
    std::vector<std::pair<const Tile*, std::size_t>> staged;
    staged.reserve(mTiles.size());
    for (auto& [key, t] : mTiles) {
        staged.emplace_back(&t, mStagePositions.size());
        stageVertices(t);
    }
    mStageColours.assign(mStagePositions.size(), glm::u8vec4(0));
    if (colour) colour(mStagePositions, mStageColours);
    for (const auto& [t, first] : staged)
        mVertexArena.write(kColours, t->vertices.offset, mStageColours.data() + first,
                           t->vertices.used);
}

void TiledGpuMesh::bindVertexArray() {
    if (mVertexArena.name(kPositions) == mBoundPositions && mIndexArena.name(0) == mBoundIndices)
        return;
    if (!mVao) glGenVertexArrays(1, &mVao);
    glBindVertexArray(mVao);
    struct Attribute {
        VertexBuffer buffer;
        GLuint location;
        GLint components;
        GLenum type;
        GLboolean normalised;
    };
    const Attribute attributes[] = {{kPositions, attrib::kPosition, 3, GL_FLOAT, GL_FALSE},
                                    {kNormals, attrib::kNormal, 3, GL_FLOAT, GL_FALSE},
                                    {kColours, attrib::kColour, 4, GL_UNSIGNED_BYTE, GL_TRUE},
                                    {kSpacings, attrib::kSpacing, 1, GL_FLOAT, GL_FALSE}};
    for (const Attribute& a : attributes) {
        glBindBuffer(GL_ARRAY_BUFFER, mVertexArena.name(a.buffer));
        glEnableVertexAttribArray(a.location);
        glVertexAttribPointer(a.location, a.components, a.type, a.normalised, 0, nullptr);
    }
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, mIndexArena.name(0));  // recorded in the vertex array
    glBindVertexArray(0);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    mBoundPositions = mVertexArena.name(kPositions);
    mBoundIndices = mIndexArena.name(0);
}

void TiledGpuMesh::refreshDrawList() {
    mDrawCounts.clear();
    mDrawOffsets.clear();
    mPointFirsts.clear();
    mPointCounts.clear();
    mTriangles = mVertices = 0;
    bool first = true;
    mBoundsMin = mBoundsMax = glm::vec3(0.0f);
    // In buffer order: the GPU reads the index buffer front to back.
    std::vector<const Tile*> order;
    order.reserve(mTiles.size());
    for (const auto& [key, t] : mTiles) order.push_back(&t);
    std::sort(order.begin(), order.end(),
              [](const Tile* a, const Tile* b) { return a->indices.offset < b->indices.offset; });
    std::size_t end = 0;  // of the last range drawn
    for (const Tile* t : order) {
        mVertices += t->vertices.used;
        if (t->vertices.used) {
            mBoundsMin = first ? t->boundsMin : glm::min(mBoundsMin, t->boundsMin);
            mBoundsMax = first ? t->boundsMax : glm::max(mBoundsMax, t->boundsMax);
            first = false;
        }
        mTriangles += t->indices.used / 3;
        if (t->indices.capacity == 0) continue;
        if (!mDrawCounts.empty() && end == t->indices.offset) {  // back to back: one range
            mDrawCounts.back() += GLsizei(t->indices.capacity);
        } else {
            mDrawCounts.push_back(GLsizei(t->indices.capacity));
            mDrawOffsets.push_back(
                reinterpret_cast<const void*>(t->indices.offset * sizeof(uint32_t)));
        }
        end = t->indices.offset + t->indices.capacity;
    }
    std::sort(order.begin(), order.end(),
              [](const Tile* a, const Tile* b) { return a->vertices.offset < b->vertices.offset; });
    end = 0;
    for (const Tile* t : order) {
        if (t->vertices.capacity == 0) continue;
        if (!mPointCounts.empty() && end == t->vertices.offset)
            mPointCounts.back() += GLsizei(t->vertices.capacity);
        else {
            mPointFirsts.push_back(GLint(t->vertices.offset));
            mPointCounts.push_back(GLsizei(t->vertices.capacity));
        }
        end = t->vertices.offset + t->vertices.capacity;
    }
}

void TiledGpuMesh::draw() const {
    if (mTriangles == 0) return;
    glBindVertexArray(mVao);
    glMultiDrawElements(GL_TRIANGLES, mDrawCounts.data(), GL_UNSIGNED_INT, mDrawOffsets.data(),
                        GLsizei(mDrawCounts.size()));
    glBindVertexArray(0);
}

void TiledGpuMesh::drawPoints() const {
    if (mTriangles == 0) return;
    glBindVertexArray(mVao);
    glMultiDrawArrays(GL_POINTS, mPointFirsts.data(), mPointCounts.data(),
                      GLsizei(mPointCounts.size()));
    glBindVertexArray(0);
}

mesh::MeshBuffers TiledGpuMesh::readBack() const {
    mesh::MeshBuffers m;
    if (mTiles.empty()) return m;
    auto read = [](GLuint buffer, std::size_t bytes, void* out) {
        if (bytes == 0) return;
        glBindBuffer(GL_COPY_READ_BUFFER, buffer);
        glGetBufferSubData(GL_COPY_READ_BUFFER, 0, GLsizeiptr(bytes), out);
        glBindBuffer(GL_COPY_READ_BUFFER, 0);
    };
    const std::size_t vertices = mVertexArena.capacity(), indices = mIndexArena.capacity();
    std::vector<glm::vec3> positions(vertices), normals(vertices);
    std::vector<glm::u8vec4> colours(vertices);
    std::vector<uint32_t> index(indices);
    read(mVertexArena.name(kPositions), vertices * sizeof(glm::vec3), positions.data());
    read(mVertexArena.name(kNormals), vertices * sizeof(glm::vec3), normals.data());
    read(mVertexArena.name(kColours), vertices * sizeof(glm::u8vec4), colours.data());
    read(mIndexArena.name(0), indices * sizeof(uint32_t), index.data());
    // Only what the tiles' ranges use: slack and freed ranges hold stale data.
    std::vector<uint32_t> renumber(vertices, UINT32_MAX);
    for (const auto& [key, t] : mTiles)
        for (std::size_t i = 0; i < t.vertices.used; ++i) {
            const std::size_t v = t.vertices.offset + i;
            renumber[v] = uint32_t(m.positions.size());
            m.positions.push_back(positions[v]);
            m.normals.push_back(normals[v]);
            m.colours.push_back(glm::u8vec3(colours[v]));
        }
    for (const auto& [key, t] : mTiles)
        for (std::size_t i = 0; i < t.indices.used; ++i) {
            const uint32_t v = index[t.indices.offset + i];
            m.indices.push_back(v < vertices ? renumber[v] : UINT32_MAX);
        }
    return m;
}

}  // namespace kizamu::render
