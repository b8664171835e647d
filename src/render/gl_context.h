// SPDX-License-Identifier: Apache-2.0
/// @file gl_context.h
/// @brief An off-screen OpenGL 3.3+ core context: EGL on Mesa's surfaceless platform, or on an
/// EGL device (EGL_EXT_platform_device, as NVIDIA's driver offers) where that is missing.
///
/// Needs no display, no window system and no GPU: with no GPU Mesa renders on CPU threads
/// (llvmpipe; `LP_NUM_THREADS` bounds how many). There is no default framebuffer; draw into a
/// `Framebuffer` (framebuffer.h). GL entry points come from libepoxy, which resolves them for
/// whichever context is current.
///
/// Threading: a context is current on the thread that created it (or last called
/// `makeCurrent`); every GL object made while it is current belongs to it, and GL calls on that
/// thread only. One context per renderer thread.
#pragma once

#include <memory>
#include <string>

namespace kizamu::render {

/// Which EGL platform provides the display.
enum class EglPlatform {
    Auto,         ///< $KIZAMU_EGL_PLATFORM ("surfaceless" or "device") when set; else surfaceless
                  ///< where the library has it, else the first EGL device that gives a context
    Surfaceless,  ///< EGL_MESA_platform_surfaceless
    Device,       ///< EGL_EXT_platform_device: the devices in the order EGL lists them
};

/// An EGL display plus a GL core context on it, current on the creating thread.
/// Owned by one thread (unique_ptr); not thread-safe; move-only by pointer.
class GlContext {
public:
    /// Opens an off-screen EGL display on `platform`, creates a GL core context of at least 3.3
    /// and makes it current on this thread with no surface.
    /// @throw std::runtime_error, one line, when EGL, the platform, a GL 3.3 core context or
    ///        surfaceless make-current is unavailable (e.g. "EGL: neither the surfaceless
    ///        platform nor EGL devices are available: install Mesa's EGL (libegl-mesa0) ...").
    /// Complexity: driver start-up (milliseconds). Threading: makes it current on the caller.
    /// Memory: the driver's context state.
    static std::unique_ptr<GlContext> createOffscreen(EglPlatform platform = EglPlatform::Auto);

    GlContext(const GlContext&) = delete;
    GlContext& operator=(const GlContext&) = delete;
    /// Destroys the context and releases the display; the GL objects made in it go with it.
    ~GlContext();

    /// Makes the context current on the calling thread (surfaceless).
    /// @throw std::runtime_error when EGL refuses.
    void makeCurrent();
    /// GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)".
    std::string renderer() const;
    /// GL_VERSION, e.g. "4.5 (Core Profile) Mesa 22.3.6".
    std::string version() const;
    /// The platform the display came from: Surfaceless or Device.
    EglPlatform platform() const { return mPlatform; }

private:
    GlContext() = default;
    void* mDisplay = nullptr;  ///< EGLDisplay
    void* mContext = nullptr;  ///< EGLContext
    EglPlatform mPlatform = EglPlatform::Surfaceless;
};

}  // namespace kizamu::render
