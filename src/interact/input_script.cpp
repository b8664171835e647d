// SPDX-License-Identifier: Apache-2.0
/// @file input_script.cpp
/// @brief Reading and writing input scripts (docs/INPUT.md) with nlohmann::json, a line at a time.
#include "interact/input_script.h"

#include "util/file_error.h"
#include "util/json_lines.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace kizamu::interact {

namespace {

using json = nlohmann::json;

using util::finiteNumber;

const char* buttonName(MouseButton b) {
    switch (b) {
    case MouseButton::Left: return "left";
    case MouseButton::Right: return "right";
    case MouseButton::Middle: return "middle";
    }
    return "left";
}

MouseButton parseButton(const json& j) {
    if (j.is_string()) {
        const std::string s = j.get<std::string>();
        if (s == "left") return MouseButton::Left;
        if (s == "right") return MouseButton::Right;
        if (s == "middle") return MouseButton::Middle;
    }
    throw std::invalid_argument("a button is \"left\", \"right\" or \"middle\"");
}

bool validKey(const std::string& k) {
    if (k.size() == 1) return (k[0] >= 'a' && k[0] <= 'z') || (k[0] >= '0' && k[0] <= '9');
    const auto& names = keyNames();
    return std::find(names.begin(), names.end(), k) != names.end();
}

uint32_t parseMods(const json& j) {
    if (!j.is_array()) throw std::invalid_argument("\"mods\" must be a list of \"ctrl\", \"shift\", \"alt\"");
    uint32_t mods = 0;
    for (const json& m : j) {
        const std::string s = m.is_string() ? m.get<std::string>() : std::string();
        if (s == "ctrl") mods |= kModCtrl;
        else if (s == "shift") mods |= kModShift;
        else if (s == "alt") mods |= kModAlt;
        else throw std::invalid_argument("unknown modifier " + m.dump() + " (ctrl, shift, alt)");
    }
    return mods;
}

json modsJson(uint32_t mods) {
    json a = json::array();
    if (mods & kModCtrl) a.push_back("ctrl");
    if (mods & kModShift) a.push_back("shift");
    if (mods & kModAlt) a.push_back("alt");
    return a;
}

void readHeader(const json& j, InputScript& s) {
    if (!j.is_object() || !j.contains("kizamu_input"))
        throw std::invalid_argument("not a Kizamu input script (the first record must be {\"kizamu_input\": 1, ...})");
    const json& v = j["kizamu_input"];
    if (!v.is_number_integer() || v.get<int64_t>() != kInputScriptVersion)
        throw std::invalid_argument("input script version " + v.dump() + " is not supported (this build reads " +
                                    std::to_string(kInputScriptVersion) + ")");
    if (j.contains("size")) {
        const json& size = j["size"];
        if (!size.is_array() || size.size() != 2 || !size[0].is_number_integer() || !size[1].is_number_integer())
            throw std::invalid_argument("\"size\" must be [width, height] in pixels");
        s.width = size[0].get<int>();
        s.height = size[1].get<int>();
        if (s.width < 16 || s.height < 16 || s.width > 16384 || s.height > 16384)
            throw std::invalid_argument("\"size\" must be 16 to 16384 pixels each way");
    }
}

std::vector<double> finiteArray(const json& j, const char* what, std::size_t n) {
    if (!j.is_array() || j.size() != n)
        throw std::invalid_argument(std::string("\"") + what + "\" must be a list of " + std::to_string(n) + " numbers");
    std::vector<double> v;
    for (const json& x : j) v.push_back(finiteNumber(x, what));
    return v;
}

float unitNumber(const json& j, const char* what, double lo) {
    const double v = finiteNumber(j, what);
    if (v < lo || v > 1.0) throw std::invalid_argument(std::string("\"") + what + "\" must be in [" + (lo < 0 ? "-1" : "0") + ", 1]");
    return float(v);
}

bool boolean(const json& j, const char* what) {
    if (!j.is_boolean()) throw std::invalid_argument(std::string("\"") + what + "\" must be true or false");
    return j.get<bool>();
}

/// {"frame": F, "controller": "left"|"right", "position": [x, y, z], "orientation": [x, y, z, w],
///  "trigger": v, "squeeze": v, "thumbstick": [x, y], "primary": b, "secondary": b, "active": b}
void readController(const json& j, InputEvent& e) {
    e.kind = InputEventKind::Controller;
    ControllerInput& c = e.controller;
    const json& hand = j["controller"];
    if (hand == "left") c.hand = 0;
    else if (hand == "right") c.hand = 1;
    else throw std::invalid_argument("\"controller\" is \"left\" or \"right\"");
    for (const auto& [key, value] : j.items()) {
        if (key == "frame" || key == "controller") continue;
        if (key == "position") {
            const auto v = finiteArray(value, "position", 3);
            c.position = glm::dvec3(v[0], v[1], v[2]);
        } else if (key == "orientation") {
            const auto v = finiteArray(value, "orientation", 4);
            const glm::dquat q(v[3], v[0], v[1], v[2]);
            if (std::abs(glm::length(q) - 1.0) > 1e-3) throw std::invalid_argument("\"orientation\" must be a unit quaternion [x, y, z, w]");
            c.orientation = glm::normalize(q);
        } else if (key == "trigger") {
            c.trigger = unitNumber(value, "trigger", 0.0);
        } else if (key == "squeeze") {
            c.squeeze = unitNumber(value, "squeeze", 0.0);
        } else if (key == "thumbstick") {
            if (!value.is_array() || value.size() != 2) throw std::invalid_argument("\"thumbstick\" must be [x, y], each in [-1, 1]");
            c.thumbstick = glm::vec2(unitNumber(value[0], "thumbstick", -1.0), unitNumber(value[1], "thumbstick", -1.0));
        } else if (key == "primary") {
            c.primary = boolean(value, "primary");
        } else if (key == "secondary") {
            c.secondary = boolean(value, "secondary");
        } else if (key == "active") {
            c.active = boolean(value, "active");
        } else {
            throw std::invalid_argument("unknown key \"" + key + "\" in a controller event");
        }
    }
}

json controllerJson(const ControllerInput& c) {
    json j;
    j["controller"] = c.hand == 0 ? "left" : "right";
    if (c.position) j["position"] = {c.position->x, c.position->y, c.position->z};
    if (c.orientation) j["orientation"] = {c.orientation->x, c.orientation->y, c.orientation->z, c.orientation->w};
    if (c.trigger) j["trigger"] = double(*c.trigger);
    if (c.squeeze) j["squeeze"] = double(*c.squeeze);
    if (c.thumbstick) j["thumbstick"] = {double(c.thumbstick->x), double(c.thumbstick->y)};
    if (c.primary) j["primary"] = *c.primary;
    if (c.secondary) j["secondary"] = *c.secondary;
    if (c.active) j["active"] = *c.active;
    return j;
}

InputEvent readEvent(const json& j, const InputScript& s) {
    if (!j.is_object()) throw std::invalid_argument("an event must be an object");
    InputEvent e;
    if (!j.contains("frame") || !j["frame"].is_number_integer()) throw std::invalid_argument("an event needs an integer \"frame\"");
    e.frame = j["frame"].get<int64_t>();
    if (e.frame < 0) throw std::invalid_argument("\"frame\" is negative");
    if (!s.events.empty() && e.frame < s.events.back().frame)
        throw std::invalid_argument("frame " + std::to_string(e.frame) + " comes after frame " + std::to_string(s.events.back().frame));
    if (j.contains("controller")) {
        readController(j, e);
        return e;
    }
    int kinds = 0;
    for (const char* k : {"move", "press", "release", "wheel", "key", "drop", "text"}) kinds += j.contains(k) ? 1 : 0;
    if (kinds != 1)
        throw std::invalid_argument(
            "an event is exactly one of \"move\", \"press\", \"release\", \"wheel\", \"key\", \"drop\", \"text\", \"controller\"");
    for (const auto& [key, value] : j.items())
        if (key != "frame" && key != "move" && key != "press" && key != "release" && key != "wheel" && key != "key" &&
            key != "drop" && key != "text" && key != "mods" && key != "pressure")
            throw std::invalid_argument("unknown key \"" + key + "\"");
    if (j.contains("mods")) {
        if (j.contains("move") || j.contains("drop") || j.contains("text"))
            throw std::invalid_argument("\"mods\" belong to a press, release, key or wheel");
        e.mods = parseMods(j["mods"]);
    }
    if (j.contains("move")) {
        const json& p = j["move"];
        if (!p.is_array() || p.size() != 2) throw std::invalid_argument("\"move\" must be [x, y] in pixels");
        e.kind = InputEventKind::Move;
        e.x = finiteNumber(p[0], "move");
        e.y = finiteNumber(p[1], "move");
        if (j.contains("pressure")) {
            const double pr = finiteNumber(j["pressure"], "pressure");
            if (pr < 0.0 || pr > 1.0) throw std::invalid_argument("\"pressure\" must be in [0, 1]");
            e.pressure = float(pr);
        }
    } else if (j.contains("pressure")) {
        throw std::invalid_argument("\"pressure\" belongs to a move");
    } else if (j.contains("press")) {
        e.kind = InputEventKind::Press;
        e.button = parseButton(j["press"]);
    } else if (j.contains("release")) {
        e.kind = InputEventKind::Release;
        e.button = parseButton(j["release"]);
    } else if (j.contains("wheel")) {
        e.kind = InputEventKind::Wheel;
        e.wheel = finiteNumber(j["wheel"], "wheel");
    } else if (j.contains("key")) {
        e.kind = InputEventKind::Key;
        if (!j["key"].is_string() || !validKey(j["key"].get<std::string>()))
            throw std::invalid_argument("unknown key " + j["key"].dump() + " (a-z, 0-9 or a name in docs/INPUT.md)");
        e.key = j["key"].get<std::string>();
    } else if (j.contains("text")) {
        e.kind = InputEventKind::Text;
        if (!j["text"].is_string() || j["text"].get<std::string>().empty()) throw std::invalid_argument("\"text\" must be a non-empty string");
        e.text = j["text"].get<std::string>();
    } else {
        e.kind = InputEventKind::Drop;
        if (!j["drop"].is_string() || j["drop"].get<std::string>().empty())
            throw std::invalid_argument("\"drop\" must be a file path");
        e.path = j["drop"].get<std::string>();
    }
    return e;
}

}  // namespace

