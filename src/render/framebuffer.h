// SPDX-License-Identifier: Apache-2.0
/// @file framebuffer.h
/// @brief An off-screen render target: a multisampled colour + depth framebuffer object,
/// resolved into a single-sampled one that is read back as RGBA8.
///
/// Colour is RGBA8 and holds sRGB-encoded values (the shaders encode); depth is 24-bit.
/// Threading: GL objects of the context current at construction; use them on its thread only.
#pragma once

#include "render/image.h"

#include <epoxy/gl.h>

namespace kizamu::render {

/// Owned by the renderer that draws into it; not thread-safe; move-only.
class Framebuffer {
public:
    /// Creates the target. `samples` is clamped to the driver's GL_MAX_SAMPLES; 1 draws straight
    /// into the resolved buffer.
    /// @throw std::runtime_error when the driver reports the framebuffer incomplete.
    /// Complexity: O(width × height × samples) memory set-up. Threading: a current GL context.
    /// Memory: 8 bytes per sample (colour + depth) plus 4 per resolved pixel, on the GL side.
    Framebuffer(int width, int height, int samples);
    Framebuffer(Framebuffer&& other) noexcept;
    Framebuffer& operator=(Framebuffer&& other) noexcept;
    Framebuffer(const Framebuffer&) = delete;
    Framebuffer& operator=(const Framebuffer&) = delete;
    ~Framebuffer();

    /// Binds the target for drawing and sets the viewport to cover it.
    void bind() const;
    /// Resolves the samples and reads the pixels back, top row first (as images are stored).
    /// Complexity: O(pixels); stalls until the GPU has finished drawing.
    Image read() const;

    int width() const { return mWidth; }
    int height() const { return mHeight; }
    int samples() const { return mSamples; }

private:
    void release() noexcept;
    int mWidth = 0, mHeight = 0, mSamples = 1;
    GLuint mDrawFbo = 0;     ///< multisampled, or the resolve target itself when mSamples == 1
    GLuint mResolveFbo = 0;  ///< single-sampled colour, read back
    GLuint mColourMs = 0, mDepth = 0, mColour = 0;  ///< renderbuffers
};

}  // namespace kizamu::render
