// SPDX-License-Identifier: Apache-2.0
/// @file negotiate.cpp
/// @brief The loader/runtime negotiation and the runtime's xrGetInstanceProcAddr, which hands
/// out every function the runtime implements.
#include "sim/openxr/entry_points.h"
#include "sim/openxr/loader_negotiation.h"
#include "sim/openxr/runtime_state.h"

#include <cstring>

namespace kizamu::xrsim {
namespace {

template <class F>
PFN_xrVoidFunction fn(F* f) {
    return reinterpret_cast<PFN_xrVoidFunction>(f);
}

struct ProcEntry {
    const char* name;
    PFN_xrVoidFunction function;
    const char* extension;  ///< nullptr: core
};

const ProcEntry kProcs[] = {
    {"xrGetInstanceProcAddr", fn(&xrGetInstanceProcAddr), nullptr},
    {"xrEnumerateApiLayerProperties", fn(&xrEnumerateApiLayerProperties), nullptr},
    {"xrEnumerateInstanceExtensionProperties", fn(&xrEnumerateInstanceExtensionProperties),
     nullptr},
    {"xrCreateInstance", fn(&xrCreateInstance), nullptr},
    {"xrDestroyInstance", fn(&xrDestroyInstance), nullptr},
    {"xrGetInstanceProperties", fn(&xrGetInstanceProperties), nullptr},
    {"xrPollEvent", fn(&xrPollEvent), nullptr},
    {"xrResultToString", fn(&xrResultToString), nullptr},
    {"xrStructureTypeToString", fn(&xrStructureTypeToString), nullptr},
    {"xrStringToPath", fn(&xrStringToPath), nullptr},
    {"xrPathToString", fn(&xrPathToString), nullptr},
    {"xrGetSystem", fn(&xrGetSystem), nullptr},
    {"xrGetSystemProperties", fn(&xrGetSystemProperties), nullptr},
    {"xrEnumerateEnvironmentBlendModes", fn(&xrEnumerateEnvironmentBlendModes), nullptr},
    {"xrEnumerateViewConfigurations", fn(&xrEnumerateViewConfigurations), nullptr},
    {"xrGetViewConfigurationProperties", fn(&xrGetViewConfigurationProperties), nullptr},
    {"xrEnumerateViewConfigurationViews", fn(&xrEnumerateViewConfigurationViews), nullptr},
    {"xrGetOpenGLGraphicsRequirementsKHR", fn(&xrGetOpenGLGraphicsRequirementsKHR), kExtOpenGl},
    {"xrCreateSession", fn(&xrCreateSession), nullptr},
    {"xrDestroySession", fn(&xrDestroySession), nullptr},
    {"xrBeginSession", fn(&xrBeginSession), nullptr},
    {"xrEndSession", fn(&xrEndSession), nullptr},
    {"xrRequestExitSession", fn(&xrRequestExitSession), nullptr},
    {"xrWaitFrame", fn(&xrWaitFrame), nullptr},
    {"xrBeginFrame", fn(&xrBeginFrame), nullptr},
    {"xrEndFrame", fn(&xrEndFrame), nullptr},
    {"xrEnumerateReferenceSpaces", fn(&xrEnumerateReferenceSpaces), nullptr},
    {"xrCreateReferenceSpace", fn(&xrCreateReferenceSpace), nullptr},
    {"xrGetReferenceSpaceBoundsRect", fn(&xrGetReferenceSpaceBoundsRect), nullptr},
    {"xrCreateActionSpace", fn(&xrCreateActionSpace), nullptr},
    {"xrLocateSpace", fn(&xrLocateSpace), nullptr},
    {"xrDestroySpace", fn(&xrDestroySpace), nullptr},
    {"xrLocateViews", fn(&xrLocateViews), nullptr},
    {"xrEnumerateSwapchainFormats", fn(&xrEnumerateSwapchainFormats), nullptr},
    {"xrCreateSwapchain", fn(&xrCreateSwapchain), nullptr},
    {"xrDestroySwapchain", fn(&xrDestroySwapchain), nullptr},
    {"xrEnumerateSwapchainImages", fn(&xrEnumerateSwapchainImages), nullptr},
    {"xrAcquireSwapchainImage", fn(&xrAcquireSwapchainImage), nullptr},
    {"xrWaitSwapchainImage", fn(&xrWaitSwapchainImage), nullptr},
    {"xrReleaseSwapchainImage", fn(&xrReleaseSwapchainImage), nullptr},
    {"xrCreateActionSet", fn(&xrCreateActionSet), nullptr},
    {"xrDestroyActionSet", fn(&xrDestroyActionSet), nullptr},
    {"xrCreateAction", fn(&xrCreateAction), nullptr},
    {"xrDestroyAction", fn(&xrDestroyAction), nullptr},
    {"xrSuggestInteractionProfileBindings", fn(&xrSuggestInteractionProfileBindings), nullptr},
    {"xrAttachSessionActionSets", fn(&xrAttachSessionActionSets), nullptr},
    {"xrGetCurrentInteractionProfile", fn(&xrGetCurrentInteractionProfile), nullptr},
    {"xrGetActionStateBoolean", fn(&xrGetActionStateBoolean), nullptr},
    {"xrGetActionStateFloat", fn(&xrGetActionStateFloat), nullptr},
    {"xrGetActionStateVector2f", fn(&xrGetActionStateVector2f), nullptr},
    {"xrGetActionStatePose", fn(&xrGetActionStatePose), nullptr},
    {"xrSyncActions", fn(&xrSyncActions), nullptr},
    {"xrEnumerateBoundSourcesForAction", fn(&xrEnumerateBoundSourcesForAction), nullptr},
    {"xrGetInputSourceLocalizedName", fn(&xrGetInputSourceLocalizedName), nullptr},
    {"xrApplyHapticFeedback", fn(&xrApplyHapticFeedback), nullptr},
    {"xrStopHapticFeedback", fn(&xrStopHapticFeedback), nullptr},
    {"xrSetInputDeviceActiveEXT", fn(&xrSetInputDeviceActiveEXT), kExtAutomation},
    {"xrSetInputDeviceStateBoolEXT", fn(&xrSetInputDeviceStateBoolEXT), kExtAutomation},
    {"xrSetInputDeviceStateFloatEXT", fn(&xrSetInputDeviceStateFloatEXT), kExtAutomation},
    {"xrSetInputDeviceStateVector2fEXT", fn(&xrSetInputDeviceStateVector2fEXT), kExtAutomation},
    {"xrSetInputDeviceLocationEXT", fn(&xrSetInputDeviceLocationEXT), kExtAutomation},
};

/// The functions that may be queried with XR_NULL_HANDLE for the instance.
bool isGlobalFunction(const char* name) {
    return std::strcmp(name, "xrEnumerateInstanceExtensionProperties") == 0 ||
           std::strcmp(name, "xrEnumerateApiLayerProperties") == 0 ||
           std::strcmp(name, "xrCreateInstance") == 0;
}

}  // namespace

/// XR_ERROR_HANDLE_INVALID for a dead instance, or for XR_NULL_HANDLE and a function other than
/// the three global ones; XR_ERROR_FUNCTION_UNSUPPORTED (and a null *function) for an unknown
/// name or an extension function whose extension the instance did not enable.
XrResult xrGetInstanceProcAddr(XrInstance instance, const char* name,
                               PFN_xrVoidFunction* function) {
    *function = nullptr;
    Runtime& rt = runtime();
    std::lock_guard lock(rt.mutex);
    const InstanceObject* inst = nullptr;
    if (instance == XR_NULL_HANDLE) {
        if (!isGlobalFunction(name) && std::strcmp(name, "xrGetInstanceProcAddr") != 0)
            return XR_ERROR_HANDLE_INVALID;
    } else if ((inst = rt.find<InstanceObject>(instance)) == nullptr) {
        return XR_ERROR_HANDLE_INVALID;
    }
    for (const ProcEntry& e : kProcs) {
        if (std::strcmp(e.name, name) != 0) continue;
        if (e.extension != nullptr && (inst == nullptr || !inst->extensions.count(e.extension)))
            return XR_ERROR_FUNCTION_UNSUPPORTED;
        *function = e.function;
        return XR_SUCCESS;
    }
    return XR_ERROR_FUNCTION_UNSUPPORTED;
}

}  // namespace kizamu::xrsim

