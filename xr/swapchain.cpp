// SPDX-License-Identifier: Apache-2.0
#include "xr/swapchain.h"

#include "xr/xr_error.h"

#include <algorithm>
#include <stdexcept>

namespace kizamu::xr {

ColourSwapchain::ColourSwapchain(XrInstance instance, XrSession session, int width, int height)
    : mInstance(instance), mSize(width, height) {
    uint32_t count = 0;
    check(instance, xrEnumerateSwapchainFormats(session, 0, &count, nullptr), "xrEnumerateSwapchainFormats");
    std::vector<int64_t> formats(count);
    check(instance, xrEnumerateSwapchainFormats(session, count, &count, formats.data()), "xrEnumerateSwapchainFormats");
    for (const int64_t wanted : {int64_t(GL_SRGB8_ALPHA8), int64_t(GL_RGBA8)}) {
        if (std::find(formats.begin(), formats.end(), wanted) != formats.end()) {
            mFormat = wanted;
            break;
        }
    }
    if (mFormat == 0) throw std::runtime_error("the OpenXR runtime offers no GL_SRGB8_ALPHA8 or GL_RGBA8 swapchain");

    XrSwapchainCreateInfo info{XR_TYPE_SWAPCHAIN_CREATE_INFO};
    info.usageFlags = XR_SWAPCHAIN_USAGE_COLOR_ATTACHMENT_BIT | XR_SWAPCHAIN_USAGE_SAMPLED_BIT;
    info.format = mFormat;
    info.sampleCount = 1;
    info.width = uint32_t(width);
    info.height = uint32_t(height);
    info.faceCount = 1;
    info.arraySize = 1;
    info.mipCount = 1;
    check(instance, xrCreateSwapchain(session, &info, &mSwapchain), "xrCreateSwapchain");

    check(instance, xrEnumerateSwapchainImages(mSwapchain, 0, &count, nullptr), "xrEnumerateSwapchainImages");
    std::vector<XrSwapchainImageOpenGLKHR> images(count, {XR_TYPE_SWAPCHAIN_IMAGE_OPENGL_KHR});
    check(instance,
          xrEnumerateSwapchainImages(mSwapchain, count, &count, reinterpret_cast<XrSwapchainImageBaseHeader*>(images.data())),
          "xrEnumerateSwapchainImages");
    glGenRenderbuffers(1, &mDepth);
    glBindRenderbuffer(GL_RENDERBUFFER, mDepth);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, width, height);
    glBindRenderbuffer(GL_RENDERBUFFER, 0);
    mFramebuffers.resize(count);
    glGenFramebuffers(GLsizei(count), mFramebuffers.data());
    for (uint32_t i = 0; i < count; ++i) {
        glBindFramebuffer(GL_FRAMEBUFFER, mFramebuffers[i]);
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, images[i].image, 0);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, mDepth);
        if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
            glBindFramebuffer(GL_FRAMEBUFFER, 0);
            throw std::runtime_error("an OpenXR swapchain image cannot be drawn into (incomplete framebuffer)");
        }
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

ColourSwapchain::~ColourSwapchain() {
    if (!mFramebuffers.empty()) glDeleteFramebuffers(GLsizei(mFramebuffers.size()), mFramebuffers.data());
    if (mDepth) glDeleteRenderbuffers(1, &mDepth);
    if (mSwapchain != XR_NULL_HANDLE) xrDestroySwapchain(mSwapchain);
}

void ColourSwapchain::acquire() {
    XrSwapchainImageAcquireInfo acquireInfo{XR_TYPE_SWAPCHAIN_IMAGE_ACQUIRE_INFO};
    check(mInstance, xrAcquireSwapchainImage(mSwapchain, &acquireInfo, &mAcquired), "xrAcquireSwapchainImage");
    XrSwapchainImageWaitInfo waitInfo{XR_TYPE_SWAPCHAIN_IMAGE_WAIT_INFO};
    waitInfo.timeout = XR_INFINITE_DURATION;
    check(mInstance, xrWaitSwapchainImage(mSwapchain, &waitInfo), "xrWaitSwapchainImage");
    glBindFramebuffer(GL_FRAMEBUFFER, mFramebuffers[mAcquired]);
    glViewport(0, 0, mSize.x, mSize.y);
}

void ColourSwapchain::release() {
    XrSwapchainImageReleaseInfo releaseInfo{XR_TYPE_SWAPCHAIN_IMAGE_RELEASE_INFO};
    check(mInstance, xrReleaseSwapchainImage(mSwapchain, &releaseInfo), "xrReleaseSwapchainImage");
}

}  // namespace kizamu::xr
