// SPDX-License-Identifier: Apache-2.0
#include "xr/stylus_workspace.h"

#include "util/atomic_file.h"
#include "util/file_error.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <span>

namespace kizamu::xr {

namespace {
using json = nlohmann::json;

double finite(const json& j, const char* key) {
    if (!j.contains(key) || !j[key].is_number()) throw std::invalid_argument(std::string("\"") + key + "\" must be a number");
    const double v = j[key].get<double>();
    if (!std::isfinite(v)) throw std::invalid_argument(std::string("\"") + key + "\" is not finite");
    return v;
}

std::vector<double> numbers(const json& j, const char* key, std::size_t n) {
    if (!j.contains(key) || !j[key].is_array() || j[key].size() != n)
        throw std::invalid_argument(std::string("\"") + key + "\" must be " + std::to_string(n) + " numbers");
    std::vector<double> v;
    for (const json& x : j[key]) {
        if (!x.is_number() || !std::isfinite(x.get<double>())) throw std::invalid_argument(std::string("\"") + key + "\" holds a non-number");
        v.push_back(x.get<double>());
    }
    return v;
}
}  // namespace

haptics::WorkspaceMapping stylusMapping(const Similarity& deviceToSpace, const Similarity& placement) {
    const Similarity deviceToClay = placement.inverse() * deviceToSpace;
    haptics::WorkspaceMapping m;
    m.scale = deviceToClay.scale;
    m.rotation = deviceToClay.rotation;
    m.deviceAnchor = glm::dvec3(0.0);
    m.worldAnchor = deviceToClay.translation;
    return m;
}

std::string defaultRegistrationPath() {
    namespace fs = std::filesystem;
    fs::path dir;
    if (const char* x = std::getenv("XDG_CONFIG_HOME"); x && *x) dir = x;
    else if (const char* h = std::getenv("HOME"); h && *h) dir = fs::path(h) / ".config";
    else dir = fs::temp_directory_path();
    return (dir / "kizamu" / "stylus-registration.json").string();
}

void saveStylusRegistration(const std::string& path, const StylusRegistration& r, const std::string& device) {
    const Similarity& s = r.deviceToSpace;
    const json j = {{"kizamu_stylus_registration", 1},
                    {"device", device},
                    {"scale", s.scale},
                    {"rotation", {s.rotation.w, s.rotation.x, s.rotation.y, s.rotation.z}},
                    {"translation", {s.translation.x, s.translation.y, s.translation.z}},
                    {"rms_m", r.rmsM}};
    const std::string text = j.dump(2) + "\n";
    std::error_code ec;
    std::filesystem::create_directories(std::filesystem::path(path).parent_path(), ec);
    util::writeFileAtomically(path, std::as_bytes(std::span(text.data(), text.size())));
}

std::optional<StylusRegistration> loadStylusRegistration(const std::string& path) {
    std::ifstream in(path);
    if (!in) {
        if (!std::filesystem::exists(path)) return std::nullopt;
        throw FileError(path, "cannot be read");
    }
    try {
        const json j = json::parse(in);
        if (!j.is_object() || j.value("kizamu_stylus_registration", 0) != 1) throw std::invalid_argument("not a Kizamu stylus registration");
        StylusRegistration r;
        r.deviceToSpace.scale = finite(j, "scale");
        if (r.deviceToSpace.scale < 1e-3 || r.deviceToSpace.scale > 1e3) throw std::invalid_argument("\"scale\" is out of range");
        const auto q = numbers(j, "rotation", 4);
        const glm::dquat rotation(q[0], q[1], q[2], q[3]);
        if (glm::length(rotation) < 1e-6) throw std::invalid_argument("\"rotation\" is zero");
        r.deviceToSpace.rotation = glm::normalize(rotation);
        const auto t = numbers(j, "translation", 3);
        r.deviceToSpace.translation = glm::dvec3(t[0], t[1], t[2]);
        r.rmsM = finite(j, "rms_m");
        return r;
    } catch (const std::exception& e) {  // nlohmann's parse errors and ours
        throw FileError(path, e.what());
    }
}

}  // namespace kizamu::xr
