// SPDX-License-Identifier: Apache-2.0
/// @file runtime_state.h
/// @brief All state of the simulated OpenXR runtime: the live handles and what they own, the
/// path atoms, the event queues, and the recorded outputs the control API reads.
///
/// Where it sits: sim/ is the project's null backend (STYLE.md §6). The OpenXR loader opens
/// libkizamu_xrsim.so through its manifest; every entry point (entry_points.h) takes the one
/// lock of `Runtime`, so an application may call from any thread, and calls are serialised.
/// Handles are keys of `Runtime::objects`; an entry point looks a handle up with the type it
/// expects and answers XR_ERROR_HANDLE_INVALID when it is not there: no handle is ever
/// dereferenced. Units: XrTime and XrDuration in ns of the simulated clock, poses in m.
///
/// Features:
///  [X] instance, system (one HMD), PRIMARY_STEREO views, OPAQUE blending
///  [X] session lifecycle with its events; runtime-initiated stop; session loss
///  [X] lock-step clock: each xrWaitFrame advances the predicted display time by 1/90 s
///  [X] reference spaces VIEW, LOCAL, STAGE; action spaces; xrLocateSpace, xrLocateViews
///  [X] GL swapchains (GL_SRGB8_ALPHA8, GL_RGBA8; 3 images; texture arrays)
///  [X] projection layers read back at xrEndFrame (control API, PNG capture)
///  [X] actions and bindings for khr/simple, oculus/touch and valve/index controllers
///  [X] XR_EXT_conformance_automation input; haptics recorded
///  [ ] cube, cylinder, equirect layers; depth or multisampled swapchains; static swapchains
///  [ ] XR_EXT_debug_utils; visibility masks; instance loss
/// Changes: none yet (first version, issue 34).
#pragma once

#include "sim/openxr/xr_headers.h"
#include "sim/openxr/xrsim_control.h"

#include <array>
#include <cstdint>
#include <deque>
#include <map>
#include <mutex>
#include <set>
#include <string>
#include <unordered_map>
#include <utility>
#include <variant>
#include <vector>

