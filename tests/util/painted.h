// SPDX-License-Identifier: Apache-2.0
/// @file painted.h
/// @brief Test helpers: a snapshot with paint laid directly into its colour layer (no tool), and
/// a reader for the colours assimp finds in an exported file.
#pragma once

#include "adf/adf.h"
#include "adf/colour_layer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace kizamu::test {

/// `adf` with every lattice point at z >= zWorld painted `colour` (dense: small domains only).
inline adf::AdfPtr paintedAbove(const adf::AdfPtr& adf, adf::Rgb8 colour, double zWorld) {
    const adf::Domain& d = adf->domain();
    const adf::ColourLayer empty(d);
    const uint32_t span = uint32_t(d.tileSpan()), side = 1u << span, n = d.slotsPerAxis();
    const uint32_t zMin = uint32_t(std::ceil((zWorld - d.originWorld.z) / d.finestCellSize()));
    std::vector<std::pair<uint32_t, adf::ColourTilePtr>> tiles;
    for (uint32_t sz = 0; sz < n; ++sz)
        for (uint32_t sy = 0; sy < n; ++sy)
            for (uint32_t sx = 0; sx < n; ++sx) {
                std::vector<uint32_t> points;
                for (uint32_t z = 0; z < side; ++z) {
                    if (sz * side + z < zMin) continue;
                    for (uint32_t i = 0; i < side * side; ++i) points.push_back((z << (2 * span)) | i);
                }
                if (points.empty()) continue;
                std::vector<adf::Rgb8> colours(points.size(), colour);
                tiles.emplace_back(empty.slotKey({sx, sy, sz}),
                                   std::make_shared<const adf::ColourTile>(std::move(points), std::move(colours)));
            }
    adf::AdfBuilder b(*adf);
    b.setColours(empty.withTiles(std::move(tiles)));
    return b.build(adf->version() + 1);
}

/// What `assimp dump` reads from `path`: positions and the first colour set (RGB, 0..1 as
/// stored in the file). Fails the test when assimp is missing or reads no colours.
struct AssimpColours {
    std::vector<glm::vec3> positions;
    std::vector<glm::vec3> colours;
};
inline AssimpColours assimpColours(const std::string& path) {
    AssimpColours out;
    EXPECT_EQ(std::system("command -v assimp >/dev/null 2>&1"), 0) << "assimp (assimp-utils) is required";
    const std::string xml = path + ".assxml";
    if (std::system(("assimp dump '" + path + "' '" + xml + "' >/dev/null 2>&1").c_str()) != 0) {
        ADD_FAILURE() << "assimp dump failed on " << path;
        return out;
    }
    std::string text;
    if (FILE* f = std::fopen(xml.c_str(), "rb")) {
        char buf[65536];
        while (std::size_t n = std::fread(buf, 1, sizeof buf, f)) text.append(buf, n);
        std::fclose(f);
    }
    // Plain string search: std::regex recurses per character and overflows on big blocks.
    auto block = [&](const char* tag, std::vector<glm::vec3>& into) {
        const std::size_t at = text.find(std::string("<") + tag + " num=\"");
        if (at == std::string::npos) return false;
        unsigned long count = 0;
        int stride = 0;
        if (std::sscanf(text.c_str() + at + std::strlen(tag) + 1, " num=\"%lu\" set=\"0\" num_components=\"%d\"", &count,
                        &stride) != 2 ||
            stride < 3)
            return false;
        const std::size_t begin = text.find('>', at), end = text.find('<', begin);
        if (begin == std::string::npos || end == std::string::npos) return false;
        std::vector<float> v;
        const std::string body = text.substr(begin + 1, end - begin - 1);
        const char* p = body.c_str();
        char* next = nullptr;
        for (float x = std::strtof(p, &next); next != p; x = std::strtof(p, &next)) {
            v.push_back(x);
            p = next;
        }
        for (std::size_t i = 0; i + std::size_t(stride) <= v.size(); i += std::size_t(stride)) into.push_back({v[i], v[i + 1], v[i + 2]});
        return into.size() == count;
    };
    EXPECT_TRUE(block("Positions", out.positions)) << "assimp found no positions in " << path;
    EXPECT_TRUE(block("Colors", out.colours)) << "assimp found no vertex colours in " << path;
    return out;
}

/// sRGB byte of a linear value (glTF stores linear colours).
inline float srgbByteOfLinear(float v) {
    const float s = v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
    return 255.0f * s;
}

}  // namespace kizamu::test
