// SPDX-License-Identifier: Apache-2.0
/// @file buffer_arena.cpp
/// @brief The first-fit range allocator and its GL buffers (see buffer_arena.h).
#include "render/buffer_arena.h"

#include <algorithm>
#include <cassert>
#include <iterator>
#include <utility>

namespace kizamu::render {

std::optional<std::size_t> RangeAllocator::allocate(std::size_t count) {
    assert(count > 0 && "RangeAllocator::allocate: an empty range");
    for (auto it = mFree.begin(); it != mFree.end(); ++it) {
        if (it->second < count) continue;
        const std::size_t offset = it->first, left = it->second - count;
        mFree.erase(it);
        if (left > 0) mFree.emplace(offset + count, left);
        mFreeElements -= count;
        return offset;
    }
    return std::nullopt;
}

void RangeAllocator::release(std::size_t offset, std::size_t count) {
    if (count == 0) return;
    assert(offset + count <= mCapacity && "RangeAllocator::release: a range beyond the capacity");
    auto next = mFree.lower_bound(offset);
    assert((next == mFree.end() || next->first >= offset + count) &&
           "RangeAllocator::release: the range overlaps a free one");
    mFreeElements += count;
    if (next != mFree.begin()) {
        auto prev = std::prev(next);
        assert(prev->first + prev->second <= offset &&
               "RangeAllocator::release: the range overlaps a free one");
        if (prev->first + prev->second == offset) {  // merge into the free range before
            offset = prev->first;
            count += prev->second;
            mFree.erase(prev);
        }
    }
    if (next != mFree.end() && next->first == offset + count) {  // and the one after
        count += next->second;
        mFree.erase(next);
    }
    mFree.emplace(offset, count);
}

void RangeAllocator::grow(std::size_t capacity) {
    assert(capacity >= mCapacity && "RangeAllocator::grow: shrinking");
    const std::size_t tail = mCapacity;
    mCapacity = capacity;
    release(tail, capacity - tail);
}

void RangeAllocator::clear() {
    mFree.clear();
    mFreeElements = 0;
    const std::size_t capacity = mCapacity;
    mCapacity = 0;
    grow(capacity);
}

BufferArena::BufferArena(std::initializer_list<std::size_t> elementBytes) {
    for (std::size_t bytes : elementBytes) mBuffers.push_back({0, bytes});
}

BufferArena::BufferArena(BufferArena&& other) noexcept {
    *this = std::move(other);
}

BufferArena& BufferArena::operator=(BufferArena&& other) noexcept {
    if (this != &other) {
        release();
        mBuffers = std::move(other.mBuffers);
        other.mBuffers.clear();
        mRanges = std::exchange(other.mRanges, RangeAllocator());
        mBytesCopied = other.mBytesCopied;
    }
    return *this;
}

BufferArena::~BufferArena() {
    release();
}

void BufferArena::release() noexcept {
    for (Buffer& b : mBuffers)
        if (b.name) glDeleteBuffers(1, &b.name);
    for (Buffer& b : mBuffers) b.name = 0;
}

std::size_t BufferArena::allocate(std::size_t count) {
    if (auto offset = mRanges.allocate(count)) return *offset;
    growTo(std::max(2 * mRanges.capacity(), mRanges.capacity() + count));
    const auto offset = mRanges.allocate(count);
    assert(offset && "BufferArena::allocate: no room after growing");
    return *offset;
}

void BufferArena::growTo(std::size_t capacity) {
    const std::size_t old = mRanges.capacity();
    for (Buffer& b : mBuffers) {
        GLuint grown = 0;
        glGenBuffers(1, &grown);
        glBindBuffer(GL_COPY_WRITE_BUFFER, grown);
        glBufferData(GL_COPY_WRITE_BUFFER, GLsizeiptr(capacity * b.elementBytes), nullptr,
                     GL_DYNAMIC_DRAW);
        if (b.name && old > 0) {
            // Every live range keeps its offset and its data: one copy of the whole old buffer.
            glBindBuffer(GL_COPY_READ_BUFFER, b.name);
            glCopyBufferSubData(GL_COPY_READ_BUFFER, GL_COPY_WRITE_BUFFER, 0, 0,
                                GLsizeiptr(old * b.elementBytes));
            mBytesCopied += old * b.elementBytes;
            glDeleteBuffers(1, &b.name);
        }
        b.name = grown;
    }
    glBindBuffer(GL_COPY_READ_BUFFER, 0);
    glBindBuffer(GL_COPY_WRITE_BUFFER, 0);
    mRanges.grow(capacity);
}

std::size_t BufferArena::write(std::size_t buffer, std::size_t offset, const void* data,
                               std::size_t count) {
    const Buffer& b = mBuffers[buffer];
    assert(offset + count <= mRanges.capacity() && "BufferArena::write: beyond the capacity");
    const std::size_t bytes = count * b.elementBytes;
    if (bytes == 0) return 0;
    // Through GL_COPY_WRITE_BUFFER: writing an element buffer through GL_ELEMENT_ARRAY_BUFFER
    // would change the element buffer of whatever vertex array is bound now.
    glBindBuffer(GL_COPY_WRITE_BUFFER, b.name);
    glBufferSubData(GL_COPY_WRITE_BUFFER, GLintptr(offset * b.elementBytes), GLsizeiptr(bytes),
                    data);
    glBindBuffer(GL_COPY_WRITE_BUFFER, 0);
    return bytes;
}

}  // namespace kizamu::render