extern "C" XrResult xrNegotiateLoaderRuntimeInterface(const XrNegotiateLoaderInfo* loaderInfo,
                                                      XrNegotiateRuntimeRequest* runtimeRequest) {
    if (loaderInfo == nullptr || runtimeRequest == nullptr ||
        loaderInfo->structType != XR_LOADER_INTERFACE_STRUCT_LOADER_INFO ||
        loaderInfo->structVersion != XR_LOADER_INFO_STRUCT_VERSION ||
        loaderInfo->structSize != sizeof(XrNegotiateLoaderInfo) ||
        runtimeRequest->structType != XR_LOADER_INTERFACE_STRUCT_RUNTIME_REQUEST ||
        runtimeRequest->structVersion != XR_RUNTIME_INFO_STRUCT_VERSION ||
        runtimeRequest->structSize != sizeof(XrNegotiateRuntimeRequest))
        return XR_ERROR_INITIALIZATION_FAILED;
    if (loaderInfo->minInterfaceVersion > XR_CURRENT_LOADER_RUNTIME_VERSION ||
        loaderInfo->maxInterfaceVersion < XR_CURRENT_LOADER_RUNTIME_VERSION)
        return XR_ERROR_INITIALIZATION_FAILED;
    // The runtime speaks OpenXR 1.0 (patch ignored).
    const XrVersion api = XR_MAKE_VERSION(1, 0, 0);
    if (XR_MAKE_VERSION(XR_VERSION_MAJOR(loaderInfo->minApiVersion),
                        XR_VERSION_MINOR(loaderInfo->minApiVersion), 0) > api ||
        XR_MAKE_VERSION(XR_VERSION_MAJOR(loaderInfo->maxApiVersion),
                        XR_VERSION_MINOR(loaderInfo->maxApiVersion), 0) < api)
        return XR_ERROR_INITIALIZATION_FAILED;
    runtimeRequest->runtimeInterfaceVersion = XR_CURRENT_LOADER_RUNTIME_VERSION;
    runtimeRequest->runtimeApiVersion = XR_CURRENT_API_VERSION;
    runtimeRequest->getInstanceProcAddr = &kizamu::xrsim::xrGetInstanceProcAddr;
    return XR_SUCCESS;
}
