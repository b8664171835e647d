// SPDX-License-Identifier: Apache-2.0
/// @file runtime_state.cpp
/// @brief The process's runtime, path atoms, session state changes and the event queue.
#include "sim/openxr/runtime_state.h"

#include "sim/openxr/capture.h"

#include <algorithm>
#include <cstring>

namespace kizamu::xrsim {

Runtime& runtime() {
    static Runtime rt;
    return rt;
}

XrPath internPath(Runtime& rt, const std::string& path) {
    const auto it = rt.pathAtoms.find(path);
    if (it != rt.pathAtoms.end()) return it->second;
    rt.paths.push_back(path);
    const XrPath atom = rt.paths.size();
    rt.pathAtoms.emplace(path, atom);
    return atom;
}

const std::string* pathString(const Runtime& rt, XrPath atom) {
    if (atom == XR_NULL_PATH || atom > rt.paths.size()) return nullptr;
    return &rt.paths[atom - 1];
}

XrResult findSession(Runtime& rt, XrSession handle, SessionObject** out) {
    SessionObject* s = rt.find<SessionObject>(handle);
    if (s == nullptr) return XR_ERROR_HANDLE_INVALID;
    if (s->lost) return XR_ERROR_SESSION_LOST;
    *out = s;
    return XR_SUCCESS;
}

void queueEvent(InstanceObject& instance, const void* event, size_t size) {
    XrEventDataBuffer buffer{};
    std::memcpy(&buffer, event, std::min(size, sizeof(buffer)));
    instance.events.push_back(buffer);
}

void setSessionState(Runtime& rt, XrSession handle, SessionObject& session, XrSessionState state) {
    session.state = state;
    XrEventDataSessionStateChanged e{XR_TYPE_EVENT_DATA_SESSION_STATE_CHANGED};
    e.session = handle;
    e.state = state;
    e.time = session.now;
    if (InstanceObject* inst = rt.find<InstanceObject>(session.instance))
        queueEvent(*inst, &e, sizeof(e));
    captureEvent(rt, std::string("{\"event\":\"state\",\"state\":\"") + sessionStateName(state) +
                         "\",\"time\":" + std::to_string(session.now) + "}");
}

void stopSession(Runtime& rt, XrSession handle, SessionObject& session) {
    if (session.state == XR_SESSION_STATE_FOCUSED)
        setSessionState(rt, handle, session, XR_SESSION_STATE_VISIBLE);
    if (session.state == XR_SESSION_STATE_VISIBLE)
        setSessionState(rt, handle, session, XR_SESSION_STATE_SYNCHRONIZED);
    if (session.state == XR_SESSION_STATE_SYNCHRONIZED)
        setSessionState(rt, handle, session, XR_SESSION_STATE_STOPPING);
}

XrResult twoCallString(const std::string& value, uint32_t capacity, uint32_t* countOutput,
                       char* buffer) {
    const auto count = static_cast<uint32_t>(value.size() + 1);
    return twoCall(capacity, countOutput, count,
                   [&](uint32_t i) { buffer[i] = i < value.size() ? value[i] : '\0'; });
}

const XrBaseInStructure* findInChain(const void* next, XrStructureType type) {
    for (auto* s = static_cast<const XrBaseInStructure*>(next); s != nullptr; s = s->next)
        if (s->type == type) return s;
    return nullptr;
}

}  // namespace kizamu::xrsim
