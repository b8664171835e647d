// SPDX-License-Identifier: Apache-2.0
/// @file tiled_gpu_mesh.h
/// @brief The mesher's mesh on the GPU, kept by applying its MeshDeltas tile by tile: only the
/// tiles whose data changed are written, and every tile is drawn with one multi-draw call.
///
/// Pipeline: the render thread takes the engine's mesh delta (mesh_delta.h) and applies it here
/// instead of flattening a MeshMirror and uploading the whole mesh (GpuMesh). The vertices and
/// triangles are those MeshMirror::flatten() gives, bit for bit, in another order.
///
/// Layout. Five shared buffers: positions, normals, colours, spacings (one vertex range per
/// tile, the same in the four) and indices (one index range per tile), sub-allocated by
/// BufferArena. A tile's vertex range holds its live slots, then its split vertices, then its
/// fan centres; its index
/// range its triangles, then its fans' triangles, as absolute vertex numbers. Ranges get some
/// slack (a quarter for vertices, an eighth for indices), so a tile that gains a few vertices
/// or triangles stays where it is. Index slack holds degenerate triangles, so each index range
/// is drawn whole and tiles lying back to back are one range of the multi-draw: after a build
/// all of them, after edits a few more, one for each hole that moved tiles left. Freed ranges
/// are reused first fit; the buffers grow by doubling and never shrink; nothing compacts them
/// but a reset delta, which lays every tile out afresh.
///
/// What a delta re-emits (writes again, vertices and indices): the delta's tiles; every tile
/// that references one of them or a removed tile (its triangles name their vertices by number,
/// which change with their shares or when their range moves; its split vertices lie between
/// theirs); and every tile whose fans use a split vertex of a tile re-emitted so (the fan
/// centre is the mean of the corners). A reverse map, tile -> tiles referencing it, finds them.
/// Re-emitted vertices get their colours from the caller's colour function.
///
/// Vertex attributes as GpuMesh binds them (gpu_mesh.h): 0 position, 1 normal, 2 colour (alpha
/// 255 where the colour function painted it, 0 for the clay colour), 3 spacing (the longest edge
/// at the vertex among its tile's triangles; 0 in slack, which points mode culls, so it draws
/// back-to-back vertex ranges whole too).
/// Threading: the GL context current at the first apply must be current on every call; one
/// instance per context; not thread-safe.
#pragma once

#include "mesh/mesh_buffers.h"
#include "mesh/mesh_delta.h"
#include "render/buffer_arena.h"

#include <epoxy/gl.h>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <unordered_map>
#include <vector>

namespace kizamu::render {

/// Fills `colours[i]` (sRGB bytes, alpha 255 where painted) for the vertex at `positions[i]`
/// (world, m); entries left alone stay (0, 0, 0, 0): the clay colour. Called once per apply with
/// the re-emitted vertices only, on the applying thread.
using VertexColourFunction =
    std::function<void(std::span<const glm::vec3> positionsWorld, std::span<glm::u8vec4> colours)>;

/// What the last apply() did.
struct TiledUploadStats {
    std::size_t tilesInDelta = 0;    ///< shares and removals the delta held
    std::size_t tilesReEmitted = 0;  ///< tiles whose vertices and indices were written
    std::size_t tilesMoved = 0;      ///< tiles of the delta that outgrew their vertex range
    std::size_t verticesWritten = 0;
    std::size_t bytesUploaded = 0;  ///< CPU to GPU (glBufferSubData), index slack included
    std::size_t bytesCopied = 0;    ///< GPU to GPU, when a buffer grew
};

/// Owned by its renderer; move-only; not thread-safe.
class TiledGpuMesh {
public:
    TiledGpuMesh();
    TiledGpuMesh(TiledGpuMesh&& other) noexcept;
    TiledGpuMesh& operator=(TiledGpuMesh&& other) noexcept;
    TiledGpuMesh(const TiledGpuMesh&) = delete;
    TiledGpuMesh& operator=(const TiledGpuMesh&) = delete;
    ~TiledGpuMesh();

    /// Applies `delta` if it follows this mesh (delta.base == generation(), or delta.reset) and
    /// returns true; returns false and changes nothing otherwise (the caller asks for a full
    /// delta). `colour` paints the re-emitted vertices; empty: unpainted.
    /// @throw std::logic_error if an address names a tile or slot the mesh lacks (a bug)
    /// Complexity: O(re-emitted tiles' vertices and triangles + tiles) CPU and upload; O(buffer)
    ///             GPU copy when a buffer grows.
    /// Threading: the context's thread. Memory: takes the shares over; staging for the
    ///            re-emitted tiles; buffers grow by doubling and never shrink.
    bool apply(mesh::MeshDelta&& delta, const VertexColourFunction& colour = {});
    /// Refuses every delta but a reset from now on (the deltas' source was replaced: its
    /// generations start again); keeps drawing the mesh held until the reset arrives.
    void requireReset() { mSynced = false; }
    /// Writes every vertex's colour again from `colour` (a paint stroke changes no share).
    /// Complexity: O(vertices) CPU and upload. Threading: the context's thread.
    void recolour(const VertexColourFunction& colour);
    /// Draws every tile with the program and state in use: one glMultiDrawElements call; nothing
    /// when empty. Complexity: O(tiles) CPU for the call's arrays (kept), O(triangles) GPU.
    void draw() const;
    /// Draws every vertex as a point (points mode): one glMultiDrawArrays call; nothing when
    /// empty. Complexity: O(vertex ranges) CPU, O(vertices) GPU.
    void drawPoints() const;

