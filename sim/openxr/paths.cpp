// SPDX-License-Identifier: Apache-2.0
/// @file paths.cpp
/// @brief Enum names (xrResultToString, xrStructureTypeToString) and path atoms
/// (xrStringToPath, xrPathToString).
#include "sim/openxr/entry_points.h"
#include "sim/openxr/runtime_state.h"

#include <openxr/openxr_reflection.h>

#include <cstdio>
#include <cstring>
#include <string_view>

namespace kizamu::xrsim {
namespace {

const char* resultName(XrResult value) {
#define KIZAMU_XRSIM_RESULT_CASE(name, number) \
    case name:                                 \
        return #name;
    switch (value) { XR_LIST_ENUM_XrResult(KIZAMU_XRSIM_RESULT_CASE) default : return nullptr; }
#undef KIZAMU_XRSIM_RESULT_CASE
}

const char* structureName(XrStructureType value) {
#define KIZAMU_XRSIM_STRUCTURE_CASE(name, number) \
    case name:                                    \
        return #name;
    switch (value) {
        XR_LIST_ENUM_XrStructureType(KIZAMU_XRSIM_STRUCTURE_CASE) default : return nullptr;
    }
#undef KIZAMU_XRSIM_STRUCTURE_CASE
}

/// The spec's path syntax: '/' then components of [a-z0-9-_.], not only dots, separated by
/// single '/', no trailing '/', shorter than XR_MAX_PATH_LENGTH.
bool isWellFormedPath(std::string_view p) {
    if (p.size() < 2 || p.size() >= XR_MAX_PATH_LENGTH || p.front() != '/' || p.back() == '/')
        return false;
    size_t start = 1;
    while (start <= p.size()) {
        size_t end = p.find('/', start);
        if (end == std::string_view::npos) end = p.size();
        const std::string_view c = p.substr(start, end - start);
        if (c.empty()) return false;
        bool onlyDots = true;
        for (char ch : c) {
            const bool ok = (ch >= 'a' && ch <= 'z') || (ch >= '0' && ch <= '9') || ch == '-' ||
                            ch == '_' || ch == '.';
            if (!ok) return false;
            onlyDots = onlyDots && ch == '.';
        }
        if (onlyDots) return false;
        start = end + 1;
    }
    return true;
}

}  // namespace

/// Unknown values give XR_UNKNOWN_SUCCESS_n / XR_UNKNOWN_FAILURE_n as the spec says.
XrResult xrResultToString(XrInstance instance, XrResult value,
                          char buffer[XR_MAX_RESULT_STRING_SIZE]) {
    Runtime& rt = runtime();
    std::lock_guard lock(rt.mutex);
    if (rt.find<InstanceObject>(instance) == nullptr) return XR_ERROR_HANDLE_INVALID;
    if (const char* name = resultName(value))
        std::snprintf(buffer, XR_MAX_RESULT_STRING_SIZE, "%s", name);
    else
        std::snprintf(buffer, XR_MAX_RESULT_STRING_SIZE, "XR_UNKNOWN_%s_%d",
                      value >= 0 ? "SUCCESS" : "FAILURE", static_cast<int>(value));
    return XR_SUCCESS;
}

/// Unknown values give XR_UNKNOWN_STRUCTURE_TYPE_n.
XrResult xrStructureTypeToString(XrInstance instance, XrStructureType value,
                                 char buffer[XR_MAX_STRUCTURE_NAME_SIZE]) {
    Runtime& rt = runtime();
    std::lock_guard lock(rt.mutex);
    if (rt.find<InstanceObject>(instance) == nullptr) return XR_ERROR_HANDLE_INVALID;
    if (const char* name = structureName(value))
        std::snprintf(buffer, XR_MAX_STRUCTURE_NAME_SIZE, "%s", name);
    else
        std::snprintf(buffer, XR_MAX_STRUCTURE_NAME_SIZE, "XR_UNKNOWN_STRUCTURE_TYPE_%d",
                      static_cast<int>(value));
    return XR_SUCCESS;
}

/// XR_ERROR_PATH_FORMAT_INVALID for a string that is not a well-formed path.
XrResult xrStringToPath(XrInstance instance, const char* pathString, XrPath* path) {
    Runtime& rt = runtime();
    std::lock_guard lock(rt.mutex);
    if (rt.find<InstanceObject>(instance) == nullptr) return XR_ERROR_HANDLE_INVALID;
    if (!isWellFormedPath(pathString)) return XR_ERROR_PATH_FORMAT_INVALID;
    *path = internPath(rt, pathString);
    return XR_SUCCESS;
}

/// XR_ERROR_PATH_INVALID for an atom the runtime never gave out.
XrResult xrPathToString(XrInstance instance, XrPath path, uint32_t bufferCapacityInput,
                        uint32_t* bufferCountOutput, char* buffer) {
    Runtime& rt = runtime();
    std::lock_guard lock(rt.mutex);
    if (rt.find<InstanceObject>(instance) == nullptr) return XR_ERROR_HANDLE_INVALID;
    const std::string* s = kizamu::xrsim::pathString(rt, path);
    if (s == nullptr) return XR_ERROR_PATH_INVALID;
    return twoCallString(*s, bufferCapacityInput, bufferCountOutput, buffer);
}

}  // namespace kizamu::xrsim
