// SPDX-License-Identifier: Apache-2.0
/// @file control.cpp
/// @brief The exported control API (xrsim_control.h).
#include "sim/openxr/xrsim_control.h"

#include "sim/openxr/runtime_state.h"

#include <mutex>

using kizamu::xrsim::Runtime;
using kizamu::xrsim::runtime;
using kizamu::xrsim::SessionObject;

extern "C" {

int kizamuXrSimLastView(int eye, int* width, int* height, const unsigned char** rgba) {
    if (eye != 0 && eye != 1) return 2;
    Runtime& rt = runtime();
    std::lock_guard lock(rt.mutex);
    const kizamu::xrsim::ViewImage& v = rt.lastViews[static_cast<size_t>(eye)];
    if (v.rgba.empty()) return 1;
    *width = v.width;
    *height = v.height;
    *rgba = v.rgba.data();
    return 0;
}

unsigned long long kizamuXrSimFramesEnded(void) {
    Runtime& rt = runtime();
    std::lock_guard lock(rt.mutex);
    return rt.framesEnded;
}

int kizamuXrSimHapticCount(void) {
    Runtime& rt = runtime();
    std::lock_guard lock(rt.mutex);
    return static_cast<int>(rt.haptics.size());
}

int kizamuXrSimHapticEvent(int i, KizamuXrSimHaptic* out) {
    Runtime& rt = runtime();
    std::lock_guard lock(rt.mutex);
    if (i < 0 || static_cast<size_t>(i) >= rt.haptics.size()) return 1;
    *out = rt.haptics[static_cast<size_t>(i)];
    return 0;
}

void kizamuXrSimRequestStop(void) {
    Runtime& rt = runtime();
    std::lock_guard lock(rt.mutex);
    for (auto& [id, object] : rt.objects)
        if (auto* s = std::get_if<SessionObject>(&object); s && s->running && !s->lost)
            kizamu::xrsim::stopSession(rt, reinterpret_cast<XrSession>(id), *s);
}

void kizamuXrSimLoseSession(void) {
    Runtime& rt = runtime();
    std::lock_guard lock(rt.mutex);
    for (auto& [id, object] : rt.objects)
        if (auto* s = std::get_if<SessionObject>(&object); s && !s->lost) {
            kizamu::xrsim::setSessionState(rt, reinterpret_cast<XrSession>(id), *s,
                                           XR_SESSION_STATE_LOSS_PENDING);
            s->lost = true;
        }
}

void kizamuXrSimSetHeadPose(const float position[3], const float orientation[4]) {
    Runtime& rt = runtime();
    std::lock_guard lock(rt.mutex);
    rt.headPose = XrPosef{{orientation[0], orientation[1], orientation[2], orientation[3]},
                          {position[0], position[1], position[2]}};
}

void kizamuXrSimReset(void) {
    Runtime& rt = runtime();
    std::lock_guard lock(rt.mutex);
    rt.framesEnded = 0;
    rt.lastViews = {};
    rt.haptics.clear();
    rt.headPose = XrPosef{{0.0f, 0.0f, 0.0f, 1.0f}, {0.0f, 0.0f, 0.0f}};
}

}  // extern "C"
