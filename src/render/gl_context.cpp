// SPDX-License-Identifier: Apache-2.0
/// @file gl_context.cpp
/// @brief EGL off-screen display and GL core context (see gl_context.h).
#include "render/gl_context.h"

#include <epoxy/egl.h>
#include <epoxy/gl.h>

#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

namespace kizamu::render {

namespace {

std::string eglErrorSuffix() {
    char code[32];
    std::snprintf(code, sizeof code, " (EGL error 0x%04x)", unsigned(eglGetError()));
    return code;
}

[[noreturn]] void fail(const std::string& what) {
    throw std::runtime_error("EGL: " + what + eglErrorSuffix());
}

bool hasExtension(const char* list, const std::string& name) {
    if (!list) return false;
    const std::string all = std::string(" ") + list + " ";
    return all.find(" " + name + " ") != std::string::npos;
}

/// The platform Auto resolves to, from $KIZAMU_EGL_PLATFORM and the client extensions.
EglPlatform resolve(EglPlatform asked, const char* client) {
    if (asked != EglPlatform::Auto) return asked;
    if (const char* env = std::getenv("KIZAMU_EGL_PLATFORM"); env && *env) {
        const std::string e = env;
        if (e == "surfaceless") return EglPlatform::Surfaceless;
        if (e == "device") return EglPlatform::Device;
        throw std::runtime_error("EGL: KIZAMU_EGL_PLATFORM is '" + e +
                                 "'; expected 'surfaceless' or 'device'");
    }
    if (hasExtension(client, "EGL_MESA_platform_surfaceless")) return EglPlatform::Surfaceless;
    if (hasExtension(client, "EGL_EXT_platform_device")) return EglPlatform::Device;
    throw std::runtime_error(
        "EGL: neither the surfaceless platform (EGL_MESA_platform_surfaceless) nor EGL devices "
        "(EGL_EXT_platform_device) are available: install Mesa's EGL (libegl-mesa0) and "
        "drivers (libgl1-mesa-dri)");
}

/// Creates a GL 3.3 core context on an initialised display and makes it current without a
/// surface; EGL_NO_CONTEXT (with the reason in `why`) when the display cannot.
EGLContext makeContext(EGLDisplay display, std::string& why) {
    if (!hasExtension(eglQueryString(display, EGL_EXTENSIONS), "EGL_KHR_surfaceless_context")) {
        why =
            "the display cannot make a context current without a surface "
            "(EGL_KHR_surfaceless_context)";
        return EGL_NO_CONTEXT;
    }
    if (!eglBindAPI(EGL_OPENGL_API)) {
        why = "no desktop OpenGL API" + eglErrorSuffix();
        return EGL_NO_CONTEXT;
    }
    // No surface is ever made: the config only has to render OpenGL.
    const EGLint configAttribs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE, 0,
                                    EGL_NONE};
    EGLConfig config = nullptr;
    EGLint configs = 0;
    if (!eglChooseConfig(display, configAttribs, &config, 1, &configs) || configs < 1) {
        why = "no config that renders OpenGL" + eglErrorSuffix();
        return EGL_NO_CONTEXT;
    }
    const EGLint contextAttribs[] = {EGL_CONTEXT_MAJOR_VERSION,
                                     3,
                                     EGL_CONTEXT_MINOR_VERSION,
                                     3,
                                     EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                     EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                     EGL_NONE};
    EGLContext context = eglCreateContext(display, config, EGL_NO_CONTEXT, contextAttribs);
    if (context == EGL_NO_CONTEXT) {
        why = "no OpenGL 3.3 core context" + eglErrorSuffix();
        return EGL_NO_CONTEXT;
    }
    if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) {
        why = "cannot make the context current" + eglErrorSuffix();
        eglDestroyContext(display, context);
        return EGL_NO_CONTEXT;
    }
    return context;
}

}  // namespace

std::unique_ptr<GlContext> GlContext::createOffscreen(EglPlatform platform) {
    // Client extensions (EGL 1.5 or EGL_EXT_client_extensions): the platforms this libEGL has.
    const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    const EglPlatform chosen = resolve(platform, client);
    std::unique_ptr<GlContext> c(new GlContext);
    c->mPlatform = chosen;
    std::string why;
    if (chosen == EglPlatform::Surfaceless) {
        if (!hasExtension(client, "EGL_MESA_platform_surfaceless"))
            throw std::runtime_error(
                "EGL: no surfaceless platform (EGL_MESA_platform_surfaceless): install Mesa's "
                "EGL (libegl-mesa0) and drivers (libgl1-mesa-dri)");
        EGLDisplay display =
            eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
        if (display == EGL_NO_DISPLAY) fail("no surfaceless display");
        if (!eglInitialize(display, nullptr, nullptr))
            fail("cannot initialise the surfaceless display");
        c->mDisplay = display;
        c->mContext = makeContext(display, why);
        if (c->mContext == EGL_NO_CONTEXT)
            throw std::runtime_error("EGL: surfaceless display: " + why);
        return c;
    }
    if (!hasExtension(client, "EGL_EXT_platform_device") ||
        !hasExtension(client, "EGL_EXT_device_enumeration"))
        throw std::runtime_error(
            "EGL: no EGL devices (EGL_EXT_platform_device, EGL_EXT_device_enumeration)");
    EGLint count = 0;
    if (!eglQueryDevicesEXT(0, nullptr, &count) || count < 1) fail("no EGL devices");
    std::vector<EGLDeviceEXT> devices(static_cast<std::size_t>(count));
    if (!eglQueryDevicesEXT(count, devices.data(), &count)) fail("cannot list the EGL devices");
    // The first device that gives a context wins; each failure is kept for the message.
    std::string reasons;
    for (EGLint i = 0; i < count; ++i) {
        EGLDisplay display =
            eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, devices[std::size_t(i)], nullptr);
        if (display == EGL_NO_DISPLAY || !eglInitialize(display, nullptr, nullptr)) {
            reasons += "; device " + std::to_string(i) + ": cannot initialise" + eglErrorSuffix();
            continue;
        }
        EGLContext context = makeContext(display, why);
        if (context != EGL_NO_CONTEXT) {
            c->mDisplay = display;
            c->mContext = context;
            return c;
        }
        reasons += "; device " + std::to_string(i) + ": " + why;
    }
    throw std::runtime_error("EGL: no EGL device gives an OpenGL 3.3 core context" + reasons);
}

GlContext::~GlContext() {
    if (mDisplay) {
        EGLDisplay display = mDisplay;
        if (eglGetCurrentContext() == mContext)
            eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        if (mContext) eglDestroyContext(display, mContext);
        // EGL keeps one display per platform and native display in a process, shared by every
        // context on it: terminating it here would pull it from under another live GlContext,
        // so it stays initialised until the process ends.
    }
}

void GlContext::makeCurrent() {
    if (!eglMakeCurrent(mDisplay, EGL_NO_SURFACE, EGL_NO_SURFACE, mContext))
        fail("cannot make the context current");
}

std::string GlContext::renderer() const {
    const auto* s = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    return s ? s : "";
}

std::string GlContext::version() const {
    const auto* s = reinterpret_cast<const char*>(glGetString(GL_VERSION));
    return s ? s : "";
}

}  // namespace kizamu::render