namespace kizamu::xrsim {

inline constexpr XrTime kStartTime = 1'000'000'000;     ///< first predicted display time
inline constexpr XrDuration kFramePeriod = 11'111'111;  ///< 1/90 s
inline constexpr XrSystemId kSystemId = 1;              ///< the one HMD
inline constexpr float kEyeOffset = 0.032f;             ///< m, each eye from the head on X
inline constexpr float kFovHalfAngle = 0.785398163f;    ///< rad (45°)
inline constexpr uint32_t kMaxLayers = 16;
inline constexpr uint32_t kSwapchainImages = 3;
inline constexpr uint32_t kMaxImageSize = 4096;
inline constexpr char kExtOpenGl[] = "XR_KHR_opengl_enable";
inline constexpr char kExtAutomation[] = "XR_EXT_conformance_automation";

/// One suggested binding: an action and the full input or output path it reads.
struct Binding {
    XrAction action;
    XrPath path;
};

/// An XrInstance: enabled extensions, its event queue, suggested bindings, its session.
struct InstanceObject {
    std::set<std::string> extensions;
    bool glRequirementsQueried = false;
    std::deque<XrEventDataBuffer> events;
    std::map<XrPath, std::vector<Binding>> suggested;  ///< per interaction profile
    XrSession session = XR_NULL_HANDLE;                ///< at most one at a time
};

/// An action's state after the last xrSyncActions, for one subaction path (or all: XR_NULL_PATH).
struct ActionValue {
    bool isActive = false;
    bool boolValue = false;
    float floatValue = 0.0f;
    XrVector2f vectorValue{0.0f, 0.0f};
    bool changed = false;
    XrTime lastChange = 0;
};

/// An XrSession: lifecycle and frame-loop state, its clock, attached action sets, the simulated
/// controllers' state (set by automation.cpp) and the action states of the last sync.
struct SessionObject {
    XrInstance instance = XR_NULL_HANDLE;
    XrSessionState state = XR_SESSION_STATE_UNKNOWN;
    bool running = false;
    bool lost = false;
    uint32_t pendingWaits = 0;  ///< xrWaitFrame calls not yet consumed by xrBeginFrame
    bool frameBegun = false;
    uint64_t framesWaited = 0;
    XrTime now = kStartTime;  ///< the last predicted display time
    std::set<XrActionSet> attachedSets;
    XrPath profile = XR_NULL_PATH;  ///< the current interaction profile, chosen at attach
    std::unordered_map<std::string, float> inputs;   ///< component path -> value (bool 0/1)
    std::unordered_map<std::string, XrPosef> poses;  ///< pose path -> pose in LOCAL
    std::unordered_map<std::string, bool> inactive;  ///< top-level path -> switched off
    std::map<std::pair<XrAction, XrPath>, ActionValue> actionValues;
};

/// An XrSpace: a reference space, or an action space when `action` is set.
struct SpaceObject {
    XrSession session = XR_NULL_HANDLE;
    XrReferenceSpaceType referenceType = XR_REFERENCE_SPACE_TYPE_LOCAL;
    XrAction action = XR_NULL_HANDLE;  ///< non-null: an action space
    XrPath subactionPath = XR_NULL_PATH;
    XrPosef offset{};  ///< pose in the reference or action space
};

/// An XrSwapchain: its GL textures and the acquire → wait → release bookkeeping.
struct SwapchainObject {
    XrSession session = XR_NULL_HANDLE;
    int64_t format = 0;
    uint32_t width = 0, height = 0, arraySize = 1;
    std::vector<uint32_t> textures;  ///< GL names in the application's context
    std::deque<uint32_t> acquired;   ///< acquired, not released, oldest first
    uint32_t waited = 0;             ///< how many of `acquired` (from the front) were waited
    uint32_t nextImage = 0;
    int64_t lastReleased = -1;
};

/// An XrActionSet.
struct ActionSetObject {
    XrInstance instance = XR_NULL_HANDLE;
    std::string name, localizedName;
    bool attached = false;  ///< to any session: the set and its actions are immutable
};

/// An XrAction.
struct ActionObject {
    XrActionSet set = XR_NULL_HANDLE;
    std::string name;
    XrActionType type = XR_ACTION_TYPE_BOOLEAN_INPUT;
    std::vector<XrPath> subactionPaths;
};

using Object = std::variant<InstanceObject, SessionObject, SpaceObject, SwapchainObject,
                            ActionSetObject, ActionObject>;

/// One eye's last read-back image: RGBA8, top row first.
struct ViewImage {
    int width = 0, height = 0;
    std::vector<unsigned char> rgba;
};

/// The runtime: one per process (the loader opens the library once). Guard every access with
/// `mutex`; entry points hold it for their whole call.
struct Runtime {
    std::mutex mutex;
    uint64_t nextHandle = 1;
    std::unordered_map<uint64_t, Object> objects;
    std::vector<std::string> paths;  ///< atom - 1 -> string
    std::unordered_map<std::string, XrPath> pathAtoms;
    uint64_t framesEnded = 0;
    std::array<ViewImage, 2> lastViews;
    std::vector<KizamuXrSimHaptic> haptics;
    XrPosef headPose{{0.0f, 0.0f, 0.0f, 1.0f}, {0.0f, 0.0f, 0.0f}};
    std::string captureDir;  ///< $KIZAMU_XRSIM_CAPTURE at xrCreateInstance; empty: no capture
    /// $KIZAMU_XRSIM_STOP_AT_FRAME and $KIZAMU_XRSIM_LOSE_AT_FRAME at xrCreateInstance: after
    /// that many frames ended, the runtime stops the session (as if the artist quit from the
    /// headset) or loses it, so a test of an application run as a process can script either. 0: never.
    uint64_t stopAtFrame = 0, loseAtFrame = 0;

