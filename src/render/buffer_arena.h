// SPDX-License-Identifier: Apache-2.0
/// @file buffer_arena.h
/// @brief Sub-allocation of a few large GL buffers: a first-fit range allocator over element
/// indices (RangeAllocator) and a set of GL buffers that share its ranges (BufferArena).
///
/// TiledGpuMesh gives each tile a vertex range (the same range in its position, normal and
/// colour buffers) and an index range, so a frame draws every tile from the same buffers with
/// one multi-draw call. Ranges are in elements, not bytes; each buffer of an arena has its own
/// element size. When no free range is large enough the arena grows: new GL buffers of twice the
/// capacity (or more), the old contents copied on the GPU (glCopyBufferSubData), so ranges keep
/// their offsets and their data; the buffer names change, which the owner must rebind.
/// Threading: RangeAllocator is plain data for one thread; a BufferArena's GL objects belong to
/// the context current at construction and are used on its thread only.
#pragma once

#include <epoxy/gl.h>

#include <cstddef>
#include <initializer_list>
#include <map>
#include <optional>
#include <vector>

namespace kizamu::render {

/// Free ranges of [0, capacity), first fit, neighbours coalesced on release. Owned by its arena;
/// not thread-safe.
class RangeAllocator {
public:
    /// The first free range (lowest offset) of `count` elements, or none when no free range is
    /// that large. Precondition: count > 0.
    /// Complexity: O(free ranges). Memory: may drop a free-list node.
    std::optional<std::size_t> allocate(std::size_t count);
    /// Returns [offset, offset + count) to the free list, merged with free neighbours.
    /// Precondition: the range was allocated and is not free (asserted in Debug builds).
    /// Complexity: O(log free ranges). Memory: at most one free-list node.
    void release(std::size_t offset, std::size_t count);
    /// Extends the capacity to `capacity` (not less than now); the new tail is free.
    /// Complexity: O(log free ranges).
    void grow(std::size_t capacity);
    /// Drops every allocation: the whole capacity is one free range.
    void clear();

    std::size_t capacity() const { return mCapacity; }
    std::size_t freeElements() const { return mFreeElements; }
    std::size_t freeRangeCount() const { return mFree.size(); }

private:
    std::map<std::size_t, std::size_t> mFree;  ///< offset -> count, disjoint, never adjacent
    std::size_t mCapacity = 0;
    std::size_t mFreeElements = 0;
};

/// GL buffers of the same element count, sub-allocated together. Owned by one mesh; move-only;
/// not thread-safe.
class BufferArena {
public:
    /// One GL buffer per entry of `elementBytes` (bytes per element), none allocated yet: the
    /// first allocate() makes them. Any target may bind them (vertex attributes, indices).
    explicit BufferArena(std::initializer_list<std::size_t> elementBytes);
    BufferArena(BufferArena&& other) noexcept;
    BufferArena& operator=(BufferArena&& other) noexcept;
    BufferArena(const BufferArena&) = delete;
    BufferArena& operator=(const BufferArena&) = delete;
    ~BufferArena();

    /// A range of `count` elements (count > 0) in every buffer, growing the buffers when no free
    /// range is large enough. Returns its first element.
    /// Complexity: O(free ranges), plus an O(capacity) GPU copy when it grows.
    /// Memory: on growth, new buffers of max(2 × capacity, capacity + count) elements.
    std::size_t allocate(std::size_t count);
    /// Frees a range that `allocate` returned. Complexity: O(log free ranges).
    void release(std::size_t offset, std::size_t count) { mRanges.release(offset, count); }
    /// Frees every range; the buffers keep their capacity.
    void clear() { mRanges.clear(); }
    /// Writes `count` elements of buffer `buffer` from `data`, starting at element `offset`.
    /// Returns the bytes written. Complexity: O(count) upload.
    std::size_t write(std::size_t buffer, std::size_t offset, const void* data, std::size_t count);

    /// The GL name of buffer `buffer` (0 before the first allocation; changes when it grows).
    GLuint name(std::size_t buffer) const { return mBuffers[buffer].name; }
    std::size_t capacity() const { return mRanges.capacity(); }
    const RangeAllocator& ranges() const { return mRanges; }
    /// Bytes copied on the GPU by growth since the last resetCounters().
    std::size_t bytesCopied() const { return mBytesCopied; }
    void resetCounters() { mBytesCopied = 0; }

private:
    struct Buffer {
        GLuint name = 0;
        std::size_t elementBytes = 0;
    };
    void growTo(std::size_t capacity);
    void release() noexcept;
    std::vector<Buffer> mBuffers;
    RangeAllocator mRanges;
    std::size_t mBytesCopied = 0;
};

}  // namespace kizamu::render
