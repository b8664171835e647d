// SPDX-License-Identifier: Apache-2.0
/// @file gl_objects.cpp
/// @brief Swapchain textures in the application's GL context (libepoxy resolves the entry points
/// for whichever context, EGL or GLX, is current).
#include "sim/openxr/gl_objects.h"

#include <epoxy/egl.h>
#include <epoxy/gl.h>
#include <epoxy/glx.h>

#include <cstring>

namespace kizamu::xrsim {

bool glContextCurrent() {
    return eglGetCurrentContext() != EGL_NO_CONTEXT || glXGetCurrentContext() != nullptr;
}

std::vector<uint32_t> createTextures(uint32_t count, int64_t internalFormat, uint32_t width,
                                     uint32_t height, uint32_t arraySize, uint32_t mipCount) {
    std::vector<uint32_t> names;
    if (!glContextCurrent()) return names;
    names.resize(count);
    const GLenum target = arraySize > 1 ? GL_TEXTURE_2D_ARRAY : GL_TEXTURE_2D;
    GLint previous = 0;
    glGetIntegerv(arraySize > 1 ? GL_TEXTURE_BINDING_2D_ARRAY : GL_TEXTURE_BINDING_2D, &previous);
    GLint unpackBuffer = 0;
    glGetIntegerv(GL_PIXEL_UNPACK_BUFFER_BINDING, &unpackBuffer);
    glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
    glGenTextures(static_cast<GLsizei>(count), names.data());
    for (uint32_t name : names) {
        glBindTexture(target, name);
        GLsizei w = static_cast<GLsizei>(width), h = static_cast<GLsizei>(height);
        for (uint32_t level = 0; level < mipCount; ++level) {
            if (arraySize > 1)
                glTexImage3D(target, static_cast<GLint>(level), static_cast<GLint>(internalFormat),
                             w, h, static_cast<GLsizei>(arraySize), 0, GL_RGBA, GL_UNSIGNED_BYTE,
                             nullptr);
            else
                glTexImage2D(target, static_cast<GLint>(level), static_cast<GLint>(internalFormat),
                             w, h, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
            w = w > 1 ? w / 2 : 1;
            h = h > 1 ? h / 2 : 1;
        }
        glTexParameteri(target, GL_TEXTURE_MAX_LEVEL, static_cast<GLint>(mipCount - 1));
        glTexParameteri(target, GL_TEXTURE_MIN_FILTER,
                        mipCount > 1 ? GL_LINEAR_MIPMAP_LINEAR : GL_LINEAR);
        glTexParameteri(target, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    }
    glBindTexture(target, static_cast<GLuint>(previous));
    glBindBuffer(GL_PIXEL_UNPACK_BUFFER, static_cast<GLuint>(unpackBuffer));
    return names;
}

void deleteTextures(std::vector<uint32_t>& textures) {
    if (!textures.empty() && glContextCurrent())
        glDeleteTextures(static_cast<GLsizei>(textures.size()), textures.data());
    textures.clear();
}

void readTexture(uint32_t texture, bool isArray, uint32_t layer, int x, int y, int width,
                 int height, std::vector<unsigned char>& rgba) {
    const auto rowBytes = static_cast<size_t>(width) * 4;
    rgba.assign(rowBytes * static_cast<size_t>(height), 0);
    if (!glContextCurrent()) return;
    GLint readFbo = 0, packBuffer = 0, packAlignment = 4, packRowLength = 0, packSkipRows = 0,
          packSkipPixels = 0;
    glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &readFbo);
    glGetIntegerv(GL_PIXEL_PACK_BUFFER_BINDING, &packBuffer);
    glGetIntegerv(GL_PACK_ALIGNMENT, &packAlignment);
    glGetIntegerv(GL_PACK_ROW_LENGTH, &packRowLength);
    glGetIntegerv(GL_PACK_SKIP_ROWS, &packSkipRows);
    glGetIntegerv(GL_PACK_SKIP_PIXELS, &packSkipPixels);

    GLuint fbo = 0;
    glGenFramebuffers(1, &fbo);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo);
    if (isArray)
        glFramebufferTextureLayer(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, texture, 0,
                                  static_cast<GLint>(layer));
    else
        glFramebufferTexture2D(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, texture,
                               0);
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glPixelStorei(GL_PACK_ROW_LENGTH, 0);
    glPixelStorei(GL_PACK_SKIP_ROWS, 0);
    glPixelStorei(GL_PACK_SKIP_PIXELS, 0);
    std::vector<unsigned char> bottomUp(rgba.size());
    glReadPixels(x, y, width, height, GL_RGBA, GL_UNSIGNED_BYTE, bottomUp.data());
    for (int row = 0; row < height; ++row)
        std::memcpy(&rgba[static_cast<size_t>(row) * rowBytes],
                    &bottomUp[static_cast<size_t>(height - 1 - row) * rowBytes], rowBytes);

    glBindFramebuffer(GL_READ_FRAMEBUFFER, static_cast<GLuint>(readFbo));
    glDeleteFramebuffers(1, &fbo);
    glBindBuffer(GL_PIXEL_PACK_BUFFER, static_cast<GLuint>(packBuffer));
    glPixelStorei(GL_PACK_ALIGNMENT, packAlignment);
    glPixelStorei(GL_PACK_ROW_LENGTH, packRowLength);
    glPixelStorei(GL_PACK_SKIP_ROWS, packSkipRows);
    glPixelStorei(GL_PACK_SKIP_PIXELS, packSkipPixels);
}

}  // namespace kizamu::xrsim
