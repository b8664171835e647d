// SPDX-License-Identifier: Apache-2.0
/// @file hand_file.cpp
/// @brief Reading and writing hand files (docs/HAND.md) with nlohmann::json, a line at a time.
#include "sim/hand_file.h"

#include "util/file_error.h"
#include "util/json_lines.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string_view>

namespace kizamu::sim {

namespace {

using json = nlohmann::json;

using util::finiteNumber;

void readHeader(const json& j) {
    if (!j.is_object() || !j.contains("kizamu_hand"))
        throw std::invalid_argument("not a Kizamu hand file (the first record must be {\"kizamu_hand\": 1, ...})");
    const json& v = j["kizamu_hand"];
    if (!v.is_number_integer()) throw std::invalid_argument("\"kizamu_hand\" must be an integer version");
    if (v.get<int64_t>() != kHandVersion)
        throw std::invalid_argument("hand file version " + std::to_string(v.get<int64_t>()) + " is not supported (this build reads " +
                                    std::to_string(kHandVersion) + ")");
    if (j.contains("units") && !(j["units"].is_string() && j["units"].get<std::string>() == "m"))
        throw std::invalid_argument("\"units\" must be \"m\"");
}

HandWaypoint readWaypoint(const json& j, const Hand& hand) {
    if (!j.is_object()) throw std::invalid_argument("a waypoint must be an object {\"t\": s, \"p\": [x, y, z], \"b\": buttons}");
    HandWaypoint w;
    if (!j.contains("t")) throw std::invalid_argument("a waypoint needs \"t\" (s)");
    w.t = finiteNumber(j["t"], "t");
    if (w.t < 0.0) throw std::invalid_argument("\"t\" is negative");
    if (!hand.waypoints.empty() && w.t < hand.waypoints.back().t)
        throw std::invalid_argument("time goes backwards (" + std::to_string(w.t) + " s after " +
                                    std::to_string(hand.waypoints.back().t) + " s)");
    if (j.contains("p")) {
        const json& p = j["p"];
        if (!p.is_array() || p.size() != 3) throw std::invalid_argument("\"p\" must be [x, y, z] (m)");
        w.position = {finiteNumber(p[0], "p"), finiteNumber(p[1], "p"), finiteNumber(p[2], "p")};
    } else if (hand.waypoints.empty()) {
        throw std::invalid_argument("the first waypoint needs \"p\"");
    } else {
        w.position = hand.waypoints.back().position;  // omitted: repeats
    }
    if (j.contains("b")) {
        const json& b = j["b"];
        if (!b.is_number_integer() || b.get<int64_t>() < 0 || b.get<int64_t>() > int64_t(UINT32_MAX))
            throw std::invalid_argument("\"b\" must be an integer bitmask 0 to 2^32-1");
        w.buttons = uint32_t(b.get<int64_t>());
    } else if (!hand.waypoints.empty()) {
        w.buttons = hand.waypoints.back().buttons;
    }
    for (const auto& item : j.items())
        if (item.key() != "t" && item.key() != "p" && item.key() != "b")
            throw std::invalid_argument("unknown field \"" + item.key() + "\"");
    return w;
}

}  // namespace

Hand parseHand(const std::string& text, const std::string& name) {
    Hand hand;
    const bool header = util::forEachJsonRecord(
        text, name, [&](const json& j) { readHeader(j); }, [&](const json& j) { hand.waypoints.push_back(readWaypoint(j, hand)); });
    if (!header) throw FileError(name, "not a Kizamu hand file (no header line)");
    if (hand.waypoints.empty()) throw FileError(name, "no waypoints");
    return hand;
}

Hand readHand(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw FileError(path, "cannot open");
    std::ostringstream text;
    text << in.rdbuf();
    if (in.bad()) throw FileError(path, "read failed");
    return parseHand(text.str(), path);
}

namespace {
/// The shortest of %.15g, %.16g, %.17g that reads back to `v` exactly.
std::string number(double v) {
    char buf[32];
    for (int digits = 15; digits <= 17; ++digits) {
        std::snprintf(buf, sizeof buf, "%.*g", digits, v);
        if (std::strtod(buf, nullptr) == v) break;
    }
    return buf;
}
}  // namespace

std::string formatHand(const Hand& hand) {
    std::string out = "{\"kizamu_hand\": 1, \"units\": \"m\"}\n";
    for (const HandWaypoint& w : hand.waypoints) {
        out += "{\"t\": " + number(w.t) + ", \"p\": [" + number(w.position.x) + ", " + number(w.position.y) + ", " +
               number(w.position.z) + "], \"b\": " + std::to_string(w.buttons) + "}\n";
    }
    return out;
}

}  // namespace kizamu::sim
