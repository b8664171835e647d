// SPDX-License-Identifier: Apache-2.0
/// @file camera_test.cpp
/// @brief The orbit camera: axis views as Blender's, framing, projection (no GL).
#include "render/camera.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>

#include <cmath>

namespace kizamu::render {
namespace {

void expectNear(const glm::vec3& a, const glm::vec3& b, float tol = 1e-5f) {
    EXPECT_NEAR(a.x, b.x, tol);
    EXPECT_NEAR(a.y, b.y, tol);
    EXPECT_NEAR(a.z, b.z, tol);
}

/// World direction of the screen's +x (right).
glm::vec3 rightOf(const OrbitCamera& c) {
    return glm::cross(c.forward(), c.up());
}

TEST(OrbitCamera, AxisViewsFollowBlender) {
    OrbitCamera c;
    c.setView(ViewAxis::Front);
    expectNear(c.forward(), {0, 1, 0});
    expectNear(c.up(), {0, 0, 1});
    expectNear(rightOf(c), {1, 0, 0});
    c.setView(ViewAxis::Back);
    expectNear(c.forward(), {0, -1, 0});
    c.setView(ViewAxis::Right);
    expectNear(c.forward(), {-1, 0, 0});
    expectNear(rightOf(c), {0, 1, 0});
    c.setView(ViewAxis::Left);
    expectNear(c.forward(), {1, 0, 0});
    c.setView(ViewAxis::Top);
    expectNear(c.forward(), {0, 0, -1});
    expectNear(c.up(), {0, 1, 0});
    expectNear(rightOf(c), {1, 0, 0});
    c.setView(ViewAxis::Bottom);
    expectNear(c.forward(), {0, 0, 1});
    expectNear(c.up(), {0, -1, 0});
    expectNear(rightOf(c), {1, 0, 0});
    c.setView(ViewAxis::Iso);
    expectNear(c.forward(), -glm::normalize(glm::vec3(1, -1, 1)));
}

TEST(OrbitCamera, NamesRoundTrip) {
    for (ViewAxis v : {ViewAxis::Front, ViewAxis::Back, ViewAxis::Left, ViewAxis::Right,
                       ViewAxis::Top, ViewAxis::Bottom, ViewAxis::Iso})
        EXPECT_EQ(viewAxisOf(nameOf(v)), v);
    EXPECT_FALSE(viewAxisOf("diagonal"));
}

TEST(OrbitCamera, FrameFitsTheBoundingSphere) {
    for (Projection p : {Projection::Perspective, Projection::Orthographic})
        for (float aspect : {0.5f, 1.0f, 2.0f}) {
            OrbitCamera c;
            c.projection = p;
            c.setView(ViewAxis::Iso);
            c.frame({-1, -2, -3}, {3, 2, 1}, aspect, 1.0f);
            expectNear(c.target, {1, 0, -1});
            const float r = std::sqrt(4.f * 4 + 4 * 4 + 4 * 4) / 2;
            // Points on the sphere's silhouette land inside the unit NDC square, touching it.
            const glm::mat4 vp = c.projectionMatrix(aspect) * c.viewMatrix();
            const glm::vec3 right = glm::normalize(rightOf(c)), up = c.up();
            float reach = 0.0f;
            for (const glm::vec3& dir : {right, up, -right, -up}) {
                // Perspective: the tangent point is nearer the eye than the centre.
                glm::vec3 point = c.target + dir * r;
                if (p == Projection::Perspective) {
                    const float d = c.distance, s = r / d;
                    point = c.target + dir * (r * std::sqrt(1 - s * s)) - c.forward() * (r * s);
                }
                const glm::vec4 clip = vp * glm::vec4(point, 1.0f);
                const glm::vec2 ndc = glm::vec2(clip) / clip.w;
                reach = std::max(reach, std::max(std::abs(ndc.x), std::abs(ndc.y)));
            }
            EXPECT_NEAR(reach, 1.0f, 1e-3f) << "aspect " << aspect;
        }
}

TEST(OrbitCamera, OrbitClampsPitch) {
    OrbitCamera c;
    c.orbit(0.3f, 10.0f);
    EXPECT_FLOAT_EQ(c.pitchRad, 1.5707963f);
    c.orbit(0.0f, -20.0f);
    EXPECT_FLOAT_EQ(c.pitchRad, -1.5707963f);
    const float d = c.distance;
    c.zoom(0.5f);
    EXPECT_FLOAT_EQ(c.distance, 0.5f * d);
}

}  // namespace
}  // namespace kizamu::render
