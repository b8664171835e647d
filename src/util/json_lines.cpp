// SPDX-License-Identifier: Apache-2.0
/// @file json_lines.cpp
/// @brief forEachJsonLine, forEachJsonRecord, finiteNumber, oneLine.
#include "util/json_lines.h"

#include "util/file_error.h"

#include <cmath>
#include <exception>
#include <new>
#include <stdexcept>

namespace kizamu::util {

void forEachJsonLine(std::string_view text, const std::string& name,
                     const std::function<void(std::string_view line)>& record) {
    int lineNo = 0;
    for (std::size_t at = 0; at < text.size();) {
        std::size_t end = text.find('\n', at);
        if (end == std::string_view::npos) end = text.size();
        std::string_view line = text.substr(at, end - at);
        at = end + 1;
        ++lineNo;
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
        const auto first = line.find_first_not_of(" \t\r");
        if (first == std::string_view::npos || line[first] == '#') continue;
        try {
            record(line);
        } catch (const FileError&) {
            throw;
        } catch (const std::bad_alloc&) {
            throw;
        } catch (const std::exception& e) {
            throw FileError(name, "line " + std::to_string(lineNo) + ": " + oneLine(e.what()));
        }
    }
}

bool forEachJsonRecord(std::string_view text, const std::string& name, const std::function<void(const nlohmann::json&)>& header,
                       const std::function<void(const nlohmann::json&)>& record) {
    bool seenHeader = false;
    forEachJsonLine(text, name, [&](std::string_view line) {
        const nlohmann::json j = nlohmann::json::parse(line);
        if (seenHeader) {
            record(j);
        } else {
            header(j);
            seenHeader = true;
        }
    });
    return seenHeader;
}

double finiteNumber(const nlohmann::json& j, const char* what) {
    if (!j.is_number()) throw std::invalid_argument(std::string("\"") + what + "\" must be a number");
    const double v = j.get<double>();
    if (!std::isfinite(v)) throw std::invalid_argument(std::string("\"") + what + "\" is not finite");
    return v;
}

std::string oneLine(std::string text) {
    for (char& c : text)
        if (c == '\n' || c == '\r') c = ' ';
    return text;
}

}  // namespace kizamu::util
