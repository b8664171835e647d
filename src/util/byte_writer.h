// SPDX-License-Identifier: Apache-2.0
/// @file byte_writer.h
/// @brief Appends values to a byte buffer in host (little-endian) layout: the writers of
/// binary files (.kza, STL, PLY, GLB) build their image in memory, then save it atomically.
#pragma once

#include <bit>
#include <cstddef>
#include <cstring>
#include <string_view>
#include <vector>

namespace kizamu::util {

static_assert(std::endian::native == std::endian::little, "binary file writers assume a little-endian host");

/// One per file being written; not thread-safe.
class ByteWriter {
public:
    /// Appends the object representation of `v` (a trivially copyable value).
    template <class T>
    void put(const T& v) {
        putRaw(&v, sizeof(T));
    }
    void putRaw(const void* p, std::size_t n) {
        const std::size_t at = mBytes.size();
        mBytes.resize(at + n);  // resize + memcpy: GCC 12 warns falsely on vector::insert here
        if (n) std::memcpy(mBytes.data() + at, p, n);
    }
    void text(std::string_view s) { putRaw(s.data(), s.size()); }
    /// Appends `fill` until the size is a multiple of `alignment`.
    void pad(std::size_t alignment, std::byte fill) {
        while (mBytes.size() % alignment) mBytes.push_back(fill);
    }
    std::size_t size() const { return mBytes.size(); }
    std::vector<std::byte>& bytes() { return mBytes; }

private:
    std::vector<std::byte> mBytes;
};

}  // namespace kizamu::util
