// SPDX-License-Identifier: Apache-2.0
/// @file gl_objects.h
/// @brief The GL side of swapchains: textures made and deleted in the application's context,
/// and the read-back of a submitted sub-image.
///
/// Threading: GL calls on the calling thread, in the context current there (the application's,
/// as XR_KHR_opengl_enable requires at xrCreateSwapchain, xrEndFrame and xrDestroySession).
/// Every binding and pixel-store state changed is restored. Errors: none are reported; with no
/// context current nothing is done.
#pragma once

#include <cstdint>
#include <vector>

namespace kizamu::xrsim {

/// Whether a GL context (EGL or GLX) is current on this thread.
bool glContextCurrent();

/// Makes `count` textures of `internalFormat` (GL_SRGB8_ALPHA8 or GL_RGBA8), `width` x `height`
/// with `mipCount` levels: GL_TEXTURE_2D, or GL_TEXTURE_2D_ARRAY of `arraySize` layers when
/// arraySize > 1. Returns their names; empty with no context. Memory: the driver's storage.
std::vector<uint32_t> createTextures(uint32_t count, int64_t internalFormat, uint32_t width,
                                     uint32_t height, uint32_t arraySize, uint32_t mipCount);

/// Deletes `textures` when a context is current (else they go with their context) and clears it.
void deleteTextures(std::vector<uint32_t>& textures);

/// Reads the rectangle (x, y from the image's bottom-left, `width` x `height` pixels) of layer
/// `layer` of `texture` as RGBA8 into `rgba`, top row first. `isArray`: a GL_TEXTURE_2D_ARRAY.
/// Complexity: one glReadPixels. Memory: resizes `rgba` to width*height*4.
void readTexture(uint32_t texture, bool isArray, uint32_t layer, int x, int y, int width,
                 int height, std::vector<unsigned char>& rgba);

}  // namespace kizamu::xrsim
