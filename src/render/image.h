// SPDX-License-Identifier: Apache-2.0
/// @file image.h
/// @brief An RGBA8 image (sRGB-encoded, top row first) and its PNG files (stb_image_write,
/// stb_image).
///
/// Plain value type; one owner, no internal synchronisation. PNG I/O is a cold path and
/// throws `FileError` (util/file_error.h) naming the file.
#pragma once

#include <glm/gtc/type_precision.hpp>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace kizamu::render {

struct Image {
    int width = 0;
    int height = 0;
    std::vector<uint8_t> pixels;  ///< RGBA8, row-major, top row first, no padding

    Image() = default;
    /// A width × height image of zeros.
    Image(int w, int h) : width(w), height(h), pixels(std::size_t(w) * std::size_t(h) * 4, 0) {}

    /// The pixel at column x, row y (0: top). Precondition: in range.
    glm::u8vec4 at(int x, int y) const {
        const uint8_t* p =
            pixels.data() + (std::size_t(y) * std::size_t(width) + std::size_t(x)) * 4;
        return {p[0], p[1], p[2], p[3]};
    }
};

/// Writes `image` to `path` as an 8-bit RGBA PNG.
/// @throw FileError when the file cannot be written or the image is empty.
/// Complexity: O(pixels) (zlib). Threading: any thread. Memory: stb's compression buffers.
void writePng(const std::string& path, const Image& image);

/// Reads a PNG (any channel count; converted to RGBA8).
/// @throw FileError when the file is missing or not a readable image.
/// Complexity: O(pixels). Threading: any thread. Memory: the returned image.
Image readPng(const std::string& path);

}  // namespace kizamu::render
