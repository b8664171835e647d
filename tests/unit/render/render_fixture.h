// SPDX-License-Identifier: Apache-2.0
/// @file render_fixture.h
/// @brief Test helpers for the renderer: an off-screen context per test, the source tree's
/// shaders, and pixel measures.
#pragma once

#include "render/gl_context.h"
#include "render/image.h"
#include "render/shader_program.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <memory>

namespace kizamu::test {

/// A surfaceless EGL context current for the test (Mesa's llvmpipe where there is no GPU).
class RenderTest : public ::testing::Test {
protected:
    void SetUp() override {
        // llvmpipe's rasteriser threads: two keep the tests from crowding a shared machine.
        setenv("LP_NUM_THREADS", "2", /*overwrite=*/0);
        context = render::GlContext::createOffscreen();
    }
    void TearDown() override { context.reset(); }

    render::ShaderLibrary shaders() const {
        return render::ShaderLibrary(KIZAMU_SOURCE_SHADER_DIR);
    }

    std::unique_ptr<render::GlContext> context;
};

/// Whether two pixels' RGB differ by more than `tolerance` in some channel.
inline bool differs(const glm::u8vec4& a, const glm::u8vec4& b, int tolerance) {
    for (int c = 0; c < 3; ++c)
        if (std::abs(int(a[c]) - int(b[c])) > tolerance) return true;
    return false;
}

/// How many pixels of `image` differ from `colour` by more than `tolerance`.
inline std::size_t countNot(const render::Image& image, const glm::u8vec4& colour, int tolerance) {
    std::size_t n = 0;
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x)
            n += differs(image.at(x, y), colour, tolerance) ? 1 : 0;
    return n;
}

/// How many pixels of two images of the same size differ by more than `tolerance`.
inline std::size_t countDiffering(const render::Image& a, const render::Image& b, int tolerance) {
    std::size_t n = 0;
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x)
            n += differs(a.at(x, y), b.at(x, y), tolerance) ? 1 : 0;
    return n;
}

/// The RenderSettings background as the 8-bit value the framebuffer holds.
inline glm::u8vec4 backgroundOf(const glm::vec3& srgb) {
    return glm::u8vec4(glm::u8vec3(glm::round(srgb * 255.0f)), 255);
}

}  // namespace kizamu::test
