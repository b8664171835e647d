// SPDX-License-Identifier: Apache-2.0
// .kza round trip, atomic save, and damaged files: truncated, bit-flipped, foreign, and
// structurally corrupt ones with a valid checksum. Every failure is a one-line FileError.
#include "adf/adf_file.h"

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
    std::mt19937_64 rng(3);
    int caught = 0;
    for (int i = 0; i < 300; ++i) {
        std::string bad = full;
        for (int k = 0; k < 3; ++k) {
            const std::size_t at = kHeaderBytes + rng() % (bad.size() - kHeaderBytes - 4);
            bad[at] = char(rng());
        }
        fixChecksum(bad);
        try {
            decodeAdf(bad, "x.kza");
        } catch (const FileError&) {
            ++caught;
        }
    }
    EXPECT_GT(caught, 0);
}

}  // namespace
