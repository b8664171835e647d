// SPDX-License-Identifier: Apache-2.0
// .kza round trip, atomic save, and damaged files: truncated, bit-flipped, foreign, and
// structurally corrupt ones with a valid checksum. Every failure is a one-line FileError.
#include "adf/adf_file.h"

#include "adf/colour_layer.h"
#include "adf/generate.h"
#include "adf/test_part.h"
#include "tests/util/adf_compare.h"
#include "util/file_error.h"

#include <gtest/gtest.h>
#include <zlib.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>

using namespace kizamu;
using namespace kizamu::adf;

namespace {

AdfPtr smallPart() {
    static const AdfPtr adf = [] {
        const Domain d = testPartDomain(7);
        return generate(*makeTestPart(d), d, testPartSettings());
    }();
    return adf;
}

std::string encoded() {
    const auto bytes = encodeAdf(*smallPart());
    return {reinterpret_cast<const char*>(bytes.data()), bytes.size()};
}

/// Recomputes the trailing CRC so that a deliberate corruption reaches the structural checks.
void fixChecksum(std::string& s);

/// Loads 300 copies of `full` with `flips` random bytes changed at or after `from` (checksum
/// fixed): each must load or throw FileError, never crash. Returns how many threw.
int rejectedDamages(const std::string& full, std::size_t from, int flips, uint64_t seed) {
    std::mt19937_64 rng(seed);
    int caught = 0;
    for (int i = 0; i < 300; ++i) {
        std::string bad = full;
        for (int k = 0; k < flips; ++k) bad[from + rng() % (bad.size() - from - 4)] = char(rng());
        fixChecksum(bad);
        try {
            decodeAdf(bad, "x.kza");
        } catch (const FileError&) {
            ++caught;
        }
    }
    return caught;
}

void fixChecksum(std::string& s) {
    const uint32_t crc = uint32_t(crc32(0L, reinterpret_cast<const Bytef*>(s.data()), uInt(s.size() - 4)));
    std::memcpy(s.data() + s.size() - 4, &crc, 4);
}

std::string errorOf(const std::string& bytes) {
    try {
        decodeAdf(bytes, "x.kza");
    } catch (const FileError& e) {
        const std::string msg = e.what();
        EXPECT_EQ(msg.find('\n'), std::string::npos) << "message must be one line";
        EXPECT_EQ(msg.rfind("x.kza: ", 0), 0u) << "message must name the file";
        return msg;
    }
    return "";
}

constexpr std::size_t kHeaderBytes = 8 + 4 + 4 * 8 + 2 * 4 + 4 * 8 + 8 + 8;

/// smallPart() with paint: a few slots of random points in random colours (none the base).
AdfPtr paintedPart() {
    static const AdfPtr adf = [] {
        const AdfPtr plain = smallPart();
        const ColourLayer empty(plain->domain());
        std::mt19937_64 rng(5);
        std::vector<std::pair<uint32_t, ColourTilePtr>> tiles;
        const uint32_t points = 1u << (3 * plain->domain().tileSpan());
        for (uint32_t key : {0u, 3u, 5u, 7u}) {
            std::vector<uint32_t> idx;
            for (uint32_t p = uint32_t(rng() % 7); p < points; p += 1 + uint32_t(rng() % 50)) idx.push_back(p);
            std::vector<Rgb8> colours;
            for (std::size_t i = 0; i < idx.size(); ++i) colours.push_back(Rgb8(uint8_t(rng() % 150), uint8_t(rng()), uint8_t(rng())));
            tiles.emplace_back(key, std::make_shared<const ColourTile>(std::move(idx), std::move(colours)));
        }
        AdfBuilder b(*plain);
        b.setColours(empty.withTiles(std::move(tiles)));
        return b.build(plain->version() + 1);
    }();
    return adf;
}

std::string encodedPainted() {
    const auto bytes = encodeAdf(*paintedPart());
    return {reinterpret_cast<const char*>(bytes.data()), bytes.size()};
}

/// Where the colour section starts: right after the tiles, which an unpainted file ends with.
std::size_t colourSectionAt() { return encoded().size() - 4; }

TEST(AdfFile, RoundTripIsExact) {
    const AdfPtr a = smallPart();
    const std::string bytes = encoded();
    const AdfPtr b = decodeAdf(bytes, "mem");
    EXPECT_TRUE(test::sameAdf(*a, *b));
    EXPECT_EQ(a->version(), b->version());
    EXPECT_EQ(a->settings(), b->settings());
    EXPECT_EQ(a->distance({0.31f, 0.52f, 0.77f}), b->distance({0.31f, 0.52f, 0.77f}));
    // Same snapshot, same bytes.
    EXPECT_EQ(encoded(), bytes);
}

TEST(AdfFile, SaveReplacesAtomicallyAndLoads) {
    const auto dir = std::filesystem::temp_directory_path() / ("kizamu_file_test_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    const std::string path = (dir / "part.kza").string();
    { std::ofstream(path) << "old contents"; }
    saveAdf(*smallPart(), path);
    EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));
    EXPECT_TRUE(test::sameAdf(*loadAdf(path), *smallPart()));
    EXPECT_THROW(loadAdf((dir / "missing.kza").string()), FileError);
    EXPECT_THROW(saveAdf(*smallPart(), (dir / "no" / "such" / "dir.kza").string()), FileError);
    std::filesystem::remove_all(dir);
}

