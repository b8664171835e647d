// SPDX-License-Identifier: Apache-2.0
/// @file trajectory.cpp
/// @brief Trajectory reading and writing: nlohmann::json per record, samples written by hand.
///
/// Samples are most of a file (1-4 kHz), so they are written with std::to_chars (shortest
/// round-trip forms) rather than through a json value, and the fields that repeat the previous
/// sample's are left out. Tool changes and the start go through the stroke script's reader and
/// writer (sculpt/stroke_script.h).
#include "engine/trajectory.h"

#include "sculpt/stroke_script.h"
#include "util/atomic_file.h"
#include "util/file_error.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstring>
#include <functional>
#include <set>
#include <span>
#include <stdexcept>
#include <utility>

namespace kizamu::engine {

namespace {

using nlohmann::json;

constexpr int64_t kNsPerSecond = 1'000'000'000;

/// The keys a stroke script record may have that belong to a tool (not to its path).
constexpr std::array<const char*, 14> kToolKeys = {"op",     "shape",  "radius", "length", "strength", "amount",
                                                   "rate",   "color",  "mirror", "follow", "depth",    "height",
                                                   "masks",  "keep_out"};
/// Stroke script keys that a trajectory's samples replace.
constexpr std::array<const char*, 5> kPathKeys = {"path", "bezier", "orientation", "orientations", "dwell"};

template <std::size_t N>
bool isOneOf(const std::string& key, const std::array<const char*, N>& keys) {
    for (const char* k : keys)
        if (key == k) return true;
    return false;
}

double finiteNumber(const json& j, const char* what) {
    if (!j.is_number()) throw std::invalid_argument(std::string(what) + " must be a number");
    const double v = j.get<double>();
    if (!std::isfinite(v)) throw std::invalid_argument(std::string(what) + " is not finite");
    return v;
}

/// Seconds to ns. Below kTrajectoryMaxSeconds an ulp of `t` is under 0.25 ns, so the decimal
/// the writer prints (exact ns) comes back as the same integer.
int64_t nsOfSeconds(double t) {
    const double whole = std::floor(t);
    return int64_t(whole) * kNsPerSecond + std::llround((t - whole) * 1e9);
}

int64_t timeOf(const json& j, int64_t previousNs) {
    if (!j.contains("t")) throw std::invalid_argument("missing \"t\" (time, s)");
    const double t = finiteNumber(j.at("t"), "t");
    if (!(t >= 0.0 && t <= kTrajectoryMaxSeconds))
        throw std::invalid_argument("t = " + j.at("t").dump() + " is outside [0, 1e6] s");
    const int64_t ns = nsOfSeconds(t);
    if (ns < previousNs)
        throw std::invalid_argument("time goes backwards: t = " + j.at("t").dump() + " after " +
                                    std::to_string(double(previousNs) * 1e-9) + " s");
    return ns;
}

glm::dvec3 positionOf(const json& j) {
    if (!j.is_array() || j.size() != 3) throw std::invalid_argument("p must be [x, y, z]");
    return {finiteNumber(j[0], "p"), finiteNumber(j[1], "p"), finiteNumber(j[2], "p")};
}

glm::quat orientationOf(const json& j) {
    if (!j.is_array() || j.size() != 4) throw std::invalid_argument("q must be [w, x, y, z]");
    glm::dquat q(finiteNumber(j[0], "q"), finiteNumber(j[1], "q"), finiteNumber(j[2], "q"), finiteNumber(j[3], "q"));
    const double length = glm::length(q);
    if (!(length > 1e-9) || !std::isfinite(length)) throw std::invalid_argument("q must be a non-zero quaternion of finite length");
    // Kept as written when already unit (within float precision), so the text reads back to
    // the same bits.
    if (std::abs(length - 1.0) > 1e-6) q = q / length;
    return glm::quat(float(q.w), float(q.x), float(q.y), float(q.z));
}

float strengthOf(const json& j) {
    const double s = finiteNumber(j, "s");
    if (!(s >= 0.0 && s <= 1.0)) throw std::invalid_argument("s (strength) must be within [0, 1], got " + j.dump());
    return float(s);
}

uint32_t buttonsOf(const json& j) {
    if (!j.is_number_unsigned() || j.get<uint64_t>() > 0xFFFF'FFFFu)
        throw std::invalid_argument("b (buttons) must be an integer bitmask 0..4294967295, got " + j.dump());
    return uint32_t(j.get<uint64_t>());
}

TrajectoryCommand commandOf(const json& j) {
    const std::string c = j.is_string() ? j.get<std::string>() : j.dump();
    if (c == "undo") return TrajectoryCommand::Undo;
    if (c == "redo") return TrajectoryCommand::Redo;
    if (c == "cancel") return TrajectoryCommand::Cancel;
    throw std::invalid_argument("unknown command '" + c + "' (undo, redo, cancel)");
}

/// Reads the tool object with the stroke script's record reader (a one-point path added), so the
/// vocabulary, the defaults and the checks are the stroke script's.
ToolChange toolOf(const json& tool, int64_t timeNs, const std::function<void(const std::string&)>& unknown) {
    if (!tool.is_object()) throw std::invalid_argument("tool must be an object like a stroke script record without its path");
    json record = json::object();
    for (const auto& [key, value] : tool.items()) {
        if (isOneOf(key, kPathKeys))
            throw std::invalid_argument("tool: \"" + key + "\" belongs to a stroke script's path; a trajectory's samples are its path");
        if (isOneOf(key, kToolKeys))
            record[key] = value;
        else
            unknown("tool." + key);
    }
    record["path"] = json::array({json::array({0.0, 0.0, 0.0})});
    sculpt::Step step;
    try {
        step = sculpt::parseStep(record.dump());
    } catch (const json::exception& e) {
        throw std::invalid_argument(std::string("tool: ") + e.what());
    } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(std::string("tool: ") + e.what());
    }
    if (step.kind != sculpt::Step::Kind::Stroke) throw std::invalid_argument("tool: not a tool");
    return {timeNs, step.stroke.tool, step.stroke.mirror, std::move(step.stroke.constraints)};
}

/// The header: version, units, device, and the start (a stroke script header's domain and shape).
void parseHeader(const json& h, Trajectory& out, const std::function<void(const std::string&)>& unknown) {
    if (!h.is_object() || !h.contains("kizamu_trajectory"))
        throw std::invalid_argument("not a Kizamu trajectory (the first record must be the header {\"kizamu_trajectory\": 1, ...})");
    const json& v = h.at("kizamu_trajectory");
    if (!v.is_number_integer()) throw std::invalid_argument("kizamu_trajectory must be the format version, an integer");
    if (v != kTrajectoryVersion)
        throw std::invalid_argument("trajectory version " + v.dump() + " is not supported (this build reads " +
                                    std::to_string(kTrajectoryVersion) + ")");
    out.version = kTrajectoryVersion;
    if (h.contains("units") && h.at("units") != "m")
        throw std::invalid_argument("units " + h.at("units").dump() + " are not supported (version 1: \"m\")");
    if (h.contains("device")) {
        if (!h.at("device").is_string()) throw std::invalid_argument("device must be a string");
        out.device = h.at("device").get<std::string>();
    }
    if (h.contains("start") != h.contains("domain")) throw std::invalid_argument("start and domain come together (or neither)");
    if (h.contains("start")) {
        const json script = {{"kizamu", "stroke-script"}, {"version", sculpt::kScriptVersion}, {"domain", h.at("domain")}, {"start", h.at("start")}};
        try {
            const sculpt::Script s = sculpt::parseHeaderLine(script.dump());
            out.start = TrajectoryStart{s.domain, s.start};
        } catch (const json::exception& e) {
            throw std::invalid_argument(std::string("start: ") + e.what());
        }
    }
    for (const auto& [key, value] : h.items())
        if (key != "kizamu_trajectory" && key != "units" && key != "device" && key != "domain" && key != "start") unknown(key);
}

/// Shortest text that reads back as `v` (nlohmann reads numbers with strtod; "-0" would be the
/// integer 0, so negative zero is written "-0.0").
void appendDouble(std::string& out, double v) {
    if (!std::isfinite(v)) throw std::invalid_argument("a trajectory's numbers must be finite");
    if (v == 0.0 && std::signbit(v)) {
        out += "-0.0";
        return;
    }
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    out.append(buf, r.ptr);
}

/// A float as the shortest text whose double rounds back to it; the double's own shortest form
/// where rounding decimal -> double -> float would land on a neighbour.
void appendFloat(std::string& out, float f) {
    if (!std::isfinite(f)) throw std::invalid_argument("a trajectory's numbers must be finite");
    if (f == 0.0f && std::signbit(f)) {
        out += "-0.0";
        return;
    }
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, f);
    double back = 0.0;
    std::from_chars(buf, r.ptr, back);
    const float again = float(back);
    if (std::memcmp(&again, &f, sizeof f) == 0)
        out.append(buf, r.ptr);
    else
        appendDouble(out, double(f));
}

/// Exact decimal seconds: "12", "0.001", "1.000000001".
void appendTime(std::string& out, int64_t ns) {
    if (ns < 0 || double(ns) > kTrajectoryMaxSeconds * 1e9)
        throw std::invalid_argument("a trajectory's times must lie within [0, 1e6] s");
    out += std::to_string(ns / kNsPerSecond);
    int64_t frac = ns % kNsPerSecond;
    if (frac == 0) return;
    char digits[10] = "000000000";
    for (int k = 8; k >= 0; --k, frac /= 10) digits[k] = char('0' + frac % 10);
    int n = 9;
    while (digits[n - 1] == '0') --n;
    out += '.';
    out.append(digits, std::size_t(n));
}

bool sameBits(const glm::quat& a, const glm::quat& b) { return std::memcmp(&a, &b, sizeof a) == 0; }
bool sameBits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

void appendSample(std::string& out, const ToolSample& s, const ToolSample& previous) {
    out += "{\"t\":";
    appendTime(out, s.timeNs);
    out += ",\"p\":[";
    for (int k = 0; k < 3; ++k) {
        if (k) out += ',';
        appendDouble(out, s.posWorld[k]);
    }
    out += ']';
    if (!sameBits(s.orientation, previous.orientation)) {
        out += ",\"q\":[";
        const float wxyz[4] = {s.orientation.w, s.orientation.x, s.orientation.y, s.orientation.z};
        for (int k = 0; k < 4; ++k) {
            if (k) out += ',';
            appendFloat(out, wxyz[k]);
        }
        out += ']';
    }
    if (!sameBits(s.strength, previous.strength)) {
        if (!(s.strength >= 0.0f && s.strength <= 1.0f)) throw std::invalid_argument("a sample's strength must be within [0, 1]");
        out += ",\"s\":";
        appendFloat(out, s.strength);
    }
    if (s.buttons != previous.buttons) out += ",\"b\":" + std::to_string(s.buttons);
    out += "}\n";
}

/// The tool object: the stroke script's record for a one-point stroke, less its path.
json toolJson(const ToolChange& c) {
    sculpt::Stroke stroke;
    stroke.tool = c.tool;
    stroke.mirror = c.mirror;
    stroke.constraints = c.constraints;
    stroke.samples.push_back({});
    sculpt::validate(stroke);
    json j = json::parse(sculpt::strokeLine(stroke));
    for (const char* key : kPathKeys) j.erase(key);
    return j;
}

}  // namespace

