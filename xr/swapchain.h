// SPDX-License-Identifier: Apache-2.0
/// @file swapchain.h
/// @brief One OpenXR colour swapchain of GL textures, each with a framebuffer (and a shared
/// depth buffer) to draw into: acquire, wait, draw, release, in the order the runtime enforces.
///
/// Colour: the first format the runtime offers of GL_SRGB8_ALPHA8 (preferred) and GL_RGBA8.
/// Kizamu's shaders write sRGB-encoded values and GL_FRAMEBUFFER_SRGB stays off, so an sRGB
/// image stores exactly what the desktop shows and the compositor decodes it as sRGB.
/// Threading: the GL context's thread. Not copyable.
#pragma once

#include "xr/xr_platform.h"

#include <glm/vec2.hpp>

#include <vector>

namespace kizamu::xr {

class ColourSwapchain {
public:
    /// Creates a width × height swapchain for `session` and a framebuffer per image.
    /// @throw XrFailure when the runtime refuses; std::runtime_error when it offers neither format
    ColourSwapchain(XrInstance instance, XrSession session, int width, int height);
    ~ColourSwapchain();
    ColourSwapchain(const ColourSwapchain&) = delete;
    ColourSwapchain& operator=(const ColourSwapchain&) = delete;

    /// Acquires and waits for the next image and binds its framebuffer (draw and read) with the
    /// viewport over the whole image. @throw XrFailure
    void acquire();
    /// Releases the acquired image (after drawing into it). @throw XrFailure
    void release();

    XrSwapchain handle() const { return mSwapchain; }
    glm::ivec2 size() const { return mSize; }
    int64_t format() const { return mFormat; }
    /// The framebuffer of the image acquired last (a desktop mirror reads it).
    GLuint framebuffer() const { return mFramebuffers[mAcquired]; }

private:
    XrInstance mInstance;
    XrSwapchain mSwapchain = XR_NULL_HANDLE;
    glm::ivec2 mSize;
    int64_t mFormat = 0;
    std::vector<GLuint> mFramebuffers;
    GLuint mDepth = 0;
    uint32_t mAcquired = 0;
};

}  // namespace kizamu::xr
