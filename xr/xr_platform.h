// SPDX-License-Identifier: Apache-2.0
/// @file xr_platform.h
/// @brief The OpenXR platform header with the OpenGL-on-Xlib binding Kizamu uses (GLFW's X11
/// build gives a GLX context): the X11 and GLX types openxr_platform.h needs, first.
#pragma once

#include <epoxy/gl.h>
#include <epoxy/glx.h>
#include <X11/Xlib.h>

#define XR_USE_PLATFORM_XLIB
#define XR_USE_GRAPHICS_API_OPENGL
#include <openxr/openxr.h>
#include <openxr/openxr_platform.h>
