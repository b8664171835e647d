// SPDX-License-Identifier: Apache-2.0
/// @file fuzz_trajectory.cpp
/// @brief libFuzzer harness for the trajectory reader (src/engine/trajectory.h). Any text is
/// either a one-line FileError naming its file or a trajectory that keeps the reader's promises
/// (times in order and range, finite positions, unit orientations, strengths in [0, 1], events
/// indexing their lists), whose written form reads back to the same samples bit for bit and
/// writes the same text again, with one-line warnings.
#include "engine/trajectory.h"
#include "util/file_error.h"

#include <glm/gtc/quaternion.hpp>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

namespace {

using kizamu::engine::Trajectory;
using kizamu::engine::TrajectoryEvent;

void check(bool ok) {
    if (!ok) std::abort();
}

void checkPromises(const Trajectory& t) {
    int64_t previous = 0;
    std::size_t counts[3] = {0, 0, 0};
    for (const TrajectoryEvent& e : t.events) {
        const std::size_t kind = std::size_t(e.kind);
        check(kind < 3 && e.index == counts[kind]);
        ++counts[kind];
        const int64_t ns = t.timeNs(e);
        check(ns >= previous && double(ns) <= kizamu::engine::kTrajectoryMaxSeconds * 1e9);
        previous = ns;
    }
    check(counts[0] == t.samples.size() && counts[1] == t.toolChanges.size() && counts[2] == t.commands.size());
    for (const auto& s : t.samples) {
        check(std::isfinite(s.posWorld.x) && std::isfinite(s.posWorld.y) && std::isfinite(s.posWorld.z));
        check(std::abs(glm::length(glm::dquat(s.orientation)) - 1.0) < 1e-5);
        check(s.strength >= 0.0f && s.strength <= 1.0f);
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    std::vector<std::string> warnings;
    Trajectory t;
    try {
        t = kizamu::engine::parseTrajectory(text, "fuzz", &warnings);
    } catch (const kizamu::FileError& e) {
        const std::string_view m = e.what();
        check(m.find('\n') == std::string_view::npos && m.rfind("fuzz: ", 0) == 0);
        return 0;
    }
    for (const std::string& w : warnings) check(w.find('\n') == std::string::npos && w.rfind("fuzz: line ", 0) == 0);
    checkPromises(t);
    const std::string written = kizamu::engine::formatTrajectory(t);
    warnings.clear();
    const Trajectory back = kizamu::engine::parseTrajectory(written, "again", &warnings);
    check(warnings.empty());
    check(back.events.size() == t.events.size() && back.samples.size() == t.samples.size());
    for (std::size_t i = 0; i < t.events.size(); ++i)
        check(back.events[i].kind == t.events[i].kind && back.timeNs(back.events[i]) == t.timeNs(t.events[i]));
    if (!t.samples.empty())
        check(std::memcmp(back.samples.data(), t.samples.data(), t.samples.size() * sizeof(t.samples[0])) == 0);
    check(kizamu::engine::formatTrajectory(back) == written);
    return 0;
}
