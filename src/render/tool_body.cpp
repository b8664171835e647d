// SPDX-License-Identifier: Apache-2.0
#include "render/tool_body.h"

#include <cmath>
#include <vector>

namespace kizamu::render {

namespace {

constexpr int kAround = 16, kRings = 8;

void quad(mesh::MeshBuffers& m, uint32_t a, uint32_t b, uint32_t c, uint32_t d) {
    for (const uint32_t i : {a, b, c, a, c, d}) m.indices.push_back(i);
}

/// A surface of revolution about Z: rings of (radius, z) from bottom to top, kAround segments.
mesh::MeshBuffers revolve(const std::vector<glm::vec2>& profile) {
    mesh::MeshBuffers m;
    for (const glm::vec2& rz : profile) {
        for (int i = 0; i < kAround; ++i) {
            const float t = 2.0f * float(M_PI) * float(i) / float(kAround);
            m.positions.push_back({rz.x * std::cos(t), rz.x * std::sin(t), rz.y});
        }
    }
    for (uint32_t r = 0; r + 1 < profile.size(); ++r) {
        for (uint32_t i = 0; i < kAround; ++i) {
            const uint32_t j = (i + 1) % kAround;
            quad(m, r * kAround + i, r * kAround + j, (r + 1) * kAround + j, (r + 1) * kAround + i);
        }
    }
    return m;
}

}  // namespace

mesh::MeshBuffers unitToolBody(ToolBody body) {
    switch (body) {
    case ToolBody::None: return {};
    case ToolBody::Sphere: {
        std::vector<glm::vec2> profile;
        for (int r = 0; r <= kRings; ++r) {
            const float phi = float(M_PI) * (float(r) / float(kRings) - 0.5f);
            profile.push_back({std::cos(phi), std::sin(phi)});
        }
        return revolve(profile);
    }
    case ToolBody::Cylinder: return revolve({{0.0f, -1.0f}, {1.0f, -1.0f}, {1.0f, 1.0f}, {0.0f, 1.0f}});
    case ToolBody::Cube: {
        mesh::MeshBuffers m;
        for (int i = 0; i < 8; ++i) m.positions.push_back({i & 1 ? 1.0f : -1.0f, i & 2 ? 1.0f : -1.0f, i & 4 ? 1.0f : -1.0f});
        quad(m, 0, 2, 3, 1);  // -z
        quad(m, 4, 5, 7, 6);  // +z
        quad(m, 0, 1, 5, 4);  // -y
        quad(m, 2, 6, 7, 3);  // +y
        quad(m, 0, 4, 6, 2);  // -x
        quad(m, 1, 3, 7, 5);  // +x
        return m;
    }
    }
    return {};
}

}  // namespace kizamu::render