    /// Registers `object` and returns its new handle.
    template <class H>
    H add(Object object) {
        const uint64_t id = nextHandle++;
        objects.emplace(id, std::move(object));
        return reinterpret_cast<H>(id);
    }
    /// The live object of type T behind `handle`, or nullptr (wrong type, destroyed, null).
    template <class T, class H>
    T* find(H handle) {
        const auto it = objects.find(reinterpret_cast<uint64_t>(handle));
        return it == objects.end() ? nullptr : std::get_if<T>(&it->second);
    }
    template <class H>
    void erase(H handle) {
        objects.erase(reinterpret_cast<uint64_t>(handle));
    }
};

/// The process's runtime.
Runtime& runtime();

/// The path atom of `path` (registered on first use; the string must be well formed).
XrPath internPath(Runtime& rt, const std::string& path);
/// The string of `atom`, or nullptr when it is not a path.
const std::string* pathString(const Runtime& rt, XrPath atom);

/// Looks up a session for a call on it: XR_ERROR_HANDLE_INVALID when it is not live,
/// XR_ERROR_SESSION_LOST once lost; XR_SUCCESS with *out set otherwise.
XrResult findSession(Runtime& rt, XrSession handle, SessionObject** out);

/// Runs `body(rt, session)` for one entry point's call on a session, under the runtime's lock:
/// XR_ERROR_HANDLE_INVALID or XR_ERROR_SESSION_LOST as findSession, else what `body` returns.
template <class Body>
XrResult onSession(XrSession handle, Body&& body) {
    Runtime& rt = runtime();
    std::lock_guard lock(rt.mutex);
    SessionObject* s = nullptr;
    if (const XrResult r = findSession(rt, handle, &s); r != XR_SUCCESS) return r;
    return body(rt, *s);
}

/// Destroys the live object of type T behind `handle` (an action or a space: objects that own
/// nothing), under the runtime's lock; XR_ERROR_HANDLE_INVALID when there is none.
template <class T, class H>
XrResult destroyObject(H handle) {
    Runtime& rt = runtime();
    std::lock_guard lock(rt.mutex);
    if (rt.find<T>(handle) == nullptr) return XR_ERROR_HANDLE_INVALID;
    rt.erase(handle);
    return XR_SUCCESS;
}

/// Looks up an object a session owns (a space or a swapchain) with its session:
/// XR_ERROR_HANDLE_INVALID when either is not live, XR_ERROR_SESSION_LOST once it is lost.
template <class T, class H>
XrResult findSessionChild(Runtime& rt, H handle, T** child, SessionObject** session) {
    T* c = rt.find<T>(handle);
    if (c == nullptr) return XR_ERROR_HANDLE_INVALID;
    if (const XrResult r = findSession(rt, c->session, session); r != XR_SUCCESS) return r;
    *child = c;
    return XR_SUCCESS;
}

/// Moves `session` to `state`: queues XrEventDataSessionStateChanged on its instance and logs it
/// to the capture directory.
void setSessionState(Runtime& rt, XrSession handle, SessionObject& session, XrSessionState state);

/// Runtime- or application-requested stop: from FOCUSED/VISIBLE/SYNCHRONIZED down to STOPPING,
/// one event per state passed.
void stopSession(Runtime& rt, XrSession handle, SessionObject& session);

/// Destroys a session with its spaces and swapchains (their GL textures too, when a context is
/// current); its undelivered state events are dropped. Nothing for a dead handle.
void destroySession(Runtime& rt, XrSession handle);

/// Queues an event (any XrEventData* structure of `size` bytes) on `instance`.
void queueEvent(InstanceObject& instance, const void* event, size_t size);

/// The two-call idiom: sets *countOutput to `count`; with capacity 0 returns XR_SUCCESS, with
/// 0 < capacity < count XR_ERROR_SIZE_INSUFFICIENT, else calls write(i) for each i < count.
template <class Write>
XrResult twoCall(uint32_t capacity, uint32_t* countOutput, uint32_t count, Write&& write) {
    if (countOutput == nullptr) return XR_ERROR_VALIDATION_FAILURE;
    *countOutput = count;
    if (capacity == 0) return XR_SUCCESS;
    if (capacity < count) return XR_ERROR_SIZE_INSUFFICIENT;
    for (uint32_t i = 0; i < count; ++i) write(i);
    return XR_SUCCESS;
}

/// The two-call idiom for a string buffer (count includes the terminating zero).
XrResult twoCallString(const std::string& value, uint32_t capacity, uint32_t* countOutput,
                       char* buffer);

/// Finds the first structure of `type` in a `next` chain, or nullptr.
const XrBaseInStructure* findInChain(const void* next, XrStructureType type);

}  // namespace kizamu::xrsim
