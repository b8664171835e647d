// SPDX-License-Identifier: Apache-2.0
/// @file figures.cpp
/// @brief Table and JSON-lines printing.
#include "bench/figures.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <limits>

namespace kizamu::bench {

void FigureSink::add(const std::string& name, double value, const std::string& unit, const std::string& note) {
    mFigures.push_back({name, value, unit});
    if (mJson) {
        nlohmann::ordered_json j;  // keeps the documented key order
        j["figure"] = name;
        j["value"] = std::isfinite(value) ? nlohmann::ordered_json(value) : nlohmann::ordered_json(nullptr);
        j["unit"] = unit;
        std::fprintf(mOut, "%s\n", j.dump().c_str());
    } else {
        std::fprintf(mOut, "  %-44s %14.6g %-8s %s\n", name.c_str(), value, unit.c_str(), note.c_str());
    }
    std::fflush(mOut);
}

void FigureSink::section(const std::string& title) {
    if (!mJson) std::fprintf(mOut, "\n%s\n", title.c_str());
}

void FigureSink::progress(const std::string& line) {
    std::fprintf(stderr, "%s\n", line.c_str());
    std::fflush(stderr);
}

double FigureSink::value(const std::string& name) const {
    for (const auto& f : mFigures)
        if (f.name == name) return f.value;
    return std::numeric_limits<double>::quiet_NaN();
}

}  // namespace kizamu::bench