TEST(AdfFile, ForeignAndEmptyFilesAreNamedAsSuch) {
    EXPECT_NE(errorOf("").find("not a Kizamu ADF file"), std::string::npos);
    EXPECT_NE(errorOf("solid cube\nfacet normal 0 0 1\n").find("not a Kizamu ADF file"), std::string::npos);
    EXPECT_NE(errorOf("\x89PNG\r\n\x1a\n rest of a png").find("not a Kizamu ADF file"), std::string::npos);
}

TEST(AdfFile, EveryTruncationIsReported) {
    const std::string full = encoded();
    const std::size_t stride = full.size() / 200 + 1;
    for (std::size_t len = 0; len < full.size(); len += (len < kHeaderBytes + 64 ? 1 : stride)) {
        const std::string msg = errorOf(full.substr(0, len));
        ASSERT_FALSE(msg.empty()) << "truncation to " << len << " bytes was accepted";
        EXPECT_TRUE(msg.find("truncated") != std::string::npos || msg.find("not a Kizamu") != std::string::npos ||
                    msg.find("checksum") != std::string::npos)
            << len << ": " << msg;
    }
}

TEST(AdfFile, BitFlipsFailTheChecksum) {
    const std::string full = encoded();
    std::mt19937_64 rng(2);
    for (int i = 0; i < 200; ++i) {
        std::string bad = full;
        const std::size_t at = 8 + rng() % (bad.size() - 8);
        bad[at] = char(bad[at] ^ (1 << (rng() % 8)));
        const std::string msg = errorOf(bad);
        ASSERT_FALSE(msg.empty()) << "flip at " << at << " was accepted";
    }
}

TEST(AdfFile, StructuralDamageWithAValidChecksumIsCaught) {
    const std::string full = encoded();
    {
        std::string bad = full;
        const uint32_t v = 99;
        std::memcpy(bad.data() + 8, &v, 4);
        fixChecksum(bad);
        EXPECT_NE(errorOf(bad).find("unsupported .kza format version 99"), std::string::npos);
    }
    {
        std::string bad = full;
        const int32_t level = 40;
        std::memcpy(bad.data() + 8 + 4 + 32, &level, 4);
        fixChecksum(bad);
        EXPECT_NE(errorOf(bad).find("invalid domain"), std::string::npos);
    }
    // Random corruption of tile records behind a valid checksum: an error, never a crash.
    EXPECT_GT(rejectedDamages(full, kHeaderBytes, 3, 3), 0);
}

TEST(AdfFile, PaintRoundTripsBitForBit) {
    const AdfPtr a = paintedPart();
    const std::string bytes = encodedPainted();
    const AdfPtr b = decodeAdf(bytes, "mem");
    EXPECT_TRUE(test::sameAdf(*a, *b));
    ASSERT_NE(b->colours(), nullptr);
    const ColourLayer& la = *a->colours();
    const ColourLayer& lb = *b->colours();
    EXPECT_EQ(la.baseColour(), lb.baseColour());
    ASSERT_EQ(la.slotCount(), lb.slotCount());
    for (std::size_t i = 0; i < la.slotCount(); ++i) {
        EXPECT_EQ(la.slotKeys()[i], lb.slotKeys()[i]);
        const ColourTile &ta = *la.tiles()[i], &tb = *lb.tiles()[i];
        ASSERT_EQ(ta.size(), tb.size());
        EXPECT_TRUE(std::equal(ta.points().begin(), ta.points().end(), tb.points().begin()));
        EXPECT_TRUE(std::equal(ta.colours().begin(), ta.colours().end(), tb.colours().begin()));
    }
    EXPECT_EQ(la.pointCount(), lb.pointCount());
    EXPECT_GT(la.pointCount(), 100u);
    EXPECT_EQ(encodeAdf(*b), encodeAdf(*a));
    // Unpainted clay stays unpainted (no empty layer appears).
    EXPECT_EQ(decodeAdf(encoded(), "mem")->colours(), nullptr);
}

TEST(AdfFile, VersionOneFilesStillLoad) {
    // An unpainted version-2 file is a version-1 file with another number: no sections follow.
    std::string v1 = encoded();
    const uint32_t one = 1;
    std::memcpy(v1.data() + 8, &one, 4);
    fixChecksum(v1);
    const AdfPtr a = decodeAdf(v1, "v1.kza");
    EXPECT_TRUE(test::sameAdf(*a, *smallPart()));
    // ...and version 1 has no sections.
    std::string v1painted = encodedPainted();
    std::memcpy(v1painted.data() + 8, &one, 4);
    fixChecksum(v1painted);
    EXPECT_NE(errorOf(v1painted).find("unexpected data after the last tile"), std::string::npos);
}

