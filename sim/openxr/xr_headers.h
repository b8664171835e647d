// SPDX-License-Identifier: Apache-2.0
/// @file xr_headers.h
/// @brief The OpenXR headers as the runtime includes them: core plus the OpenGL types of
/// XR_KHR_opengl_enable (no window-system types: the runtime never reads the Xlib binding's
/// fields, it only finds the binding in the `next` chain by its type).
#pragma once

#define XR_USE_GRAPHICS_API_OPENGL
// The runtime implements these functions; it must never call the loader's.
#define XR_NO_PROTOTYPES
#include <openxr/openxr.h>
#include <openxr/openxr_platform.h>
