// SPDX-License-Identifier: Apache-2.0
/// @file stroke_script.cpp
/// @brief Stroke script reading and writing (nlohmann::json per line).
#include "sculpt/stroke_script.h"

#include "util/atomic_file.h"
#include "util/file_error.h"
#include "util/json_lines.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace kizamu::sculpt {

namespace {

using nlohmann::json;

glm::dvec3 vec3Of(const json& j, const char* what) {
    if (!j.is_array() || j.size() != 3) throw std::invalid_argument(std::string(what) + " must be [x, y, z]");
    glm::dvec3 v(j[0].get<double>(), j[1].get<double>(), j[2].get<double>());
    if (!std::isfinite(v.x + v.y + v.z)) throw std::invalid_argument(std::string(what) + " is not finite");
    return v;
}

glm::dquat quatOf(const json& j) {
    if (!j.is_array() || j.size() != 4) throw std::invalid_argument("orientation must be [w, x, y, z]");
    const glm::dquat q(j[0].get<double>(), j[1].get<double>(), j[2].get<double>(), j[3].get<double>());
    if (!std::isfinite(q.w + q.x + q.y + q.z) || glm::length(q) < 1e-9)
        throw std::invalid_argument("orientation is not a finite, non-zero quaternion");
    // Kept as written when already unit, so a script reads back to the same text.
    return std::abs(glm::length(q) - 1.0) > 1e-9 ? glm::normalize(q) : q;
}

/// "color": [r, g, b], integers 0-255 (sRGB).
glm::u8vec3 colourOf(const json& j) {
    const char* expect = "color must be [r, g, b] with integers 0-255";
    if (!j.is_array() || j.size() != 3) throw std::invalid_argument(expect);
    glm::u8vec3 c(0, 0, 0);
    for (int k = 0; k < 3; ++k) {
        if (!j[std::size_t(k)].is_number_integer()) throw std::invalid_argument(expect);
        const auto v = j[std::size_t(k)].get<int64_t>();
        if (v < 0 || v > 255) throw std::invalid_argument(std::string(expect) + " (got " + std::to_string(v) + ")");
        c[k] = uint8_t(v);
    }
    return c;
}

json vecJson(const glm::dvec3& v) { return json::array({v.x, v.y, v.z}); }
json quatJson(const glm::dquat& q) { return json::array({q.w, q.x, q.y, q.z}); }

double number(const json& j, const char* key, double fallback) {
    if (!j.contains(key)) return fallback;
    return j.at(key).get<double>();
}

/// A shape; `fileAllowed`: a header's start, which may also be {"shape": "file", "file": ...}.
Shape shapeOf(const json& st, bool fileAllowed = false) {
    Shape s;
    const std::string shape = st.at("shape").get<std::string>();
    if (shape == "box") {
        s.kind = Shape::Kind::Box;
        s.halfSize = vec3Of(st.at("half"), "box half");
        s.rounding = number(st, "rounding", 0.0);
    } else if (shape == "sphere") {
        s.kind = Shape::Kind::Sphere;
        s.radius = st.at("radius").get<double>();
    } else if (shape == "test-part") {
        s.kind = Shape::Kind::TestPart;
    } else if (shape == "file") {
        if (!fileAllowed)
            throw std::invalid_argument("a \"file\" shape is a start only (a script header's start); masks and keep-out "
                                        "regions are box, sphere or test-part");
        s.kind = Shape::Kind::File;
        s.file = st.at("file").get<std::string>();
        if (s.file.empty()) throw std::invalid_argument("a file start needs a \"file\" (a .kza path)");
    } else {
        throw std::invalid_argument("unknown shape '" + shape + "' (box, sphere, test-part" + (fileAllowed ? ", file)" : ")"));
    }
    if (st.contains("centre")) s.centre = vec3Of(st.at("centre"), "shape centre");
    s.validate();
    return s;
}

json shapeJson(const Shape& s) {
    switch (s.kind) {
    case Shape::Kind::Box: {
        json j = {{"shape", "box"}, {"centre", vecJson(s.centre)}, {"half", vecJson(s.halfSize)}};
        if (s.rounding > 0.0) j["rounding"] = s.rounding;
        return j;
    }
    case Shape::Kind::Sphere: return {{"shape", "sphere"}, {"centre", vecJson(s.centre)}, {"radius", s.radius}};
    case Shape::Kind::TestPart: return {{"shape", "test-part"}};
    case Shape::Kind::File: return {{"shape", "file"}, {"file", s.file}};
    }
    return {};
}

std::vector<Shape> shapesOf(const json& j, const char* what) {
    if (!j.is_array()) throw std::invalid_argument(std::string(what) + " must be a list of shapes");
    std::vector<Shape> out;
    for (const json& e : j) out.push_back(shapeOf(e));
    return out;
}

void parseConstraints(const json& j, Stroke& s) {
    StrokeConstraints& c = s.constraints;
    if (j.contains("follow")) c.followOffset = j.at("follow").at("offset").get<double>();
    if (j.contains("depth")) c.depthLimit = j.at("depth").get<double>();
    if (j.contains("height")) c.heightLimit = j.at("height").get<double>();
    if (j.contains("masks")) c.masks = shapesOf(j.at("masks"), "masks");
    if (j.contains("keep_out")) c.keepOut = shapesOf(j.at("keep_out"), "keep_out");
}

/// A whole number that fits an int: nlohmann's get<int> converts a float out of range with
/// undefined behaviour (the trajectory fuzzer found a header with "tile_span": 6e42).
int wholeNumber(const json& j, const std::string& what) {
    const bool fits = (j.is_number_unsigned() && j.get<uint64_t>() <= uint64_t(std::numeric_limits<int>::max())) ||
                      (j.is_number_integer() && !j.is_number_unsigned() &&
                       j.get<int64_t>() >= std::numeric_limits<int>::min() &&
                       j.get<int64_t>() <= std::numeric_limits<int>::max());
    if (!fits) throw std::invalid_argument(what + " must be a whole number");
    return int(j.get<int64_t>());
}

int wholeNumber(const json& object, const char* key, int fallback) {
    return object.contains(key) ? wholeNumber(object.at(key), key) : fallback;
}

void parseHeader(const json& h, Script& s) {
    if (h.value("kizamu", "") != "stroke-script") throw std::invalid_argument("not a Kizamu stroke script (no header)");
    s.version = wholeNumber(h.at("version"), "version");
    if (s.version < 1 || s.version > kScriptVersion)
        throw std::invalid_argument("stroke script version " + std::to_string(s.version) + " is not supported (this build reads " +
                                    std::to_string(kScriptVersion) + ")");
    const json& d = h.at("domain");
    s.domain.originWorld = d.contains("origin") ? vec3Of(d.at("origin"), "domain origin") : glm::dvec3(0.0);
    s.domain.sizeWorld = d.at("size").get<double>();
    s.domain.maxLevel = wholeNumber(d, "level", 10);
    s.domain.tileSpanLevels = wholeNumber(d, "tile_span", adf::Domain{}.tileSpanLevels);
    if (!s.domain.valid()) throw std::invalid_argument("invalid domain (size > 0, level 1..16)");
    s.start = shapeOf(h.at("start"), true);
    if (s.start.kind == Shape::Kind::File && s.version < 3)
        throw std::invalid_argument("a start from a file needs version 3 (this script is version " + std::to_string(s.version) + ")");
}

/// "live": {"cuts": [...], "dwells": [...], "t": [...], "s": [...]} (version 3). Strengths are
/// floats written as the doubles they equal, so the cast back is exact.
LiveRecord liveOf(const json& j) {
    if (!j.is_object()) throw std::invalid_argument("live must be an object {\"cuts\", \"dwells\", \"t\", \"s\"}");
    auto list = [&](const char* key, bool required) -> const json* {
        if (!j.contains(key)) {
            if (required) throw std::invalid_argument(std::string("live needs \"") + key + "\"");
            return nullptr;
        }
        const json& a = j.at(key);
        if (!a.is_array()) throw std::invalid_argument(std::string("live.") + key + " must be a list");
        return &a;
    };
    LiveRecord r;
    for (const json& c : *list("cuts", true)) {
        if (!c.is_number_unsigned() || c.get<uint64_t>() > std::numeric_limits<uint32_t>::max())
            throw std::invalid_argument("live.cuts must be sample counts (whole numbers >= 0)");
        r.cuts.push_back(uint32_t(c.get<uint64_t>()));
    }
    for (const json& d : *list("dwells", true)) r.dwells.push_back(d.get<double>());
    if (const json* t = list("t", false))
        for (const json& v : *t) {
            if (!v.is_number_integer() || (v.is_number_unsigned() && v.get<uint64_t>() > uint64_t(std::numeric_limits<int64_t>::max())))
                throw std::invalid_argument("live.t must be time stamps in whole nanoseconds");
            r.timesNs.push_back(v.get<int64_t>());
        }
    if (const json* st = list("s", false))
        for (const json& v : *st) {
            const double x = v.get<double>();
            if (!(x >= 0.0 && x <= 1.0)) throw std::invalid_argument("live.s must be strengths in [0, 1]");
            r.strengths.push_back(float(x));
        }
    return r;
}

Stroke parseStroke(const json& j, int version) {
    Stroke s;
    s.tool.op = parseOp(j.at("op").get<std::string>());
    s.tool.shape = parseShape(j.at("shape").get<std::string>());
    s.tool.radius = j.at("radius").get<double>();
    s.tool.halfLength = 0.5 * number(j, "length", 2.0 * s.tool.radius);
    s.tool.strength = number(j, "strength", 1.0);
    s.tool.amount = number(j, "amount", 0.0);
    s.tool.rate = number(j, "rate", 0.0);
    s.dwell = number(j, "dwell", 0.0);
    if (!(s.dwell >= 0.0) || !std::isfinite(s.dwell)) throw std::invalid_argument("dwell must be a non-negative time in seconds");
    if (s.tool.op == ToolOp::Paint) {
        if (!j.contains("color")) throw std::invalid_argument("paint needs a \"color\": [r, g, b] with integers 0-255");
        s.tool.colour = colourOf(j.at("color"));
    }
    s.tool.validate();
    s.bezier = j.contains("bezier");
    if (s.bezier && j.contains("path")) throw std::invalid_argument("a stroke has a path or a bezier curve, not both");
    const json& path = j.at(s.bezier ? "bezier" : "path");
    if (s.bezier && (!path.is_array() || path.size() != 4))
        throw std::invalid_argument("bezier must be four control points [p0, p1, p2, p3]");
    if (!path.is_array() || path.empty()) throw std::invalid_argument("path must be a non-empty list of points");
    glm::dquat fixed(1.0, 0.0, 0.0, 0.0);
    if (j.contains("orientation")) fixed = quatOf(j.at("orientation"));
    const json* each = j.contains("orientations") ? &j.at("orientations") : nullptr;
    if (each && (!each->is_array() || each->size() != path.size()))
        throw std::invalid_argument("orientations must have one entry per path or control point");
    for (std::size_t i = 0; i < path.size(); ++i)
        s.samples.push_back({vec3Of(path[i], "path point"), each ? quatOf((*each)[i]) : fixed});
    if (j.contains("mirror")) {
        for (char c : j.at("mirror").get<std::string>()) {
            if (c < 'x' || c > 'z') throw std::invalid_argument("mirror takes the axes x, y and/or z, like \"xz\"");
            s.mirror = uint8_t(s.mirror | (1u << (c - 'x')));
        }
    }
    parseConstraints(j, s);
    if (j.contains("live")) {
        if (version < 3)
            throw std::invalid_argument("live strokes need version 3 (this script is version " + std::to_string(version) + ")");
        s.live = liveOf(j.at("live"));
    }
    validate(s);
    return s;
}

Step stepOf(const json& j, int version) {
    if (j.contains("undo")) return Step::undo();
    if (j.contains("redo")) return Step::redo();
    if (j.contains("correct")) {
        const json& c = j.at("correct");
        if (c.is_string() && c.get<std::string>() == "all") return Step::correct();
        if (c.is_number_unsigned() && c.get<std::size_t>() > 0) return Step::correct(c.get<std::size_t>());
        throw std::invalid_argument("correct takes \"all\" or a positive number of zones");
    }
    return {Step::Kind::Stroke, parseStroke(j, version), 0};
}

}  // namespace