const std::vector<std::string>& keyNames() {
    static const std::vector<std::string> names = {"escape", "enter", "space", "tab", "backspace", "delete", "left", "right",
                                                   "up", "down", "home", "end", "pageup", "pagedown", "f1", "f2", "f3", "f4",
                                                   "f5", "f6", "f7", "f8", "f9", "f10", "f11", "f12", "kp0", "kp1", "kp2",
                                                   "kp3", "kp4", "kp5", "kp6", "kp7", "kp8", "kp9", "kpdecimal", "[", "]",
                                                   "minus", "equal"};
    return names;
}

InputScript parseInputScript(const std::string& text, const std::string& name) {
    InputScript s;
    const bool header = util::forEachJsonRecord(
        text, name, [&](const json& j) { readHeader(j, s); }, [&](const json& j) { s.events.push_back(readEvent(j, s)); });
    if (!header) throw FileError(name, "not a Kizamu input script (empty)");
    return s;
}

InputScript readInputScript(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    if (!f) throw FileError(path, "cannot be read");
    std::ostringstream text;
    text << f.rdbuf();
    InputScript s = parseInputScript(text.str(), path);
    s.baseDir = std::filesystem::path(path).parent_path().string();
    return s;
}

std::string formatInputScript(const InputScript& s) {
    std::string out = json{{"kizamu_input", kInputScriptVersion}, {"size", {s.width, s.height}}}.dump() + "\n";
    for (const InputEvent& e : s.events) {
        json j;
        j["frame"] = e.frame;
        switch (e.kind) {
        case InputEventKind::Move:
            j["move"] = {e.x, e.y};
            if (e.pressure != 1.0f) j["pressure"] = double(e.pressure);
            break;
        case InputEventKind::Press: j["press"] = buttonName(e.button); break;
        case InputEventKind::Release: j["release"] = buttonName(e.button); break;
        case InputEventKind::Wheel: j["wheel"] = e.wheel; break;
        case InputEventKind::Key: j["key"] = e.key; break;
        case InputEventKind::Drop: j["drop"] = e.path; break;
        case InputEventKind::Text: j["text"] = e.text; break;
        case InputEventKind::Controller: j.update(controllerJson(e.controller)); break;
        }
        if (e.mods != 0 && e.kind != InputEventKind::Move && e.kind != InputEventKind::Drop && e.kind != InputEventKind::Text &&
            e.kind != InputEventKind::Controller)
            j["mods"] = modsJson(e.mods);
        out += j.dump() + "\n";
    }
    return out;
}

}  // namespace kizamu::interact
