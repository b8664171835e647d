// SPDX-License-Identifier: Apache-2.0
/// @file script_start.cpp
/// @brief makeSculptor and startAdf: a script's start shape generated at a level, or its start
/// file loaded.
#include "sculpt/script_start.h"

#include "adf/adf_file.h"
#include "adf/adf_source.h"
#include "adf/generate.h"

#include <cstdio>
#include <filesystem>
#include <stdexcept>

namespace kizamu::sculpt {

namespace {

std::string describe(const adf::Domain& d) {
    char text[200];
    std::snprintf(text, sizeof text, "origin [%.17g, %.17g, %.17g], size %.17g, level %d, tile span %d", d.originWorld.x,
                  d.originWorld.y, d.originWorld.z, d.sizeWorld, d.maxLevel, d.tileSpanLevels);
    return text;
}

}  // namespace

std::unique_ptr<Sculptor> makeSculptor(const Script& script, int level, util::ThreadPool* pool, std::size_t historyBytes) {
    adf::AdfPtr start = startAdf(script, level, pool);
    // A file start is its own reference: the clay just loaded, not a second read.
    adf::SourcePtr reference = script.start.kind == Shape::Kind::File ? adf::makeAdfSource(start)
                                                                        : script.start.source(start->domain());
    auto s = std::make_unique<Sculptor>(std::move(start), pool, historyBytes);
    s->setReference(std::move(reference));
    return s;
}

std::string startFilePath(const Script& script) {
    const std::filesystem::path file(script.start.file);
    if (file.is_absolute() || script.baseDir.empty()) return file.string();
    return (std::filesystem::path(script.baseDir) / file).string();
}

adf::AdfPtr startAdf(const Script& script, int level, util::ThreadPool* pool) {
    if (script.start.kind == Shape::Kind::File) {
        adf::AdfPtr clay = script.start.clay ? script.start.clay : adf::loadAdf(startFilePath(script));
        const adf::Domain& d = clay->domain();
        if (level > 0 && level != d.maxLevel)
            throw std::invalid_argument("a start from a file keeps its level " + std::to_string(d.maxLevel) + " (asked for " +
                                        std::to_string(level) + ")");
        if (!(d == script.domain))
            throw std::invalid_argument("the start file '" + script.start.file + "' has the domain " + describe(d) +
                                        ", the script's header " + describe(script.domain));
        return clay;
    }
    adf::Domain d = script.domain;
    if (level > 0) d.maxLevel = level;
    if (!d.valid()) throw std::invalid_argument("invalid domain or level for the script");
    return adf::generate(*script.start.source(d), d, adf::GenerationSettings{}, pool);
}

}  // namespace kizamu::sculpt