    /// The mesh as drawn, read back from the GPU (glGetBufferSubData): vertices of every tile's
    /// range, indices renumbered into them. For tests and debugging.
    /// Complexity: O(mesh) read-back that waits for the GPU. Memory: the returned buffers.
    mesh::MeshBuffers readBack() const;

    bool empty() const { return mTriangles == 0; }
    uint64_t generation() const { return mGeneration; }
    std::size_t tileCount() const { return mTiles.size(); }
    std::size_t triangleCount() const { return mTriangles; }
    std::size_t vertexCount() const { return mVertices; }
    /// GL draw calls one draw() makes: 1, or 0 when empty, whatever the tile count.
    std::size_t drawCallsPerDraw() const { return empty() ? 0 : 1; }
    /// Index ranges that one call draws (runs of tiles back to back in the index buffer).
    std::size_t drawRangeCount() const { return mDrawCounts.size(); }
    const TiledUploadStats& lastApply() const { return mLastApply; }
    /// Axis-aligned bounds of the vertices (m, world); both zero when empty.
    const glm::vec3& boundsMin() const { return mBoundsMin; }
    const glm::vec3& boundsMax() const { return mBoundsMax; }
    /// Elements the vertex and index buffers hold (used and free): their memory is 32 and 4
    /// bytes per element.
    std::size_t vertexCapacity() const { return mVertexArena.capacity(); }
    std::size_t indexCapacity() const { return mIndexArena.capacity(); }

private:
    struct Range {
        std::size_t offset = 0, capacity = 0, used = 0;
    };
    struct Tile {
        mesh::MeshTileShare share;
        /// Per vertex slot its number in the tile's range (UINT32_MAX where free), then per split.
        std::vector<uint32_t> number;
        std::size_t plainVertices = 0;  ///< live slots
        std::size_t fanTriangles = 0;
        Range vertices, indices;
        std::vector<uint64_t> references;   ///< other tiles its splits, triangles and fans name
        std::vector<uint64_t> splitOwners;  ///< other tiles whose split vertices its fans use
        glm::vec3 boundsMin{0.0f}, boundsMax{0.0f};
    };
    using ReverseMap = std::unordered_map<uint64_t, std::vector<uint64_t>>;

    void link(uint64_t key, const Tile& t);
    void unlink(uint64_t key, const Tile& t);
    void freeRanges(Tile& t);
    const Tile& tileOf(const mesh::VertexAddress& a) const;
    uint32_t numberOf(const mesh::VertexAddress& a) const;
    glm::vec3 latticeOf(const mesh::VertexAddress& a) const;
    glm::vec3 normalOf(const mesh::VertexAddress& a) const;
    glm::vec3 world(const glm::vec3& lattice) const;
    /// Takes `share` over as tile `key`'s: its numbering, references, and a larger vertex range
    /// when it outgrew its own. Returns whether its vertex range moved.
    bool setShare(uint64_t key, Tile& t, mesh::MeshTileShare&& share);
    /// Appends the tile's vertices (world) to the staging; sets its used count and bounds.
    void stageVertices(Tile& t);
    /// Appends the tile's indices to the staging, in a larger index range when it outgrew its
    /// own, and its vertex range's spacings; its vertices are staged from `firstVertex`.
    void stageIndices(Tile& t, std::size_t firstVertex);
    void bindVertexArray();
    void refreshDrawList();

    std::unordered_map<uint64_t, Tile> mTiles;
    ReverseMap mReferencedBy;  ///< tile -> tiles whose splits, triangles or fans name it
    ReverseMap mSplitUsers;    ///< tile -> tiles whose fans use its split vertices
    BufferArena mVertexArena;  ///< positions, normals, colours
    BufferArena mIndexArena;
    GLuint mVao = 0;
    GLuint mBoundPositions = 0, mBoundIndices = 0;  ///< buffer names the vertex array holds
    std::vector<GLsizei> mDrawCounts;
    std::vector<const void*> mDrawOffsets;
    std::vector<GLint> mPointFirsts;  ///< runs of vertex ranges back to back, for drawPoints
    std::vector<GLsizei> mPointCounts;
    uint64_t mGeneration = 0;
    bool mSynced = false;
    glm::dvec3 mOriginWorld{0.0};
    double mCellSize = 0.0;
    std::size_t mTriangles = 0, mVertices = 0;
    glm::vec3 mBoundsMin{0.0f}, mBoundsMax{0.0f};
    TiledUploadStats mLastApply;
    /// Staging of one apply: the re-emitted tiles' vertices, back to back, then written range
    /// by range. Kept to reuse its capacity.
    std::vector<glm::vec3> mStagePositions, mStageNormals;
    std::vector<glm::u8vec4> mStageColours;
    std::vector<float> mStageSpacings;  ///< per vertex range, slack included
    std::vector<uint32_t> mStageIndices;
};

}  // namespace kizamu::render
