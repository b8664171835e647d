// SPDX-License-Identifier: Apache-2.0
/// @file loader_negotiation.h
/// @brief The loader/runtime negotiation interface of the OpenXR loader specification
/// (XR_LOADER_VERSION_1_0), which the Debian 1.0.20 headers do not ship.
///
/// Declared from the specification's text (structures, constants and the one function a runtime
/// exports). Used by negotiate.cpp only; the loader calls the function once per process, before
/// any other call, on whatever thread creates the first instance.
#pragma once

#include <openxr/openxr.h>

#include <cstddef>
#include <cstdint>

extern "C" {

/// Version of the loader/runtime interface this runtime speaks.
#define XR_CURRENT_LOADER_RUNTIME_VERSION 1
/// Current version of XrNegotiateLoaderInfo.
#define XR_LOADER_INFO_STRUCT_VERSION 1
/// Current version of XrNegotiateRuntimeRequest.
#define XR_RUNTIME_INFO_STRUCT_VERSION 1

/// Tags of the loader interface structures.
typedef enum XrLoaderInterfaceStructs {
    XR_LOADER_INTERFACE_STRUCT_UNINTIALIZED = 0,
    XR_LOADER_INTERFACE_STRUCT_LOADER_INFO = 1,
    XR_LOADER_INTERFACE_STRUCT_API_LAYER_REQUEST = 2,
    XR_LOADER_INTERFACE_STRUCT_RUNTIME_REQUEST = 3,
    XR_LOADER_INTERFACE_STRUCT_API_LAYER_CREATE_INFO = 4,
    XR_LOADER_INTERFACE_STRUCT_API_LAYER_NEXT_INFO = 5,
    XR_LOADER_INTERFACE_STRUCTS_MAX_ENUM = 0x7FFFFFFF
} XrLoaderInterfaceStructs;

/// What the loader supports (input).
typedef struct XrNegotiateLoaderInfo {
    XrLoaderInterfaceStructs structType;  ///< XR_LOADER_INTERFACE_STRUCT_LOADER_INFO
    uint32_t structVersion;               ///< XR_LOADER_INFO_STRUCT_VERSION
    size_t structSize;                    ///< sizeof(XrNegotiateLoaderInfo)
    uint32_t minInterfaceVersion;
    uint32_t maxInterfaceVersion;
    XrVersion minApiVersion;
    XrVersion maxApiVersion;
} XrNegotiateLoaderInfo;

/// What the runtime chose (output).
typedef struct XrNegotiateRuntimeRequest {
    XrLoaderInterfaceStructs structType;  ///< XR_LOADER_INTERFACE_STRUCT_RUNTIME_REQUEST
    uint32_t structVersion;               ///< XR_RUNTIME_INFO_STRUCT_VERSION
    size_t structSize;                    ///< sizeof(XrNegotiateRuntimeRequest)
    uint32_t runtimeInterfaceVersion;
    XrVersion runtimeApiVersion;
    PFN_xrGetInstanceProcAddr getInstanceProcAddr;
} XrNegotiateRuntimeRequest;

/// The runtime's one exported entry point: checks the loader's ranges and hands back the
/// runtime's xrGetInstanceProcAddr. XR_ERROR_INITIALIZATION_FAILED on any mismatch.
__attribute__((visibility("default"))) XrResult xrNegotiateLoaderRuntimeInterface(
    const XrNegotiateLoaderInfo* loaderInfo, XrNegotiateRuntimeRequest* runtimeRequest);

}  // extern "C"