TEST(AdfFile, DamagedColourSectionsAreFileErrors) {
    const std::string full = encodedPainted();
    const std::size_t at = colourSectionAt();  // tag, length, then the payload
    const std::size_t payload = at + 12;
    auto damaged = [&](std::size_t offset, const void* value, std::size_t n) {
        std::string bad = full;
        std::memcpy(bad.data() + offset, value, n);
        fixChecksum(bad);
        return errorOf(bad);
    };
    ASSERT_EQ(full.substr(at, 4), "COLR");
    const uint32_t huge = 0x7fffffffu, zero = 0;
    const uint64_t longer = full.size();
    EXPECT_NE(damaged(at, "XTRA", 4).find("unknown section 'XTRA'"), std::string::npos);
    EXPECT_NE(damaged(at + 4, &longer, 8).find("section 'COLR' is longer than the file"), std::string::npos);
    EXPECT_NE(damaged(payload + 3, "\x01", 1).find("reserved byte"), std::string::npos);
    EXPECT_NE(damaged(payload + 4, &huge, 4).find("painted slots cannot fit"), std::string::npos);
    const std::size_t slot0 = payload + 8;  // key, count, points, colours
    EXPECT_NE(damaged(slot0, &huge, 4).find("outside the domain"), std::string::npos);
    EXPECT_NE(damaged(slot0 + 4, &zero, 4).find("impossible point count"), std::string::npos);
    EXPECT_NE(damaged(slot0 + 4, &huge, 4).find("impossible point count"), std::string::npos);
    const uint32_t count = [&] {
        uint32_t c;
        std::memcpy(&c, full.data() + slot0 + 4, 4);
        return c;
    }();
    const uint32_t more = count + 100000;
    EXPECT_NE(damaged(slot0 + 4, &more, 4).find("runs past the end of the section"), std::string::npos);
    const uint32_t bigger = count + 10;
    EXPECT_NE(damaged(slot0 + 4, &bigger, 4).find("colour section"), std::string::npos);
    EXPECT_NE(damaged(slot0 + 8, &huge, 4).find("point index out of range"), std::string::npos);
    uint32_t second;
    std::memcpy(&second, full.data() + slot0 + 12, 4);
    EXPECT_NE(damaged(slot0 + 8, &second, 4).find("points not strictly increasing"), std::string::npos);
    const Rgb8 base = kClayColour;
    EXPECT_NE(damaged(slot0 + 8 + 4 * std::size_t(count), &base, 3).find("stores the base colour"), std::string::npos);
    // The second slot's key not above the first's.
    const std::size_t slot1 = slot0 + 8 + 7 * std::size_t(count);
    EXPECT_NE(damaged(slot1, &zero, 4).find("not strictly increasing"), std::string::npos);
    // Every truncation inside the section is reported, and so is any random damage behind a
    // valid checksum (an error or a clean load, never a crash).
    for (std::size_t len = at; len < full.size(); len += (len < payload + 32 ? 1 : (full.size() - at) / 200 + 1)) {
        const std::string msg = errorOf(full.substr(0, len));
        EXPECT_TRUE(msg.find("truncated") != std::string::npos || msg.find("checksum") != std::string::npos) << len << ": " << msg;
    }
    EXPECT_GT(rejectedDamages(full, at, 1, 8), 0);
}

}  // namespace

TEST(AdfFile, LeafIndicesPastTheFilesLeavesAreRejectedThoughGroupsHaveMoreSlots) {
    // A built tile numbers 8 slots per leaf group, more than the file's leaves: an index past
    // the file's leaves must not land on a group's unused slot.
    const std::string full = encoded();
    std::vector<const Tile*> tiles;
    smallPart()->forEachTile([&](const Tile& t) { tiles.push_back(&t); });  // the writer's order
    std::size_t at = kHeaderBytes, tested = 0;
    for (const Tile* t : tiles) {
        uint32_t nodeCount, leafCount, brickCount;
        std::memcpy(&nodeCount, full.data() + at + 20, 4);
        std::memcpy(&leafCount, full.data() + at + 24, 4);
        std::memcpy(&brickCount, full.data() + at + 28, 4);
        const std::size_t words = at + 32;
        if (t->groupCount() > 0 && tested < 3) {
            ASSERT_LT(leafCount, t->leafCount()) << "a group's unused slots";
            for (uint32_t i = 0; i < nodeCount; ++i) {
                uint32_t w;
                std::memcpy(&w, full.data() + words + 4 * i, 4);
                if (!node::isLeaf(w)) continue;
                for (uint32_t index = leafCount; index < t->leafCount(); ++index) {
                    std::string bad = full;
                    const uint32_t moved = node::makeLeaf(index, node::leafType(w));
                    std::memcpy(bad.data() + words + 4 * i, &moved, 4);
                    fixChecksum(bad);
                    EXPECT_NE(errorOf(bad).find("leaf index out of range"), std::string::npos) << index;
                }
                ++tested;
                break;
            }
        }
        at = words + 4 * std::size_t(nodeCount) + 16 * std::size_t(leafCount) + 54 * std::size_t(brickCount);
    }
    EXPECT_EQ(tested, 3u);
}