void Trajectory::add(const ToolSample& s) {
    events.push_back({TrajectoryEvent::Kind::Sample, uint32_t(samples.size())});
    samples.push_back(s);
}

void Trajectory::add(const ToolChange& c) {
    events.push_back({TrajectoryEvent::Kind::ToolChange, uint32_t(toolChanges.size())});
    toolChanges.push_back(c);
}

void Trajectory::add(const CommandEvent& c) {
    events.push_back({TrajectoryEvent::Kind::Command, uint32_t(commands.size())});
    commands.push_back(c);
}

int64_t Trajectory::timeNs(const TrajectoryEvent& e) const {
    switch (e.kind) {
    case TrajectoryEvent::Kind::Sample: return samples[e.index].timeNs;
    case TrajectoryEvent::Kind::ToolChange: return toolChanges[e.index].timeNs;
    case TrajectoryEvent::Kind::Command: return commands[e.index].timeNs;
    }
    return 0;
}

const char* commandName(TrajectoryCommand c) {
    switch (c) {
    case TrajectoryCommand::Undo: return "undo";
    case TrajectoryCommand::Redo: return "redo";
    case TrajectoryCommand::Cancel: return "cancel";
    }
    return "?";
}

Trajectory parseTrajectory(std::string_view text, const std::string& name, std::vector<std::string>* warnings) {
    Trajectory out;
    bool header = false;
    bool anySample = false;
    ToolSample previous;  // what omitted fields repeat
    int64_t previousNs = 0;
    std::set<std::string> warned;
    int lineNo = 0;
    std::size_t at = 0;
    while (at < text.size()) {
        const std::size_t end = std::min(text.find('\n', at), text.size());
        const std::string_view line = text.substr(at, end - at);
        at = end + 1;
        ++lineNo;
        const auto first = line.find_first_not_of(" \t\r");
        if (first == std::string_view::npos || line[first] == '#') continue;
        const std::string where = "line " + std::to_string(lineNo) + ": ";
        auto unknown = [&](const std::string& key) {
            if (warnings && warned.insert(key).second)
                warnings->push_back(name + ": " + where + "unknown key '" + key + "' ignored");
        };
        try {
            const json j = json::parse(line);
            if (!header) {
                parseHeader(j, out, unknown);
                header = true;
                continue;
            }
            if (!j.is_object()) throw std::invalid_argument("a record must be a JSON object");
            const bool isTool = j.contains("tool");
            const bool isCommand = j.contains("cmd");
            const bool hasSampleKey = j.contains("p") || j.contains("q") || j.contains("s") || j.contains("b");
            if (int(isTool) + int(isCommand) + int(hasSampleKey) > 1)
                throw std::invalid_argument("a record is a sample (p, q, s, b), a tool change (tool) or a command (cmd), not several");
            const int64_t ns = timeOf(j, previousNs);
            if (isTool) {
                for (const auto& [key, value] : j.items())
                    if (key != "t" && key != "tool") unknown(key);
                out.add(toolOf(j.at("tool"), ns, unknown));
            } else if (isCommand) {
                for (const auto& [key, value] : j.items())
                    if (key != "t" && key != "cmd") unknown(key);
                out.add(CommandEvent{ns, commandOf(j.at("cmd"))});
            } else {
                ToolSample s = previous;
                s.timeNs = ns;
                if (j.contains("p"))
                    s.posWorld = positionOf(j.at("p"));
                else if (!anySample)
                    throw std::invalid_argument("the first sample needs a position \"p\"");
                if (j.contains("q")) s.orientation = orientationOf(j.at("q"));
                if (j.contains("s")) s.strength = strengthOf(j.at("s"));
                if (j.contains("b")) s.buttons = buttonsOf(j.at("b"));
                for (const auto& [key, value] : j.items())
                    if (key != "t" && key != "p" && key != "q" && key != "s" && key != "b") unknown(key);
                out.add(s);
                previous = s;
                anySample = true;
            }
            previousNs = ns;
        } catch (const json::exception& e) {
            throw FileError(name, where + e.what());
        } catch (const std::invalid_argument& e) {
            throw FileError(name, where + e.what());
        }
    }
    if (!header) throw FileError(name, "not a Kizamu trajectory (no header line)");
    return out;
}

