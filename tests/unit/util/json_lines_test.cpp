// SPDX-License-Identifier: Apache-2.0
// The shared JSON Lines loop (json_lines.h): comments and blank lines skipped, CRLF endings,
// line numbers that count every line, errors on one line with the file and the line.
#include "util/json_lines.h"

#include "util/file_error.h"

#include <gtest/gtest.h>

#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace kizamu::util {
namespace {

TEST(JsonLines, SkipsCommentsAndBlankLinesAndCountsEveryLine) {
    std::vector<std::string> seen;
    const std::string text = "# a comment\r\n{\"a\": 1}\r\n\n   \t\n  # indented comment\n{\"b\": 2}";
    forEachJsonLine(text, "t.jsonl", [&](std::string_view line) { seen.emplace_back(line); });
    EXPECT_EQ(seen, (std::vector<std::string>{"{\"a\": 1}", "{\"b\": 2}"})) << "the CR is gone";
    try {
        forEachJsonLine(text, "t.jsonl", [](std::string_view line) {
            if (line.find('b') != std::string_view::npos) throw std::invalid_argument("b");
        });
        ADD_FAILURE() << "no error";
    } catch (const FileError& e) {
        EXPECT_STREQ(e.what(), "t.jsonl: line 6: b") << "every line counts, comments and blanks too";
    }
}

TEST(JsonLines, RecordsAfterTheHeader) {
    std::vector<int> records;
    int header = 0;
    EXPECT_TRUE(forEachJsonRecord("# c\n{\"h\": 7}\n{\"r\": 1}\n{\"r\": 2}\n", "t", [&](const nlohmann::json& j) { header = j["h"]; },
                                  [&](const nlohmann::json& j) { records.push_back(j["r"]); }));
    EXPECT_EQ(header, 7);
    EXPECT_EQ(records, (std::vector<int>{1, 2}));
    EXPECT_FALSE(forEachJsonRecord("# only a comment\n", "t", [](const nlohmann::json&) {}, [](const nlohmann::json&) {}));
}

TEST(JsonLines, ErrorsAreOneLineWithTheFileAndTheLine) {
    const auto error = [](const std::string& text) {
        try {
            forEachJsonLine(text, "bad.jsonl", [](std::string_view line) {
                const nlohmann::json j = nlohmann::json::parse(line);
                if (j.contains("x")) finiteNumber(j["x"], "x");
            });
        } catch (const FileError& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    EXPECT_EQ(error("{}\n{\"x\": 1}\n"), "no error");
    EXPECT_EQ(error("{}\n\n{\"x\": \"one\"}\n").find("bad.jsonl: line 3: \"x\" must be a number"), 0u);
    const std::string parse = error("{}\n{\"x\": \n");
    EXPECT_EQ(parse.find("bad.jsonl: line 2: "), 0u) << parse;
    EXPECT_EQ(parse.find('\n'), std::string::npos);
    EXPECT_THROW(finiteNumber(nlohmann::json(std::numeric_limits<double>::infinity()), "x"), std::invalid_argument);
    EXPECT_EQ(oneLine("a\nb\rc"), "a b c");
}

}  // namespace
}  // namespace kizamu::util
