// SPDX-License-Identifier: Apache-2.0
/// @file actions.cpp
/// @brief Action sets, actions, suggested bindings, attachment, xrSyncActions and action
/// states, bound sources, localized names, haptics.
///
/// The current interaction profile is chosen when action sets are attached: $KIZAMU_XRSIM_PROFILE
/// when set (a full path or e.g. "oculus/touch_controller"), else the first of valve/index,
/// oculus/touch and khr/simple that the application suggested bindings for. States are computed
/// at xrSyncActions from the input state (automation.cpp) of the bound sources; several sources
/// combine as the spec says (booleans OR, floats and vectors the largest magnitude).
#include "sim/openxr/actions.h"

#include "sim/openxr/capture.h"
#include "sim/openxr/entry_points.h"
#include "sim/openxr/interaction_profiles.h"
#include "sim/openxr/pose_math.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <type_traits>

namespace kizamu::xrsim {
namespace {

/// Action and action set names: [a-z0-9-_.], not empty.
bool isValidName(const char* name) {
    if (name[0] == '\0') return false;
    for (const char* c = name; *c != '\0'; ++c)
        if (!((*c >= 'a' && *c <= 'z') || (*c >= '0' && *c <= '9') || *c == '-' || *c == '_' ||
              *c == '.'))
            return false;
    return true;
}

/// The live action `action` whose set is attached to `s`; XR_ERROR_HANDLE_INVALID or
/// XR_ERROR_ACTIONSET_NOT_ATTACHED otherwise.
XrResult findAttachedAction(Runtime& rt, const SessionObject& s, XrAction action,
                            ActionObject** out) {
    ActionObject* a = rt.find<ActionObject>(action);
    if (a == nullptr) return XR_ERROR_HANDLE_INVALID;
    if (!s.attachedSets.count(a->set)) return XR_ERROR_ACTIONSET_NOT_ATTACHED;
    *out = a;
    return XR_SUCCESS;
}

/// The XrSession's state of `action` for `subactionPath` after the last sync (inactive before).
ActionValue actionValue(const SessionObject& s, XrAction action, XrPath subactionPath) {
    const auto it = s.actionValues.find({action, subactionPath});
    return it == s.actionValues.end() ? ActionValue{} : it->second;
}

/// The profile to use at attach (see the file comment); XR_NULL_PATH when none fits.
XrPath chooseProfile(Runtime& rt, const InstanceObject& inst) {
    if (const char* env = std::getenv("KIZAMU_XRSIM_PROFILE"); env != nullptr && env[0] != '\0') {
        std::string p = env;
        if (p.rfind("/interaction_profiles/", 0) != 0) p = "/interaction_profiles/" + p;
        if (isKnownProfile(p)) return internPath(rt, p);
    }
    for (const char* p : kProfilesByPreference) {
        const auto it = rt.pathAtoms.find(p);
        if (it != rt.pathAtoms.end() && inst.suggested.count(it->second)) return it->second;
    }
    return XR_NULL_PATH;
}

/// Computes `a`'s state for one subaction path from its sources (filter: the set's active
/// subaction path, XR_NULL_PATH for all).
ActionValue computeValue(Runtime& rt, const SessionObject& s, XrAction handle,
                         const ActionObject& a, XrPath subactionPath, XrPath filter) {
    ActionValue v;
    for (const std::string& src : boundSources(rt, s, handle, subactionPath)) {
        const std::string top = topLevelPath(src);
        if (s.inactive.count(top) && s.inactive.at(top)) continue;
        if (filter != XR_NULL_PATH && *pathString(rt, filter) != top) continue;
        v.isActive = true;
        switch (a.type) {
            case XR_ACTION_TYPE_BOOLEAN_INPUT:
                v.boolValue = v.boolValue || readInput(s, src) > 0.5f;
                break;
            case XR_ACTION_TYPE_FLOAT_INPUT: {
                const float f = readInput(s, src);
                if (std::fabs(f) > std::fabs(v.floatValue)) v.floatValue = f;
                break;
            }
            case XR_ACTION_TYPE_VECTOR2F_INPUT: {
                const XrVector2f xy{readInput(s, src + "/x"), readInput(s, src + "/y")};
                if (xy.x * xy.x + xy.y * xy.y >
                    v.vectorValue.x * v.vectorValue.x + v.vectorValue.y * v.vectorValue.y)
                    v.vectorValue = xy;
                break;
            }
            default:
                break;
        }
    }
    return v;
}

bool sameValue(const ActionValue& a, const ActionValue& b) {
    return a.boolValue == b.boolValue && a.floatValue == b.floatValue &&
           a.vectorValue.x == b.vectorValue.x && a.vectorValue.y == b.vectorValue.y;
}

/// The checks every use of an action on an XrSession makes: the XrSession, the action with its set
/// attached to it (XR_ERROR_ACTIONSET_NOT_ATTACHED), its type (XR_ERROR_ACTION_TYPE_MISMATCH)
/// and the subaction path.
XrResult findActionUse(Runtime& rt, XrSession session, XrAction action, XrPath subactionPath,
                       XrActionType type, SessionObject** out) {
    SessionObject* s = nullptr;
    if (const XrResult r = findSession(rt, session, &s); r != XR_SUCCESS) return r;
    ActionObject* a = nullptr;
    if (const XrResult r = findAttachedAction(rt, *s, action, &a); r != XR_SUCCESS) return r;
    if (a->type != type) return XR_ERROR_ACTION_TYPE_MISMATCH;
    if (const XrResult r = checkSubactionPath(rt, *a, subactionPath); r != XR_SUCCESS) return r;
    *out = s;
    return XR_SUCCESS;
}

/// One xrGetActionState* call: the checks of findActionUse, then `state` from the last sync;
/// `current` gives currentState from the value (poses have none).
template <class State, class Current>
XrResult getState(XrSession session, const XrActionStateGetInfo* getInfo, XrActionType type,
                  State* state, Current current) {
    Runtime& rt = runtime();
    std::lock_guard lock(rt.mutex);
    SessionObject* s = nullptr;
    if (const XrResult r =
            findActionUse(rt, session, getInfo->action, getInfo->subactionPath, type, &s);
        r != XR_SUCCESS)
        return r;
    const ActionValue v = actionValue(*s, getInfo->action, getInfo->subactionPath);
    state->isActive = v.isActive ? XR_TRUE : XR_FALSE;
    if constexpr (!std::is_same_v<State, XrActionStatePose>) {
        state->currentState = current(v);
        state->changedSinceLastSync = v.changed ? XR_TRUE : XR_FALSE;
        state->lastChangeTime = v.lastChange;
    }
    return XR_SUCCESS;
}

/// One haptic call: the checks of findActionUse, then one record (control API, capture) for
/// every hand the output is bound to (those under the subaction path when it is given).
XrResult recordHaptic(XrSession session, const XrHapticActionInfo& info, float amplitude,
                      XrDuration duration, float frequency) {
    Runtime& rt = runtime();
    std::lock_guard lock(rt.mutex);
    SessionObject* s = nullptr;
    if (const XrResult r = findActionUse(rt, session, info.action, info.subactionPath,
                                         XR_ACTION_TYPE_VIBRATION_OUTPUT, &s);
        r != XR_SUCCESS)
        return r;
    for (const std::string& src : boundSources(rt, *s, info.action, info.subactionPath)) {
        KizamuXrSimHaptic h{};
        h.timeNs = s->now;
        std::snprintf(h.hand, sizeof(h.hand), "%s", topLevelPath(src).c_str());
        h.amplitude = amplitude;
        h.durationNs = duration;
        h.frequencyHz = frequency;
        rt.haptics.push_back(h);
        char line[256];
        std::snprintf(line, sizeof(line),
                      "{\"event\":\"haptic\",\"hand\":\"%s\",\"amplitude\":%g,"
                      "\"duration_ns\":%lld,\"frequency\":%g,\"time\":%lld}",
                      h.hand, static_cast<double>(amplitude), static_cast<long long>(duration),
                      static_cast<double>(frequency), static_cast<long long>(s->now));
        captureEvent(rt, line);
    }
    return XR_SUCCESS;
}

}  // namespace

XrResult checkSubactionPath(const Runtime& rt, const ActionObject& a, XrPath path) {
    if (path == XR_NULL_PATH) return XR_SUCCESS;
    if (pathString(rt, path) == nullptr) return XR_ERROR_PATH_INVALID;
    return std::count(a.subactionPaths.begin(), a.subactionPaths.end(), path) != 0
               ? XR_SUCCESS
               : XR_ERROR_PATH_UNSUPPORTED;
}

float readInput(const SessionObject& session, const std::string& path) {
    if (const auto it = session.inputs.find(path); it != session.inputs.end()) return it->second;
    const size_t slash = path.rfind('/');
    const std::string parent = path.substr(0, slash), leaf = path.substr(slash + 1);
    if (leaf == "click") {
        const auto it = session.inputs.find(parent + "/value");
        return it != session.inputs.end() && it->second > 0.5f ? 1.0f : 0.0f;
    }
    if (leaf == "value") {
        const auto it = session.inputs.find(parent + "/click");
        return it != session.inputs.end() ? it->second : 0.0f;
    }
    return 0.0f;
}

std::vector<std::string> boundSources(Runtime& rt, const SessionObject& session, XrAction action,
                                      XrPath subactionPath) {
    std::vector<std::string> out;
    const InstanceObject* inst = rt.find<InstanceObject>(session.instance);
    const ActionObject* a = rt.find<ActionObject>(action);
    if (inst == nullptr || a == nullptr || session.profile == XR_NULL_PATH) return out;
    const auto it = inst->suggested.find(session.profile);
    if (it == inst->suggested.end()) return out;
    const std::string& profile = *pathString(rt, session.profile);
    const std::string* wanted = pathString(rt, subactionPath);
    for (const Binding& b : it->second) {
        if (b.action != action) continue;
        std::string src = resolveBinding(profile, *pathString(rt, b.path), a->type);
        if (wanted != nullptr && topLevelPath(src) != *wanted) continue;
        if (std::find(out.begin(), out.end(), src) == out.end()) out.push_back(std::move(src));
    }
    return out;
}

bool actionSpacePose(Runtime& rt, const SessionObject& session, const SpaceObject& space,
                     XrPosef* poseLocal) {
    if (!actionValue(session, space.action, space.subactionPath).isActive) return false;
    for (const std::string& src : boundSources(rt, session, space.action, space.subactionPath)) {
        const std::string top = topLevelPath(src);
        if (session.inactive.count(top) && session.inactive.at(top)) continue;
        const auto it = session.poses.find(src);
        *poseLocal = compose(it != session.poses.end() ? it->second : identityPose(), space.offset);
        return true;
    }
    return false;
}

/// XR_ERROR_NAME_INVALID, XR_ERROR_NAME_DUPLICATED, XR_ERROR_LOCALIZED_NAME_INVALID,
/// XR_ERROR_LOCALIZED_NAME_DUPLICATED as the spec says (names unique per instance).
XrResult xrCreateActionSet(XrInstance instance, const XrActionSetCreateInfo* createInfo,
                           XrActionSet* actionSet) {
    Runtime& rt = runtime();
    std::lock_guard lock(rt.mutex);
    if (rt.find<InstanceObject>(instance) == nullptr) return XR_ERROR_HANDLE_INVALID;
    if (!isValidName(createInfo->actionSetName)) return XR_ERROR_NAME_INVALID;
    if (createInfo->localizedActionSetName[0] == '\0') return XR_ERROR_LOCALIZED_NAME_INVALID;
    for (const auto& [id, object] : rt.objects)
        if (const auto* set = std::get_if<ActionSetObject>(&object);
            set != nullptr && set->instance == instance) {
            if (set->name == createInfo->actionSetName) return XR_ERROR_NAME_DUPLICATED;
            if (set->localizedName == createInfo->localizedActionSetName)
                return XR_ERROR_LOCALIZED_NAME_DUPLICATED;
        }
    ActionSetObject set;
    set.instance = instance;
    set.name = createInfo->actionSetName;
    set.localizedName = createInfo->localizedActionSetName;
    *actionSet = rt.add<XrActionSet>(std::move(set));
    return XR_SUCCESS;
}

/// Destroys the set's actions too.
XrResult xrDestroyActionSet(XrActionSet actionSet) {
    Runtime& rt = runtime();
    std::lock_guard lock(rt.mutex);
    if (rt.find<ActionSetObject>(actionSet) == nullptr) return XR_ERROR_HANDLE_INVALID;
    std::erase_if(rt.objects, [&](const auto& entry) {
        const auto* a = std::get_if<ActionObject>(&entry.second);
        return a != nullptr && a->set == actionSet;
    });
    rt.erase(actionSet);
    return XR_SUCCESS;
}

/// XR_ERROR_ACTIONSETS_ALREADY_ATTACHED in an attached set; name errors as xrCreateActionSet;
/// XR_ERROR_PATH_INVALID / XR_ERROR_PATH_UNSUPPORTED for a subaction path that is not a path /
/// not a top-level user path (or repeated).
XrResult xrCreateAction(XrActionSet actionSet, const XrActionCreateInfo* createInfo,
                        XrAction* action) {
    Runtime& rt = runtime();
    std::lock_guard lock(rt.mutex);
    ActionSetObject* set = rt.find<ActionSetObject>(actionSet);
    if (set == nullptr) return XR_ERROR_HANDLE_INVALID;
    if (set->attached) return XR_ERROR_ACTIONSETS_ALREADY_ATTACHED;
    if (!isValidName(createInfo->actionName)) return XR_ERROR_NAME_INVALID;
    if (createInfo->localizedActionName[0] == '\0') return XR_ERROR_LOCALIZED_NAME_INVALID;
    for (const auto& [id, object] : rt.objects)
        if (const auto* a = std::get_if<ActionObject>(&object); a && a->set == actionSet)
            if (a->name == createInfo->actionName) return XR_ERROR_NAME_DUPLICATED;
    ActionObject a;
    a.set = actionSet;
    a.name = createInfo->actionName;
    a.type = createInfo->actionType;
    for (uint32_t i = 0; i < createInfo->countSubactionPaths; ++i) {
        const XrPath p = createInfo->subactionPaths[i];
        const std::string* s = pathString(rt, p);
        if (s == nullptr) return XR_ERROR_PATH_INVALID;
        if (!isTopLevelUserPath(*s) ||
            std::count(a.subactionPaths.begin(), a.subactionPaths.end(), p))
            return XR_ERROR_PATH_UNSUPPORTED;
        a.subactionPaths.push_back(p);
    }
    *action = rt.add<XrAction>(std::move(a));
    return XR_SUCCESS;
}

XrResult xrDestroyAction(XrAction action) {
    return destroyObject<ActionObject>(action);
}

/// XR_ERROR_ACTIONSETS_ALREADY_ATTACHED once any of the instance's sets is attached;
/// XR_ERROR_PATH_INVALID for a non-atom; XR_ERROR_PATH_UNSUPPORTED for an unknown profile or a
/// binding path the profile does not have. Replaces the profile's earlier suggestion.
XrResult xrSuggestInteractionProfileBindings(
    XrInstance instance, const XrInteractionProfileSuggestedBinding* suggestedBindings) {
    Runtime& rt = runtime();
    std::lock_guard lock(rt.mutex);
    InstanceObject* inst = rt.find<InstanceObject>(instance);
    if (inst == nullptr) return XR_ERROR_HANDLE_INVALID;
    for (const auto& [id, object] : rt.objects)
        if (const auto* set = std::get_if<ActionSetObject>(&object);
            set && set->instance == instance && set->attached)
            return XR_ERROR_ACTIONSETS_ALREADY_ATTACHED;
    const std::string* profile = pathString(rt, suggestedBindings->interactionProfile);
    if (profile == nullptr) return XR_ERROR_PATH_INVALID;
    if (!isKnownProfile(*profile)) return XR_ERROR_PATH_UNSUPPORTED;
    std::vector<Binding> bindings;
    for (uint32_t i = 0; i < suggestedBindings->countSuggestedBindings; ++i) {
        const XrActionSuggestedBinding& b = suggestedBindings->suggestedBindings[i];
        const ActionObject* a = rt.find<ActionObject>(b.action);
        if (a == nullptr) return XR_ERROR_HANDLE_INVALID;
        const ActionSetObject* set = rt.find<ActionSetObject>(a->set);
        if (set == nullptr || set->instance != instance) return XR_ERROR_HANDLE_INVALID;
        const std::string* path = pathString(rt, b.binding);
        if (path == nullptr) return XR_ERROR_PATH_INVALID;
        if (!isValidBinding(*profile, *path)) return XR_ERROR_PATH_UNSUPPORTED;
        bindings.push_back({b.action, b.binding});
    }
    inst->suggested[suggestedBindings->interactionProfile] = std::move(bindings);
    return XR_SUCCESS;
}

/// XR_ERROR_ACTIONSETS_ALREADY_ATTACHED on a second call. Chooses the interaction profile and
/// queues XrEventDataInteractionProfileChanged when there is one.
XrResult xrAttachSessionActionSets(XrSession session,
                                   const XrSessionActionSetsAttachInfo* attachInfo) {
    return onSession(session, [&](Runtime& rt, SessionObject& s) -> XrResult {
        if (!s.attachedSets.empty()) return XR_ERROR_ACTIONSETS_ALREADY_ATTACHED;
        for (uint32_t i = 0; i < attachInfo->countActionSets; ++i) {
            const ActionSetObject* set = rt.find<ActionSetObject>(attachInfo->actionSets[i]);
            if (set == nullptr || set->instance != s.instance) return XR_ERROR_HANDLE_INVALID;
        }
        for (uint32_t i = 0; i < attachInfo->countActionSets; ++i) {
            rt.find<ActionSetObject>(attachInfo->actionSets[i])->attached = true;
            s.attachedSets.insert(attachInfo->actionSets[i]);
        }
        InstanceObject& inst = *rt.find<InstanceObject>(s.instance);
        s.profile = chooseProfile(rt, inst);
        if (s.profile != XR_NULL_PATH) {
            XrEventDataInteractionProfileChanged e{XR_TYPE_EVENT_DATA_INTERACTION_PROFILE_CHANGED};
            e.session = session;
            queueEvent(inst, &e, sizeof(e));
        }
        return XR_SUCCESS;
    });
}

/// XR_ERROR_ACTIONSET_NOT_ATTACHED before attach; XR_ERROR_PATH_INVALID / UNSUPPORTED for a
/// path that is not a top-level user path. Hands get the current profile, other paths none.
XrResult xrGetCurrentInteractionProfile(XrSession session, XrPath topLevelUserPath,
                                        XrInteractionProfileState* interactionProfile) {
    return onSession(session, [&](Runtime& rt, SessionObject& s) -> XrResult {
        if (s.attachedSets.empty()) return XR_ERROR_ACTIONSET_NOT_ATTACHED;
        const std::string* top = pathString(rt, topLevelUserPath);
        if (top == nullptr) return XR_ERROR_PATH_INVALID;
        if (!isTopLevelUserPath(*top)) return XR_ERROR_PATH_UNSUPPORTED;
        const bool hand = *top == kHandLeft || *top == kHandRight;
        interactionProfile->interactionProfile = hand ? s.profile : XR_NULL_PATH;
        return XR_SUCCESS;
    });
}

XrResult xrGetActionStateBoolean(XrSession session, const XrActionStateGetInfo* getInfo,
                                 XrActionStateBoolean* state) {
    return getState(session, getInfo, XR_ACTION_TYPE_BOOLEAN_INPUT, state,
                    [](const ActionValue& v) { return v.boolValue ? XR_TRUE : XR_FALSE; });
}

XrResult xrGetActionStateFloat(XrSession session, const XrActionStateGetInfo* getInfo,
                               XrActionStateFloat* state) {
    return getState(session, getInfo, XR_ACTION_TYPE_FLOAT_INPUT, state,
                    [](const ActionValue& v) { return v.floatValue; });
}

XrResult xrGetActionStateVector2f(XrSession session, const XrActionStateGetInfo* getInfo,
                                  XrActionStateVector2f* state) {
    return getState(session, getInfo, XR_ACTION_TYPE_VECTOR2F_INPUT, state,
                    [](const ActionValue& v) { return v.vectorValue; });
}

XrResult xrGetActionStatePose(XrSession session, const XrActionStateGetInfo* getInfo,
                              XrActionStatePose* state) {
    return getState(session, getInfo, XR_ACTION_TYPE_POSE_INPUT, state,
                    [](const ActionValue&) { return 0; });
}

/// XR_ERROR_ACTIONSET_NOT_ATTACHED for a set not attached to the XrSession;
/// XR_ERROR_PATH_UNSUPPORTED for an active subaction path that is not a top-level user path;
/// XR_SESSION_NOT_FOCUSED (and every action inactive) when the XrSession is not FOCUSED.
XrResult xrSyncActions(XrSession session, const XrActionsSyncInfo* syncInfo) {
    return onSession(session, [&](Runtime& rt, SessionObject& s) -> XrResult {
        std::map<XrActionSet, XrPath> active;  // set -> subaction filter (XR_NULL_PATH: all)
        for (uint32_t i = 0; i < syncInfo->countActiveActionSets; ++i) {
            const XrActiveActionSet& as = syncInfo->activeActionSets[i];
            if (rt.find<ActionSetObject>(as.actionSet) == nullptr) return XR_ERROR_HANDLE_INVALID;
            if (!s.attachedSets.count(as.actionSet)) return XR_ERROR_ACTIONSET_NOT_ATTACHED;
            if (as.subactionPath != XR_NULL_PATH) {
                const std::string* p = pathString(rt, as.subactionPath);
                if (p == nullptr) return XR_ERROR_PATH_INVALID;
                if (!isTopLevelUserPath(*p)) return XR_ERROR_PATH_UNSUPPORTED;
            }
            // The same set twice with different subaction paths syncs all of it.
            const auto [it, inserted] = active.emplace(as.actionSet, as.subactionPath);
            if (!inserted && it->second != as.subactionPath) it->second = XR_NULL_PATH;
        }
        const bool focused = s.state == XR_SESSION_STATE_FOCUSED;
        for (const auto& [id, object] : rt.objects) {
            const auto* a = std::get_if<ActionObject>(&object);
            if (a == nullptr || !s.attachedSets.count(a->set)) continue;
            const auto handle = reinterpret_cast<XrAction>(id);
            const auto set = active.find(a->set);
            std::vector<XrPath> keys{XR_NULL_PATH};
            keys.insert(keys.end(), a->subactionPaths.begin(), a->subactionPaths.end());
            for (XrPath key : keys) {
                ActionValue v;
                if (focused && set != active.end())
                    v = computeValue(rt, s, handle, *a, key, set->second);
                const ActionValue old = actionValue(s, handle, key);
                v.changed = old.isActive && v.isActive && !sameValue(old, v);
                v.lastChange = v.changed || (v.isActive && !old.isActive) ? s.now : old.lastChange;
                s.actionValues[{handle, key}] = v;
            }
        }
        return focused ? XR_SUCCESS : XR_SESSION_NOT_FOCUSED;
    });
}

/// The resolved source paths of the action in the current profile;
/// XR_ERROR_ACTIONSET_NOT_ATTACHED when its set is not attached.
XrResult xrEnumerateBoundSourcesForAction(XrSession session,
                                          const XrBoundSourcesForActionEnumerateInfo* enumerateInfo,
                                          uint32_t sourceCapacityInput, uint32_t* sourceCountOutput,
                                          XrPath* sources) {
    return onSession(session, [&](Runtime& rt, SessionObject& s) -> XrResult {
        ActionObject* a = nullptr;
        if (const XrResult r = findAttachedAction(rt, s, enumerateInfo->action, &a);
            r != XR_SUCCESS)
            return r;
        const std::vector<std::string> found =
            boundSources(rt, s, enumerateInfo->action, XR_NULL_PATH);
        return twoCall(sourceCapacityInput, sourceCountOutput, static_cast<uint32_t>(found.size()),
                       [&](uint32_t i) { sources[i] = internPath(rt, found[i]); });
    });
}

/// E.g. "Right Hand Index Controller Trigger Value" with every component asked for;
/// XR_ERROR_ACTIONSET_NOT_ATTACHED before attach; XR_ERROR_PATH_INVALID for a non-atom or a path
/// not under a top-level user path.
XrResult xrGetInputSourceLocalizedName(XrSession session,
                                       const XrInputSourceLocalizedNameGetInfo* getInfo,
                                       uint32_t bufferCapacityInput, uint32_t* bufferCountOutput,
                                       char* buffer) {
    return onSession(session, [&](Runtime& rt, SessionObject& s) -> XrResult {
        if (s.attachedSets.empty()) return XR_ERROR_ACTIONSET_NOT_ATTACHED;
        const std::string* path = pathString(rt, getInfo->sourcePath);
        if (path == nullptr || topLevelPath(*path).empty()) return XR_ERROR_PATH_INVALID;
        std::string name;
        auto append = [&](const std::string& piece) {
            if (piece.empty()) return;
            if (!name.empty()) name += ' ';
            name += piece;
        };
        const XrInputSourceLocalizedNameFlags which = getInfo->whichComponents;
        if (which & XR_INPUT_SOURCE_LOCALIZED_NAME_USER_PATH_BIT) append(userPathName(*path));
        if ((which & XR_INPUT_SOURCE_LOCALIZED_NAME_INTERACTION_PROFILE_BIT) &&
            s.profile != XR_NULL_PATH)
            append(profileName(*pathString(rt, s.profile)));
        if (which & XR_INPUT_SOURCE_LOCALIZED_NAME_COMPONENT_BIT) append(componentName(*path));
        return twoCallString(name, bufferCapacityInput, bufferCountOutput, buffer);
    });
}

/// Records the vibration (control API, capture) for each hand the action is bound to;
/// XR_ERROR_ACTION_TYPE_MISMATCH for an action that is not a vibration output;
/// XR_ERROR_ACTIONSET_NOT_ATTACHED, XR_ERROR_PATH_UNSUPPORTED as for the states.
XrResult xrApplyHapticFeedback(XrSession session, const XrHapticActionInfo* hapticActionInfo,
                               const XrHapticBaseHeader* hapticFeedback) {
    if (hapticFeedback->type != XR_TYPE_HAPTIC_VIBRATION) return XR_ERROR_VALIDATION_FAILURE;
    const auto* v = reinterpret_cast<const XrHapticVibration*>(hapticFeedback);
    return recordHaptic(session, *hapticActionInfo, v->amplitude, v->duration, v->frequency);
}

/// Records a stop (amplitude 0, duration 0); errors as xrApplyHapticFeedback.
XrResult xrStopHapticFeedback(XrSession session, const XrHapticActionInfo* hapticActionInfo) {
    return recordHaptic(session, *hapticActionInfo, 0.0f, 0, XR_FREQUENCY_UNSPECIFIED);
}

}  // namespace kizamu::xrsim
