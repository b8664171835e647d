// SPDX-License-Identifier: Apache-2.0
/// @file entry_points.h
/// @brief The OpenXR functions the simulated runtime implements, with the specification's
/// signatures, in namespace kizamu::xrsim (hidden symbols: the loader reaches them only through
/// xrGetInstanceProcAddr, negotiate.cpp).
///
/// Each returns the specification's error codes for the rules it enforces (documented where it
/// is defined); structure validity (types, null pointers) is left to the core validation layer.
/// Threading: each takes the runtime's lock (runtime_state.h) for its whole call. GL: the
/// swapchain functions, xrEndFrame and xrDestroySession call GL in the context current on the
/// calling thread.
#pragma once

#include "sim/openxr/xr_headers.h"

namespace kizamu::xrsim {

// negotiate.cpp
XrResult xrGetInstanceProcAddr(XrInstance instance, const char* name, PFN_xrVoidFunction* function);

// instance.cpp
XrResult xrEnumerateApiLayerProperties(uint32_t propertyCapacityInput,
                                       uint32_t* propertyCountOutput,
                                       XrApiLayerProperties* properties);
XrResult xrEnumerateInstanceExtensionProperties(const char* layerName,
                                                uint32_t propertyCapacityInput,
                                                uint32_t* propertyCountOutput,
                                                XrExtensionProperties* properties);
XrResult xrCreateInstance(const XrInstanceCreateInfo* createInfo, XrInstance* instance);
XrResult xrDestroyInstance(XrInstance instance);
XrResult xrGetInstanceProperties(XrInstance instance, XrInstanceProperties* instanceProperties);
XrResult xrPollEvent(XrInstance instance, XrEventDataBuffer* eventData);

// paths.cpp
XrResult xrResultToString(XrInstance instance, XrResult value,
                          char buffer[XR_MAX_RESULT_STRING_SIZE]);
XrResult xrStructureTypeToString(XrInstance instance, XrStructureType value,
                                 char buffer[XR_MAX_STRUCTURE_NAME_SIZE]);
XrResult xrStringToPath(XrInstance instance, const char* pathString, XrPath* path);
XrResult xrPathToString(XrInstance instance, XrPath path, uint32_t bufferCapacityInput,
                        uint32_t* bufferCountOutput, char* buffer);

// system.cpp
XrResult xrGetSystem(XrInstance instance, const XrSystemGetInfo* getInfo, XrSystemId* systemId);
XrResult xrGetSystemProperties(XrInstance instance, XrSystemId systemId,
                               XrSystemProperties* properties);
XrResult xrEnumerateEnvironmentBlendModes(XrInstance instance, XrSystemId systemId,
                                          XrViewConfigurationType viewConfigurationType,
                                          uint32_t environmentBlendModeCapacityInput,
                                          uint32_t* environmentBlendModeCountOutput,
                                          XrEnvironmentBlendMode* environmentBlendModes);
XrResult xrEnumerateViewConfigurations(XrInstance instance, XrSystemId systemId,
                                       uint32_t viewConfigurationTypeCapacityInput,
                                       uint32_t* viewConfigurationTypeCountOutput,
                                       XrViewConfigurationType* viewConfigurationTypes);
XrResult xrGetViewConfigurationProperties(XrInstance instance, XrSystemId systemId,
                                          XrViewConfigurationType viewConfigurationType,
                                          XrViewConfigurationProperties* configurationProperties);
XrResult xrEnumerateViewConfigurationViews(XrInstance instance, XrSystemId systemId,
                                           XrViewConfigurationType viewConfigurationType,
                                           uint32_t viewCapacityInput, uint32_t* viewCountOutput,
                                           XrViewConfigurationView* views);
XrResult xrGetOpenGLGraphicsRequirementsKHR(XrInstance instance, XrSystemId systemId,
                                            XrGraphicsRequirementsOpenGLKHR* graphicsRequirements);

// session.cpp
XrResult xrCreateSession(XrInstance instance, const XrSessionCreateInfo* createInfo,
                         XrSession* session);
XrResult xrDestroySession(XrSession session);
XrResult xrBeginSession(XrSession session, const XrSessionBeginInfo* beginInfo);
XrResult xrEndSession(XrSession session);
XrResult xrRequestExitSession(XrSession session);

// frame.cpp
XrResult xrWaitFrame(XrSession session, const XrFrameWaitInfo* frameWaitInfo,
                     XrFrameState* frameState);
XrResult xrBeginFrame(XrSession session, const XrFrameBeginInfo* frameBeginInfo);
XrResult xrEndFrame(XrSession session, const XrFrameEndInfo* frameEndInfo);

// spaces.cpp
XrResult xrEnumerateReferenceSpaces(XrSession session, uint32_t spaceCapacityInput,
                                    uint32_t* spaceCountOutput, XrReferenceSpaceType* spaces);
XrResult xrCreateReferenceSpace(XrSession session, const XrReferenceSpaceCreateInfo* createInfo,
                                XrSpace* space);
XrResult xrGetReferenceSpaceBoundsRect(XrSession session, XrReferenceSpaceType referenceSpaceType,
                                       XrExtent2Df* bounds);
XrResult xrCreateActionSpace(XrSession session, const XrActionSpaceCreateInfo* createInfo,
                             XrSpace* space);
XrResult xrLocateSpace(XrSpace space, XrSpace baseSpace, XrTime time, XrSpaceLocation* location);
XrResult xrDestroySpace(XrSpace space);
XrResult xrLocateViews(XrSession session, const XrViewLocateInfo* viewLocateInfo,
                       XrViewState* viewState, uint32_t viewCapacityInput,
                       uint32_t* viewCountOutput, XrView* views);

// swapchain.cpp
XrResult xrEnumerateSwapchainFormats(XrSession session, uint32_t formatCapacityInput,
                                     uint32_t* formatCountOutput, int64_t* formats);
XrResult xrCreateSwapchain(XrSession session, const XrSwapchainCreateInfo* createInfo,
                           XrSwapchain* swapchain);
XrResult xrDestroySwapchain(XrSwapchain swapchain);
XrResult xrEnumerateSwapchainImages(XrSwapchain swapchain, uint32_t imageCapacityInput,
                                    uint32_t* imageCountOutput, XrSwapchainImageBaseHeader* images);
XrResult xrAcquireSwapchainImage(XrSwapchain swapchain,
                                 const XrSwapchainImageAcquireInfo* acquireInfo, uint32_t* index);
XrResult xrWaitSwapchainImage(XrSwapchain swapchain, const XrSwapchainImageWaitInfo* waitInfo);
XrResult xrReleaseSwapchainImage(XrSwapchain swapchain,
                                 const XrSwapchainImageReleaseInfo* releaseInfo);

// actions.cpp
XrResult xrCreateActionSet(XrInstance instance, const XrActionSetCreateInfo* createInfo,
                           XrActionSet* actionSet);
XrResult xrDestroyActionSet(XrActionSet actionSet);
XrResult xrCreateAction(XrActionSet actionSet, const XrActionCreateInfo* createInfo,
                        XrAction* action);
XrResult xrDestroyAction(XrAction action);
XrResult xrSuggestInteractionProfileBindings(
    XrInstance instance, const XrInteractionProfileSuggestedBinding* suggestedBindings);
XrResult xrAttachSessionActionSets(XrSession session,
                                   const XrSessionActionSetsAttachInfo* attachInfo);
XrResult xrGetCurrentInteractionProfile(XrSession session, XrPath topLevelUserPath,
                                        XrInteractionProfileState* interactionProfile);
XrResult xrGetActionStateBoolean(XrSession session, const XrActionStateGetInfo* getInfo,
                                 XrActionStateBoolean* state);
XrResult xrGetActionStateFloat(XrSession session, const XrActionStateGetInfo* getInfo,
                               XrActionStateFloat* state);
XrResult xrGetActionStateVector2f(XrSession session, const XrActionStateGetInfo* getInfo,
                                  XrActionStateVector2f* state);
XrResult xrGetActionStatePose(XrSession session, const XrActionStateGetInfo* getInfo,
                              XrActionStatePose* state);
XrResult xrSyncActions(XrSession session, const XrActionsSyncInfo* syncInfo);
XrResult xrEnumerateBoundSourcesForAction(XrSession session,
                                          const XrBoundSourcesForActionEnumerateInfo* enumerateInfo,
                                          uint32_t sourceCapacityInput, uint32_t* sourceCountOutput,
                                          XrPath* sources);
XrResult xrGetInputSourceLocalizedName(XrSession session,
                                       const XrInputSourceLocalizedNameGetInfo* getInfo,
                                       uint32_t bufferCapacityInput, uint32_t* bufferCountOutput,
                                       char* buffer);
XrResult xrApplyHapticFeedback(XrSession session, const XrHapticActionInfo* hapticActionInfo,
                               const XrHapticBaseHeader* hapticFeedback);
XrResult xrStopHapticFeedback(XrSession session, const XrHapticActionInfo* hapticActionInfo);

// automation.cpp
XrResult xrSetInputDeviceActiveEXT(XrSession session, XrPath interactionProfile,
                                   XrPath topLevelPath, XrBool32 isActive);
XrResult xrSetInputDeviceStateBoolEXT(XrSession session, XrPath topLevelPath,
                                      XrPath inputSourcePath, XrBool32 state);
XrResult xrSetInputDeviceStateFloatEXT(XrSession session, XrPath topLevelPath,
                                       XrPath inputSourcePath, float state);
XrResult xrSetInputDeviceStateVector2fEXT(XrSession session, XrPath topLevelPath,
                                          XrPath inputSourcePath, XrVector2f state);
XrResult xrSetInputDeviceLocationEXT(XrSession session, XrPath topLevelPath, XrPath inputSourcePath,
                                     XrSpace space, XrPosef pose);

}  // namespace kizamu::xrsim