Trajectory readTrajectory(const std::string& path, std::vector<std::string>* warnings) {
    return parseTrajectory(util::readWholeFile(path), path, warnings);
}

std::string formatTrajectory(const Trajectory& t) {
    std::string out = "{\"kizamu_trajectory\":" + std::to_string(kTrajectoryVersion) + ",\"units\":\"m\"";
    if (!t.device.empty()) out += ",\"device\":" + json(t.device).dump();
    if (t.start) {
        sculpt::Script script;
        script.domain = t.start->domain;
        script.start = t.start->shape;
        const json h = json::parse(sculpt::headerLine(script));
        out += ",\"domain\":" + h.at("domain").dump() + ",\"start\":" + h.at("start").dump();
    }
    out += "}\n";
    ToolSample previous;
    int64_t previousNs = 0;
    for (const TrajectoryEvent& e : t.events) {
        const int64_t ns = t.timeNs(e);
        if (ns < previousNs) throw std::invalid_argument("a trajectory's times must not decrease");
        previousNs = ns;
        switch (e.kind) {
        case TrajectoryEvent::Kind::Sample:
            appendSample(out, t.samples[e.index], previous);
            previous = t.samples[e.index];
            break;
        case TrajectoryEvent::Kind::ToolChange:
            out += "{\"t\":";
            appendTime(out, ns);
            out += ",\"tool\":" + toolJson(t.toolChanges[e.index]).dump() + "}\n";
            break;
        case TrajectoryEvent::Kind::Command:
            out += "{\"t\":";
            appendTime(out, ns);
            out += ",\"cmd\":\"" + std::string(commandName(t.commands[e.index].command)) + "\"}\n";
            break;
        }
    }
    return out;
}

void writeTrajectory(const Trajectory& t, const std::string& path) {
    const std::string text = formatTrajectory(t);
    util::writeFileAtomically(path, std::as_bytes(std::span<const char>(text.data(), text.size())));
}

}  // namespace kizamu::engine
