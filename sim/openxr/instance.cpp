// SPDX-License-Identifier: Apache-2.0
/// @file instance.cpp
/// @brief Extensions, instance creation and destruction, instance properties, the event queue.
#include "sim/openxr/entry_points.h"
#include "sim/openxr/runtime_state.h"

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <vector>

namespace kizamu::xrsim {
namespace {

struct Extension {
    const char* name;
    uint32_t version;
};
const Extension kExtensions[] = {{kExtOpenGl, 10}, {kExtAutomation, 3}};

}  // namespace

XrResult xrEnumerateApiLayerProperties(uint32_t propertyCapacityInput,
                                       uint32_t* propertyCountOutput, XrApiLayerProperties*) {
    return twoCall(propertyCapacityInput, propertyCountOutput, 0, [](uint32_t) {});
}

/// XR_ERROR_API_LAYER_NOT_PRESENT for a layer name (the runtime has no layers).
XrResult xrEnumerateInstanceExtensionProperties(const char* layerName,
                                                uint32_t propertyCapacityInput,
                                                uint32_t* propertyCountOutput,
                                                XrExtensionProperties* properties) {
    if (layerName != nullptr && layerName[0] != '\0') return XR_ERROR_API_LAYER_NOT_PRESENT;
    const auto count = static_cast<uint32_t>(std::size(kExtensions));
    return twoCall(propertyCapacityInput, propertyCountOutput, count, [&](uint32_t i) {
        std::strncpy(properties[i].extensionName, kExtensions[i].name, XR_MAX_EXTENSION_NAME_SIZE);
        properties[i].extensionVersion = kExtensions[i].version;
    });
}

/// XR_ERROR_EXTENSION_NOT_PRESENT for an extension the runtime lacks;
/// XR_ERROR_API_VERSION_UNSUPPORTED for an API version other than 1.0.
XrResult xrCreateInstance(const XrInstanceCreateInfo* createInfo, XrInstance* instance) {
    Runtime& rt = runtime();
    std::lock_guard lock(rt.mutex);
    const XrVersion v = createInfo->applicationInfo.apiVersion;
    if (XR_VERSION_MAJOR(v) != 1 || XR_VERSION_MINOR(v) != 0)
        return XR_ERROR_API_VERSION_UNSUPPORTED;
    InstanceObject inst;
    for (uint32_t i = 0; i < createInfo->enabledExtensionCount; ++i) {
        const char* name = createInfo->enabledExtensionNames[i];
        bool known = false;
        for (const Extension& e : kExtensions) known = known || std::strcmp(e.name, name) == 0;
        if (!known) return XR_ERROR_EXTENSION_NOT_PRESENT;
        inst.extensions.insert(name);
    }
    const char* capture = std::getenv("KIZAMU_XRSIM_CAPTURE");
    rt.captureDir = capture != nullptr ? capture : "";
    auto frameFromEnvironment = [](const char* name) -> uint64_t {
        const char* value = std::getenv(name);
        return value != nullptr ? std::strtoull(value, nullptr, 10) : 0;
    };
    rt.stopAtFrame = frameFromEnvironment("KIZAMU_XRSIM_STOP_AT_FRAME");
    rt.loseAtFrame = frameFromEnvironment("KIZAMU_XRSIM_LOSE_AT_FRAME");
    *instance = rt.add<XrInstance>(std::move(inst));
    return XR_SUCCESS;
}

/// Destroys the instance with its session, action sets and actions.
XrResult xrDestroyInstance(XrInstance instance) {
    Runtime& rt = runtime();
    std::lock_guard lock(rt.mutex);
    InstanceObject* inst = rt.find<InstanceObject>(instance);
    if (inst == nullptr) return XR_ERROR_HANDLE_INVALID;
    if (inst->session != XR_NULL_HANDLE) destroySession(rt, inst->session);
    std::vector<uint64_t> sets;
    for (const auto& [id, object] : rt.objects)
        if (const auto* s = std::get_if<ActionSetObject>(&object); s && s->instance == instance)
            sets.push_back(id);
    for (auto it = rt.objects.begin(); it != rt.objects.end();) {
        const auto* a = std::get_if<ActionObject>(&it->second);
        const bool owned =
            a != nullptr &&
            std::find(sets.begin(), sets.end(), reinterpret_cast<uint64_t>(a->set)) != sets.end();
        it = owned ? rt.objects.erase(it) : std::next(it);
    }
    for (uint64_t id : sets) rt.objects.erase(id);
    rt.erase(instance);
    return XR_SUCCESS;
}

XrResult xrGetInstanceProperties(XrInstance instance, XrInstanceProperties* instanceProperties) {
    Runtime& rt = runtime();
    std::lock_guard lock(rt.mutex);
    if (rt.find<InstanceObject>(instance) == nullptr) return XR_ERROR_HANDLE_INVALID;
    instanceProperties->runtimeVersion = XR_MAKE_VERSION(0, 1, 0);
    std::strncpy(instanceProperties->runtimeName, "Kizamu simulated runtime",
                 XR_MAX_RUNTIME_NAME_SIZE);
    return XR_SUCCESS;
}

/// XR_EVENT_UNAVAILABLE when the queue is empty.
XrResult xrPollEvent(XrInstance instance, XrEventDataBuffer* eventData) {
    Runtime& rt = runtime();
    std::lock_guard lock(rt.mutex);
    InstanceObject* inst = rt.find<InstanceObject>(instance);
    if (inst == nullptr) return XR_ERROR_HANDLE_INVALID;
    if (inst->events.empty()) return XR_EVENT_UNAVAILABLE;
    *eventData = inst->events.front();
    inst->events.pop_front();
    return XR_SUCCESS;
}

}  // namespace kizamu::xrsim
