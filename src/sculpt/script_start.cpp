// SPDX-License-Identifier: Apache-2.0
/// @file script_start.cpp
/// @brief makeSculptor and startAdf: a script's start shape generated at a level.
#include "sculpt/script_start.h"

#include "adf/generate.h"

#include <stdexcept>

namespace kizamu::sculpt {

std::unique_ptr<Sculptor> makeSculptor(const Script& script, int level, util::ThreadPool* pool, std::size_t historyBytes) {
    auto s = std::make_unique<Sculptor>(startAdf(script, level, pool), pool, historyBytes);
    s->setReference(script.start.source(s->current()->domain()));
    return s;
}

adf::AdfPtr startAdf(const Script& script, int level, util::ThreadPool* pool) {
    adf::Domain d = script.domain;
    if (level > 0) d.maxLevel = level;
    if (!d.valid()) throw std::invalid_argument("invalid domain or level for the script");
    return adf::generate(*script.start.source(d), d, adf::GenerationSettings{}, pool);
}

}  // namespace kizamu::sculpt
