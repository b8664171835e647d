// SPDX-License-Identifier: Apache-2.0
/// @file adf_file.cpp
/// @brief .kza encoding and validating decoding.
#include "adf/adf_file.h"

#include "adf/colour_layer.h"
#include "util/atomic_file.h"
#include "util/byte_writer.h"
#include "util/file_error.h"

#include <glm/vector_relational.hpp>
#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string_view>

namespace kizamu::adf {

namespace {

// PNG-style magic: a high byte and CR/LF catch 7-bit and text-mode mangling.
constexpr char kMagic[8] = {'\x89', 'K', 'Z', 'A', '\r', '\n', '\x1a', '\n'};

class Reader {
public:
    Reader(std::string_view bytes, const std::string& name) : mBytes(bytes), mName(name) {}
    template <class T>
    T get(const char* what) {
        T v;
        getBytes(&v, sizeof(T), what);
        return v;
    }
    void getBytes(void* out, std::size_t n, const std::string& what) {
        if (n == 0) return;  // `out` may be the null data() of an empty vector
        if (n > mBytes.size() - mPos) fail("truncated: " + what + " ends past the end of the file");
        std::memcpy(out, mBytes.data() + mPos, n);
        mPos += n;
    }
    std::size_t remaining() const { return mBytes.size() - mPos; }
    std::size_t position() const { return mPos; }
    void skip(std::size_t n) { mPos += std::min(n, remaining()); }
    [[noreturn]] void fail(const std::string& problem) const { throw FileError(mName, problem); }

private:
    std::string_view mBytes;
    std::size_t mPos = 0;
    const std::string& mName;
};

/// Checks that the node words form a tree rooted at 0 whose children always follow their
/// parent (so walking it terminates), no deeper than `maxDepth`, with every own leaf and brick
/// used exactly once, a leaf group's slots at most once (the loader has checked the file's leaf
/// indices; the build puts each member in its slot), and each lone leaf's type matching the
/// signs of its corners.
bool validTree(const Tile& t, int maxDepth, std::string& why) {
    struct Item {
        uint32_t node;
        int depth;
    };
    std::vector<Item> stack{{0, 0}};
    std::vector<uint8_t> seenLeaf(t.leafCount(), 0), seenBrick(t.brickCount(), 0);
    std::size_t visited = 0;
    while (!stack.empty()) {
        const Item it = stack.back();
        stack.pop_back();
        if (++visited > t.nodeCount()) return why = "a node is reachable twice", false;
        const uint32_t w = t.node(it.node);
        if (node::isLeaf(w)) {
            const uint32_t leaf = node::leafIndex(w);
            if (leaf >= t.leafCount()) return why = "leaf index out of range", false;
            if (seenLeaf[leaf]++) return why = "two cells share one leaf", false;
            float c[8];
            for (int k = 0; k < 8; ++k) c[k] = t.corner(leaf, k);
            if (node::leafType(w) != cellTypeOf(std::span<const float, 8>(c, 8)))
                return why = "cell type does not match its corner signs", false;
            continue;
        }
        if (node::isBrick(w)) {
            const uint32_t brick = node::brickIndex(w);
            if (brick >= t.brickCount()) return why = "brick index out of range", false;
            if (seenBrick[brick]++) return why = "two cells share one brick", false;
            if (it.depth + 1 > maxDepth) return why = "cells deeper than the maximum level", false;
            continue;
        }
        if (w <= it.node || uint64_t(w) + 8 > t.nodeCount()) return why = "child index out of range", false;
        if (it.depth + 1 > maxDepth) return why = "cells deeper than the maximum level", false;
        for (uint32_t c = 0; c < 8; ++c) stack.push_back({w + c, it.depth + 1});
    }
    if (visited != t.nodeCount()) return why = "unreachable nodes", false;
    // Slots of a leaf group whose child is not a lone leaf hold no values of their own.
    for (std::size_t l = 8 * std::size_t(t.groupCount()); l < seenLeaf.size(); ++l)
        if (!seenLeaf[l]) return why = "unused leaf values", false;
    for (uint8_t used : seenBrick)
        if (!used) return why = "unused brick values", false;
    return true;
}

/// Section tags: four ASCII bytes, read as a little-endian u32.
constexpr uint32_t sectionTag(const char (&t)[5]) {
    return uint32_t(uint8_t(t[0])) | uint32_t(uint8_t(t[1])) << 8 | uint32_t(uint8_t(t[2])) << 16 | uint32_t(uint8_t(t[3])) << 24;
}
constexpr uint32_t kColourSection = sectionTag("COLR");

std::string tagText(uint32_t tag) {
    std::string s;
    for (int k = 0; k < 4; ++k) {
        const char c = char((tag >> (8 * k)) & 0xffu);
        s += (c >= 0x20 && c < 0x7f) ? c : '?';
    }
    return s;
}

void encodeColours(const ColourLayer& layer, util::ByteWriter& w) {
    util::ByteWriter p;
    p.put(layer.baseColour());
    p.put(uint8_t(0));  // reserved
    p.put(uint32_t(layer.slotCount()));
    for (std::size_t i = 0; i < layer.slotCount(); ++i) {
        const ColourTile& t = *layer.tiles()[i];
        p.put(layer.slotKeys()[i]);
        p.put(uint32_t(t.size()));
        p.putRaw(t.points().data(), t.size() * sizeof(uint32_t));
        p.putRaw(t.colours().data(), t.size() * sizeof(Rgb8));
    }
    w.put(kColourSection);
    w.put(uint64_t(p.size()));
    w.putRaw(p.bytes().data(), p.size());
}

/// Reads and checks a colour section of `length` bytes (the checksum is already known good).
ColourLayerPtr decodeColours(Reader& r, uint64_t length, const Domain& d) {
    const std::size_t end = r.position() + std::size_t(length);
    auto left = [&] { return end - r.position(); };
    auto need = [&](uint64_t bytes, const std::string& what) {
        if (bytes > left()) r.fail("colour section: " + what + " runs past the end of the section");
    };
    need(8, "the header");
    Rgb8 base;
    r.getBytes(&base, sizeof base, "colour section");
    if (r.get<uint8_t>("colour section") != 0) r.fail("colour section: reserved byte is not zero");
    const auto slots = r.get<uint32_t>("colour section");
    const uint64_t totalSlots = uint64_t(d.slotsPerAxis()) * d.slotsPerAxis() * d.slotsPerAxis();
    const uint32_t pointsPerSlot = 1u << (3 * d.tileSpan());
    if (slots > totalSlots || uint64_t(slots) * 8 > left())
        r.fail("colour section: " + std::to_string(slots) + " painted slots cannot fit");
    std::vector<uint32_t> keys(slots);
    std::vector<ColourTilePtr> tiles(slots);
    for (uint32_t i = 0; i < slots; ++i) {
        const std::string what = "painted slot " + std::to_string(i) + " of " + std::to_string(slots);
        need(8, what);
        keys[i] = r.get<uint32_t>("colour section");
        const auto count = r.get<uint32_t>("colour section");
        if (keys[i] >= totalSlots) r.fail("colour section: " + what + " lies outside the domain");
        if (i > 0 && keys[i] <= keys[i - 1]) r.fail("colour section: slots are not strictly increasing");
        if (count == 0 || count > pointsPerSlot) r.fail("colour section: " + what + " has an impossible point count");
        need(uint64_t(count) * (sizeof(uint32_t) + sizeof(Rgb8)), what);
        std::vector<uint32_t> points(count);
        std::vector<Rgb8> colours(count);
        r.getBytes(points.data(), points.size() * sizeof(uint32_t), what);
        r.getBytes(colours.data(), colours.size() * sizeof(Rgb8), what);
        for (uint32_t k = 0; k < count; ++k) {
            if (points[k] >= pointsPerSlot) r.fail("colour section: " + what + " has a point index out of range");
            if (k > 0 && points[k] <= points[k - 1]) r.fail("colour section: " + what + " has points not strictly increasing");
            if (colours[k] == base) r.fail("colour section: " + what + " stores the base colour (unpainted points are not stored)");
        }
        tiles[i] = std::make_shared<const ColourTile>(std::move(points), std::move(colours));
    }
    if (left() != 0) r.fail("colour section: " + std::to_string(left()) + " bytes after the last painted slot");
    return ColourLayer::create(d, base, std::move(keys), std::move(tiles));
}

}  // namespace

std::vector<std::byte> encodeAdf(const Adf& adf) {
    util::ByteWriter w;
    const Domain& d = adf.domain();
    const GenerationSettings& s = adf.settings();
    w.putRaw(kMagic, sizeof kMagic);
    w.put(kAdfFormatVersion);
    w.put(d.originWorld.x);
    w.put(d.originWorld.y);
    w.put(d.originWorld.z);
    w.put(d.sizeWorld);
    w.put(int32_t(d.maxLevel));
    w.put(int32_t(d.tileSpanLevels));
    w.put(s.epsilonCells);
    w.put(s.boundK);
    w.put(s.boundC);
    w.put(s.bandCells);
    w.put(adf.version());
    const std::size_t countAt = w.bytes().size();
    w.put(uint64_t(0));
    uint64_t tiles = 0;
    adf.forEachTile([&](const Tile& t) {
        ++tiles;
        w.put(int32_t(t.level()));
        w.put(t.latticeOrigin().x);
        w.put(t.latticeOrigin().y);
        w.put(t.latticeOrigin().z);
        w.put(t.scale());
        // Node words as 32 bits, leaves and bricks as 16-bit values (packed ones decoded), each
        // lone leaf with its own 8 corners: the format predates the packed forms and leaf
        // groups, and loading packs and groups them again to the same bits.
        const Tile::Quantised q = t.quantised();
        w.put(t.nodeCount());
        w.put(uint32_t(q.leafCorners.size() / 8));
        w.put(t.brickCount());
        w.putRaw(q.nodes.data(), q.nodes.size() * 4);
        w.putRaw(q.leafCorners.data(), q.leafCorners.size() * 2);
        w.putRaw(q.brickValues.data(), q.brickValues.size() * 2);
    });
    std::memcpy(w.bytes().data() + countAt, &tiles, sizeof tiles);
    if (adf.colours()) encodeColours(*adf.colours(), w);
    const uLong crc = crc32_z(0L, reinterpret_cast<const Bytef*>(w.bytes().data()), w.bytes().size());
    w.put(uint32_t(crc));
    return std::move(w.bytes());
}

AdfPtr decodeAdf(const std::string& bytes, const std::string& name) {
    Reader r(bytes, name);
    char magic[8];
    if (bytes.size() < sizeof magic || std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0)
        r.fail("not a Kizamu ADF file (.kza magic missing)");
    r.getBytes(magic, sizeof magic, "magic");
    const auto version = r.get<uint32_t>("format version");
    if (version < 1 || version > kAdfFormatVersion)
        r.fail("unsupported .kza format version " + std::to_string(version) + " (this build reads 1 to " +
               std::to_string(kAdfFormatVersion) + ")");
    if (bytes.size() < 4 + 8 + 4) r.fail("truncated: no room for the checksum");
    uint32_t stored;
    std::memcpy(&stored, bytes.data() + bytes.size() - 4, 4);
    const uLong crc = crc32_z(0L, reinterpret_cast<const Bytef*>(bytes.data()), bytes.size() - 4);
    // A shorter file usually fails the checksum; say "truncated" when the tiles run out first.
    const bool crcOk = uint32_t(crc) == stored;

    Domain d;
    d.originWorld.x = r.get<double>("domain origin");
    d.originWorld.y = r.get<double>("domain origin");
    d.originWorld.z = r.get<double>("domain origin");
    d.sizeWorld = r.get<double>("domain size");
    d.maxLevel = r.get<int32_t>("maximum level");
    d.tileSpanLevels = r.get<int32_t>("tile span");
    GenerationSettings s;
    s.epsilonCells = r.get<double>("epsilon");
    s.boundK = r.get<double>("bound k");
    s.boundC = r.get<double>("bound C");
    s.bandCells = r.get<double>("band");
    const auto snapshotVersion = r.get<uint64_t>("snapshot version");
    const auto tileCount = r.get<uint64_t>("tile count");
    if (!crcOk && r.remaining() < 4) r.fail("truncated: the file ends inside its header");
    if (!d.valid()) r.fail("invalid domain in header (level " + std::to_string(d.maxLevel) + ")");
    if (!s.valid()) r.fail("invalid generation settings in header");
    const uint64_t totalSlots = uint64_t(d.slotsPerAxis()) * d.slotsPerAxis() * d.slotsPerAxis();
    if (tileCount == 0 || tileCount > totalSlots) r.fail("tile count " + std::to_string(tileCount) + " is impossible");

    AdfBuilder builder(d, s);
    uint64_t coveredSlots = 0;
    for (uint64_t i = 0; i < tileCount; ++i) {
        const std::string what = "tile " + std::to_string(i) + " of " + std::to_string(tileCount);
        if (!crcOk && r.remaining() < 4 + 36) r.fail("truncated: " + what + " is missing");
        const auto level = r.get<int32_t>(what.c_str());
        glm::uvec3 origin;
        origin.x = r.get<uint32_t>(what.c_str());
        origin.y = r.get<uint32_t>(what.c_str());
        origin.z = r.get<uint32_t>(what.c_str());
        const auto scale = r.get<float>(what.c_str());
        const auto nodeCount = r.get<uint32_t>(what.c_str());
        const auto leafCount = r.get<uint32_t>(what.c_str());
        const auto brickCount = r.get<uint32_t>(what.c_str());
        if (level < 0 || level > d.tileLevel()) r.fail(what + " has level " + std::to_string(level) + " above its tile level");
        const uint32_t cell = d.cellLattice(level);
        if (origin.x % cell || origin.y % cell || origin.z % cell ||
            glm::any(glm::greaterThanEqual(origin, glm::uvec3(d.latticeSize()))))
            r.fail(what + " lies outside the domain or off its grid");
        if (!(scale > 0.0f) || !std::isfinite(scale)) r.fail(what + " has an invalid distance scale");
        if (nodeCount == 0 || leafCount + uint64_t(brickCount) == 0 || leafCount + uint64_t(brickCount) > nodeCount ||
            uint64_t(nodeCount) * 4 + uint64_t(leafCount) * 16 + uint64_t(brickCount) * 54 > r.remaining())
            r.fail(crcOk ? what + " has impossible cell counts" : "truncated: " + what + " ends past the end of the file");
        std::vector<uint32_t> nodes(nodeCount);
        std::vector<int16_t> corners(std::size_t(leafCount) * 8), bricks(std::size_t(brickCount) * 27);
        r.getBytes(nodes.data(), nodes.size() * 4, what);
        r.getBytes(corners.data(), corners.size() * 2, what);
        r.getBytes(bricks.data(), bricks.size() * 2, what);
        if (!crcOk) continue;  // reported below, once the structure has been read
        // Checked here, not after building: the built tile numbers leaves differently (leaf
        // groups), so a file's out-of-range index could land on a group's unused slot there.
        for (uint32_t w : nodes)
            if (node::isLeaf(w) && node::leafIndex(w) >= leafCount) r.fail(what + ": leaf index out of range");
        TilePtr tile = Tile::createQuantised(level, origin, nodes, corners, bricks, scale, snapshotVersion, d.finestCellSize());
        std::string why;
        if (!validTree(*tile, d.maxLevel - level, why)) r.fail(what + ": " + why);
        const uint64_t side = uint64_t(1) << (d.tileLevel() - level);
        coveredSlots += side * side * side;
        builder.setTile(std::move(tile));
    }
    // Version 2: tagged sections until the checksum, each a u32 tag, a u64 length and its bytes.
    bool haveColours = false;
    while (version >= 2 && r.remaining() > 4) {
        if (r.remaining() < 4 + 12) r.fail(crcOk ? "a section header is cut short" : "truncated: a section header is missing");
        const auto tag = r.get<uint32_t>("section tag");
        const auto length = r.get<uint64_t>("section length");
        const std::string what = "section '" + tagText(tag) + "'";
        if (length > r.remaining() - 4)
            r.fail(crcOk ? what + " is longer than the file" : "truncated: " + what + " ends past the end of the file");
        if (!crcOk) {
            r.skip(std::size_t(length));
            continue;
        }
        if (tag != kColourSection) r.fail("unknown " + what + " (written by a newer Kizamu?)");
        if (haveColours) r.fail("two colour sections");
        haveColours = true;
        builder.setColours(decodeColours(r, length, d));
    }
    if (!crcOk) {
        if (r.remaining() < 4) r.fail("truncated: the checksum is missing");
        r.fail("checksum mismatch: the file is corrupt");
    }
    if (r.remaining() != 4) r.fail(version >= 2 ? "unexpected data after the last section" : "unexpected data after the last tile");
    if (coveredSlots != totalSlots) r.fail("tiles overlap or leave holes in the domain");
    try {
        return builder.build(snapshotVersion);
    } catch (const std::logic_error&) {
        r.fail("tiles overlap or leave holes in the domain");
    }
}

void saveAdf(const Adf& adf, const std::string& path) {
    const std::vector<std::byte> bytes = encodeAdf(adf);
    util::writeFileAtomically(path, bytes);
}

AdfPtr loadAdf(const std::string& path) { return decodeAdf(util::readWholeFile(path), path); }

}  // namespace kizamu::adf
