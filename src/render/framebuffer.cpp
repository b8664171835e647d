// SPDX-License-Identifier: Apache-2.0
/// @file framebuffer.cpp
/// @brief Multisampled off-screen target and its read-back (see framebuffer.h).
#include "render/framebuffer.h"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>
#include <utility>

namespace kizamu::render {

namespace {

void checkComplete(const char* which) {
    const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE)
        throw std::runtime_error(std::string("GL: the ") + which +
                                 " framebuffer is incomplete (status 0x" +
                                 [&] {
                                     char hex[16];
                                     std::snprintf(hex, sizeof hex, "%04x", unsigned(status));
                                     return std::string(hex);
                                 }() +
                                 ")");
}

}  // namespace

Framebuffer::Framebuffer(int width, int height, int samples) : mWidth(width), mHeight(height) {
    if (width < 1 || height < 1)
        throw std::runtime_error("GL: a framebuffer needs a positive size");
    GLint maxSamples = 1;
    glGetIntegerv(GL_MAX_SAMPLES, &maxSamples);
    mSamples = std::clamp(samples, 1, std::max(1, int(maxSamples)));

    glGenRenderbuffers(1, &mColour);
    glBindRenderbuffer(GL_RENDERBUFFER, mColour);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
    glGenFramebuffers(1, &mResolveFbo);
    glBindFramebuffer(GL_FRAMEBUFFER, mResolveFbo);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, mColour);

    glGenRenderbuffers(1, &mDepth);
    glBindRenderbuffer(GL_RENDERBUFFER, mDepth);
    if (mSamples > 1) {
        glRenderbufferStorageMultisample(GL_RENDERBUFFER, mSamples, GL_DEPTH_COMPONENT24, width,
                                         height);
        glGenRenderbuffers(1, &mColourMs);
        glBindRenderbuffer(GL_RENDERBUFFER, mColourMs);
        glRenderbufferStorageMultisample(GL_RENDERBUFFER, mSamples, GL_RGBA8, width, height);
        checkComplete("resolve");
        glGenFramebuffers(1, &mDrawFbo);
        glBindFramebuffer(GL_FRAMEBUFFER, mDrawFbo);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, mColourMs);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, mDepth);
        checkComplete("multisampled");
    } else {
        glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, width, height);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, mDepth);
        checkComplete("off-screen");
        mDrawFbo = mResolveFbo;
    }
    glBindRenderbuffer(GL_RENDERBUFFER, 0);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

Framebuffer::Framebuffer(Framebuffer&& other) noexcept {
    *this = std::move(other);
}

Framebuffer& Framebuffer::operator=(Framebuffer&& other) noexcept {
    if (this != &other) {
        release();
        mWidth = other.mWidth;
        mHeight = other.mHeight;
        mSamples = other.mSamples;
        mDrawFbo = std::exchange(other.mDrawFbo, 0);
        mResolveFbo = std::exchange(other.mResolveFbo, 0);
        mColourMs = std::exchange(other.mColourMs, 0);
        mDepth = std::exchange(other.mDepth, 0);
        mColour = std::exchange(other.mColour, 0);
    }
    return *this;
}

Framebuffer::~Framebuffer() {
    release();
}

void Framebuffer::release() noexcept {
    if (mDrawFbo && mDrawFbo != mResolveFbo) glDeleteFramebuffers(1, &mDrawFbo);
    if (mResolveFbo) glDeleteFramebuffers(1, &mResolveFbo);
    for (GLuint* rb : {&mColourMs, &mDepth, &mColour})
        if (*rb) glDeleteRenderbuffers(1, rb);
    mDrawFbo = mResolveFbo = mColourMs = mDepth = mColour = 0;
}

void Framebuffer::bind() const {
    glBindFramebuffer(GL_FRAMEBUFFER, mDrawFbo);
    glViewport(0, 0, mWidth, mHeight);
}

Image Framebuffer::read() const {
    if (mDrawFbo != mResolveFbo) {
        glBindFramebuffer(GL_READ_FRAMEBUFFER, mDrawFbo);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, mResolveFbo);
        glBlitFramebuffer(0, 0, mWidth, mHeight, 0, 0, mWidth, mHeight, GL_COLOR_BUFFER_BIT,
                          GL_NEAREST);
    }
    glBindFramebuffer(GL_READ_FRAMEBUFFER, mResolveFbo);
    Image image(mWidth, mHeight);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, mWidth, mHeight, GL_RGBA, GL_UNSIGNED_BYTE, image.pixels.data());
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    // GL's rows run bottom to top; images store the top row first.
    const std::size_t row = std::size_t(mWidth) * 4;
    std::vector<uint8_t> tmp(row);
    for (int y = 0; y < mHeight / 2; ++y) {
        uint8_t* a = image.pixels.data() + std::size_t(y) * row;
        uint8_t* b = image.pixels.data() + std::size_t(mHeight - 1 - y) * row;
        std::memcpy(tmp.data(), a, row);
        std::memcpy(a, b, row);
        std::memcpy(b, tmp.data(), row);
    }
    return image;
}

}  // namespace kizamu::render
