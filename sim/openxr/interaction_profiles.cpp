// SPDX-License-Identifier: Apache-2.0
/// @file interaction_profiles.cpp
/// @brief The three profiles' paths (from the spec's interaction profile section) and the
/// shorthand rules.
#include "sim/openxr/interaction_profiles.h"

#include <cctype>
#include <vector>

namespace kizamu::xrsim {
namespace {

enum Hands { kLeft = 1, kRight = 2, kBoth = 3 };

struct Source {
    Hands hands;
    const char* path;  ///< below the top-level path
};

struct Profile {
    const char* path;
    std::vector<Source> sources;
};

const std::vector<Profile>& profiles() {
    static const std::vector<Profile> kProfiles = {
        {"/interaction_profiles/khr/simple_controller",
         {{kBoth, "/input/select/click"},
          {kBoth, "/input/menu/click"},
          {kBoth, "/input/grip/pose"},
          {kBoth, "/input/aim/pose"},
          {kBoth, "/output/haptic"}}},
        {"/interaction_profiles/oculus/touch_controller",
         {{kLeft, "/input/x/click"},          {kLeft, "/input/x/touch"},
          {kLeft, "/input/y/click"},          {kLeft, "/input/y/touch"},
          {kLeft, "/input/menu/click"},       {kRight, "/input/a/click"},
          {kRight, "/input/a/touch"},         {kRight, "/input/b/click"},
          {kRight, "/input/b/touch"},         {kRight, "/input/system/click"},
          {kBoth, "/input/squeeze/value"},    {kBoth, "/input/trigger/value"},
          {kBoth, "/input/trigger/touch"},    {kBoth, "/input/thumbstick/x"},
          {kBoth, "/input/thumbstick/y"},     {kBoth, "/input/thumbstick/click"},
          {kBoth, "/input/thumbstick/touch"}, {kBoth, "/input/thumbrest/touch"},
          {kBoth, "/input/grip/pose"},        {kBoth, "/input/aim/pose"},
          {kBoth, "/output/haptic"}}},
        {"/interaction_profiles/valve/index_controller",
         {{kBoth, "/input/system/click"},     {kBoth, "/input/system/touch"},
          {kBoth, "/input/a/click"},          {kBoth, "/input/a/touch"},
          {kBoth, "/input/b/click"},          {kBoth, "/input/b/touch"},
          {kBoth, "/input/squeeze/value"},    {kBoth, "/input/squeeze/force"},
          {kBoth, "/input/trigger/click"},    {kBoth, "/input/trigger/value"},
          {kBoth, "/input/trigger/touch"},    {kBoth, "/input/thumbstick/x"},
          {kBoth, "/input/thumbstick/y"},     {kBoth, "/input/thumbstick/click"},
          {kBoth, "/input/thumbstick/touch"}, {kBoth, "/input/trackpad/x"},
          {kBoth, "/input/trackpad/y"},       {kBoth, "/input/trackpad/force"},
          {kBoth, "/input/trackpad/touch"},   {kBoth, "/input/grip/pose"},
          {kBoth, "/input/aim/pose"},         {kBoth, "/output/haptic"}}},
    };
    return kProfiles;
}

const Profile* findProfile(std::string_view path) {
    for (const Profile& p : profiles())
        if (path == p.path) return &p;
    return nullptr;
}

/// The full paths of a profile's sources for both hands.
std::vector<std::string> fullPaths(const Profile& p) {
    std::vector<std::string> out;
    for (const Source& s : p.sources) {
        if (s.hands & kLeft) out.push_back(std::string(kHandLeft) + s.path);
        if (s.hands & kRight) out.push_back(std::string(kHandRight) + s.path);
    }
    return out;
}

std::string_view parentOf(std::string_view path) {
    const size_t slash = path.rfind('/');
    return slash == std::string_view::npos ? std::string_view{} : path.substr(0, slash);
}

std::string capitalised(std::string_view words) {
    std::string out;
    bool start = true;
    for (char c : words) {
        if (c == '/' || c == '_') {
            if (!out.empty() && out.back() != ' ') out += ' ';
            start = true;
            continue;
        }
        out += start ? static_cast<char>(std::toupper(static_cast<unsigned char>(c))) : c;
        start = false;
    }
    while (!out.empty() && out.back() == ' ') out.pop_back();
    return out;
}

}  // namespace

bool isKnownProfile(std::string_view profile) {
    return findProfile(profile) != nullptr;
}

bool isValidBinding(std::string_view profile, std::string_view path) {
    const Profile* p = findProfile(profile);
    if (p == nullptr) return false;
    for (const std::string& full : fullPaths(*p)) {
        if (path == full) return true;
        if (full.find("/input/") != std::string::npos && path == parentOf(full)) return true;
    }
    return false;
}

std::string resolveBinding(std::string_view profile, std::string_view path, XrActionType type) {
    const Profile* p = findProfile(profile);
    if (p == nullptr) return std::string(path);
    const std::vector<std::string> all = fullPaths(*p);
    for (const std::string& full : all)
        if (path == full) return full;
    auto has = [&](const char* component) {
        const std::string candidate = std::string(path) + "/" + component;
        for (const std::string& full : all)
            if (full == candidate) return true;
        return false;
    };
    std::vector<const char*> order;
    switch (type) {
        case XR_ACTION_TYPE_BOOLEAN_INPUT:
            order = {"click", "value", "force"};
            break;
        case XR_ACTION_TYPE_FLOAT_INPUT:
            order = {"value", "click", "force"};
            break;
        case XR_ACTION_TYPE_POSE_INPUT:
            order = {"pose"};
            break;
        default:
            break;
    }
    for (const char* c : order)
        if (has(c)) return std::string(path) + "/" + c;
    return std::string(path);
}

std::string topLevelPath(std::string_view path) {
    for (const char* top :
         {kHandLeft, kHandRight, "/user/head", "/user/gamepad", "/user/treadmill"}) {
        const std::string_view t(top);
        if (path.substr(0, t.size()) == t && (path.size() == t.size() || path[t.size()] == '/'))
            return std::string(t);
    }
    return {};
}

bool isTopLevelUserPath(std::string_view path) {
    return !path.empty() && topLevelPath(path) == path;
}

std::string userPathName(std::string_view path) {
    const std::string top = topLevelPath(path);
    if (top == kHandLeft) return "Left Hand";
    if (top == kHandRight) return "Right Hand";
    return capitalised(std::string_view(top).substr(top.rfind('/') + 1));
}

std::string profileName(std::string_view profile) {
    return capitalised(profile.substr(profile.rfind('/') + 1));
}

std::string componentName(std::string_view path) {
    const std::string top = topLevelPath(path);
    std::string_view rest = path.substr(top.size());
    for (std::string_view prefix : {"/input/", "/output/"})
        if (rest.substr(0, prefix.size()) == prefix) rest = rest.substr(prefix.size());
    return capitalised(rest);
}

}  // namespace kizamu::xrsim