Step parseStep(const std::string& line, int version) { return stepOf(json::parse(line), version); }

Script parseHeaderLine(const std::string& line) {
    Script s;
    parseHeader(json::parse(line), s);
    return s;
}

Script parseScript(const std::string& text, const std::string& name) {
    Script s;
    const bool header = util::forEachJsonRecord(
        text, name, [&](const json& j) { parseHeader(j, s); }, [&](const json& j) { s.steps.push_back(stepOf(j, s.version)); });
    if (!header) throw FileError(name, "not a Kizamu stroke script (no header line)");
    return s;
}

Script readScript(const std::string& path) {
    Script s = parseScript(util::readWholeFile(path), path);
    s.baseDir = std::filesystem::path(path).parent_path().string();
    return s;
}

std::string headerLine(const Script& s) {
    const json start = shapeJson(s.start);
    const json h = {{"kizamu", "stroke-script"},
                    {"version", s.version},
                    {"domain",
                     {{"origin", vecJson(s.domain.originWorld)},
                      {"size", s.domain.sizeWorld},
                      {"level", s.domain.maxLevel},
                      {"tile_span", s.domain.tileSpanLevels}}},
                    {"start", start}};
    return h.dump();
}

std::string strokeLine(const Stroke& s) {
    json j = {{"op", opName(s.tool.op)}, {"shape", shapeName(s.tool.shape)}, {"radius", s.tool.radius}};
    if (s.tool.shape == ToolShape::Cylinder) j["length"] = 2.0 * s.tool.halfLength;
    if (s.tool.strength != 1.0) j["strength"] = s.tool.strength;
    if (s.tool.op == ToolOp::Build) j["amount"] = s.tool.amount;
    if (s.tool.op == ToolOp::Paint) j["color"] = json::array({s.tool.colour.r, s.tool.colour.g, s.tool.colour.b});
    if (s.tool.op == ToolOp::HeatGun) j["rate"] = s.tool.rate;
    // A live stroke's dwell is the sum of its segments' (validate()), whatever the tool.
    if (s.tool.op == ToolOp::HeatGun || (s.live && s.dwell != 0.0)) j["dwell"] = s.dwell;
    json path = json::array();
    bool sameOrientation = true;
    for (const ToolSample& t : s.samples) {
        path.push_back(vecJson(t.position));
        sameOrientation = sameOrientation && t.orientation == s.samples.front().orientation;
    }
    j[s.bezier ? "bezier" : "path"] = path;
    if (s.mirror) {
        std::string axes;
        for (int k = 0; k < 3; ++k)
            if ((s.mirror >> k) & 1) axes += char('x' + k);
        j["mirror"] = axes;
    }
    if (sameOrientation) {
        if (s.samples.front().orientation != glm::dquat(1.0, 0.0, 0.0, 0.0)) j["orientation"] = quatJson(s.samples.front().orientation);
    } else {
        json o = json::array();
        for (const ToolSample& t : s.samples) o.push_back(quatJson(t.orientation));
        j["orientations"] = o;
    }
    const StrokeConstraints& c = s.constraints;
    if (c.followOffset) j["follow"] = {{"offset", *c.followOffset}};
    if (c.depthLimit) j["depth"] = *c.depthLimit;
    if (c.heightLimit) j["height"] = *c.heightLimit;
    auto shapes = [](const std::vector<Shape>& v) {
        json a = json::array();
        for (const Shape& sh : v) a.push_back(shapeJson(sh));
        return a;
    };
    if (!c.masks.empty()) j["masks"] = shapes(c.masks);
    if (!c.keepOut.empty()) j["keep_out"] = shapes(c.keepOut);
    if (s.live) {
        const LiveRecord& r = *s.live;
        json live = {{"cuts", r.cuts}, {"dwells", r.dwells}};
        if (!r.timesNs.empty()) live["t"] = r.timesNs;
        if (!r.strengths.empty()) {
            json a = json::array();
            for (float v : r.strengths) a.push_back(double(v));
            live["s"] = a;
        }
        j["live"] = live;
    }
    return j.dump();
}

std::string stepLine(const Step& step) {
    switch (step.kind) {
    case Step::Kind::Undo: return R"({"undo": 1})";
    case Step::Kind::Redo: return R"({"redo": 1})";
    case Step::Kind::Correct: return step.zones == 0 ? R"({"correct": "all"})" : R"({"correct": )" + std::to_string(step.zones) + "}";
    case Step::Kind::Stroke: break;
    }
    return strokeLine(step.stroke);
}

std::string formatScript(const Script& s) {
    std::string out = headerLine(s) + "\n";
    for (const Step& st : s.steps) out += stepLine(st) + "\n";
    return out;
}

}  // namespace kizamu::sculpt
