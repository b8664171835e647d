// SPDX-License-Identifier: Apache-2.0
/// @file gl_context_test.cpp
/// @brief The off-screen context: GL 3.3+ core on the surfaceless platform and on an EGL device,
/// which render the same picture; a bad platform name is a clear error.
#include "render/gl_context.h"
#include "render/clay_renderer.h"
#include "tests/unit/render/render_fixture.h"
#include "tests/util/icosphere.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <string>

namespace kizamu::render {
namespace {

Image sphereImage() {
    ClayRenderer renderer(ShaderLibrary(KIZAMU_SOURCE_SHADER_DIR));
    renderer.setMesh(test::icosphere(0.1f, 3));
    OrbitCamera camera;
    camera.setView(ViewAxis::Iso);
    camera.frame(glm::vec3(-0.1f), glm::vec3(0.1f), 1.0f);
    return renderer.renderToImage(camera, 96, 96, RenderSettings{});
}

TEST(GlContext, SurfacelessCoreProfile) {
    setenv("LP_NUM_THREADS", "2", 0);
    const auto c = GlContext::createOffscreen(EglPlatform::Surfaceless);
    EXPECT_EQ(c->platform(), EglPlatform::Surfaceless);
    GLint major = 0, minor = 0, mask = 0;
    glGetIntegerv(GL_MAJOR_VERSION, &major);
    glGetIntegerv(GL_MINOR_VERSION, &minor);
    glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &mask);
    EXPECT_GE(major * 10 + minor, 33) << c->version();
    EXPECT_TRUE(mask & GL_CONTEXT_CORE_PROFILE_BIT) << c->version();
    std::printf("GL: %s | %s\n", c->renderer().c_str(), c->version().c_str());
}

TEST(GlContext, DevicePlatformRendersTheSame) {
    setenv("LP_NUM_THREADS", "2", 0);
    Image surfaceless, device;
    {
        const auto c = GlContext::createOffscreen(EglPlatform::Surfaceless);
        surfaceless = sphereImage();
    }
    {
        const auto c = GlContext::createOffscreen(EglPlatform::Device);
        EXPECT_EQ(c->platform(), EglPlatform::Device);
        std::printf("GL on an EGL device: %s\n", c->renderer().c_str());
        device = sphereImage();
    }
    ASSERT_EQ(device.pixels.size(), surfaceless.pixels.size());
    std::size_t off = 0;
    for (int y = 0; y < device.height; ++y)
        for (int x = 0; x < device.width; ++x)
            off += test::differs(device.at(x, y), surfaceless.at(x, y), 2) ? 1 : 0;
    EXPECT_LT(off, 20u);
}

TEST(GlContext, EnvironmentChoosesThePlatform) {
    setenv("KIZAMU_EGL_PLATFORM", "device", 1);
    EXPECT_EQ(GlContext::createOffscreen()->platform(), EglPlatform::Device);
    setenv("KIZAMU_EGL_PLATFORM", "pbuffer", 1);
    try {
        GlContext::createOffscreen();
        ADD_FAILURE() << "accepted KIZAMU_EGL_PLATFORM=pbuffer";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("KIZAMU_EGL_PLATFORM is 'pbuffer'"), std::string::npos)
            << e.what();
    }
    unsetenv("KIZAMU_EGL_PLATFORM");
    EXPECT_EQ(GlContext::createOffscreen()->platform(), EglPlatform::Surfaceless);
}

}  // namespace
}  // namespace kizamu::render
