// SPDX-License-Identifier: Apache-2.0
/// @file surface_points.cpp
/// @brief Projection, random surface points, walks and crease detection.
#include "tests/support/surface_points.h"

#include <glm/geometric.hpp>

#include <cmath>
#include <random>

namespace kizamu::adf {

glm::dvec3 sourceGradient(const DistanceSource& source, const glm::dvec3& p, double step) {
    glm::dvec3 g;
    for (int a = 0; a < 3; ++a) {
        glm::dvec3 e(0.0);
        e[a] = step;
        g[a] = (source.distance(p + e) - source.distance(p - e)) / (2.0 * step);
    }
    return g;
}

glm::dvec3 projectToSurface(const DistanceSource& source, glm::dvec3 p, double step, double tolerance) {
    for (int i = 0; i < 32; ++i) {
        const double d = source.distance(p);
        if (std::abs(d) < tolerance) break;
        const glm::dvec3 g = sourceGradient(source, p, step);
        const double g2 = glm::dot(g, g);
        if (g2 < 1e-12) break;
        p -= g * (d / g2);
    }
    return p;
}

std::vector<glm::dvec3> randomSurfacePoints(const DistanceSource& source, const BoxWorld& box,
                                            std::size_t count, uint64_t seed, double step) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<glm::dvec3> out;
    out.reserve(count);
    while (out.size() < count) {
        const glm::dvec3 p = box.min + (box.max - box.min) * glm::dvec3(u(rng), u(rng), u(rng));
        const glm::dvec3 q = projectToSurface(source, p, step, step * 1e-3);
        if (box.contains(q) && std::abs(source.distance(q)) < step * 1e-2) out.push_back(q);
    }
    return out;
}

std::vector<glm::dvec3> surfaceWalk(const DistanceSource& source, glm::dvec3 start, std::size_t count,
                                    double stepLength, uint64_t seed, double step) {
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> turn(0.0, 0.05);
    std::vector<glm::dvec3> out;
    out.reserve(count);
    glm::dvec3 p = projectToSurface(source, start, step, step * 1e-3);
    glm::dvec3 dir(1.0, 0.3, 0.1);
    for (std::size_t i = 0; i < count; ++i) {
        out.push_back(p);
        const glm::dvec3 n = glm::normalize(sourceGradient(source, p, step));
        dir += glm::dvec3(turn(rng), turn(rng), turn(rng));
        dir -= n * glm::dot(dir, n);  // stay in the tangent plane
        if (glm::length(dir) < 1e-9) dir = glm::cross(n, glm::dvec3(0.3, 0.5, 0.8));
        dir = glm::normalize(dir);
        p = projectToSurface(source, p + dir * stepLength, step, step * 1e-3);
    }
    return out;
}

bool nearCrease(const DistanceSource& source, const glm::dvec3& p, double radius) {
    // Any two of the nine gradients, not just each against the centre's: across a kink of 40°
    // each side is only 20° from the gradient on the sheet between them.
    const double step = radius * 0.25;
    glm::dvec3 g[9];
    for (int c = 0; c < 9; ++c) {
        const glm::dvec3 o = c == 8 ? glm::dvec3(0.0)
                                    : glm::dvec3((c & 1) ? radius : -radius, (c & 2) ? radius : -radius, (c & 4) ? radius : -radius);
        g[c] = sourceGradient(source, p + o, step);
        const double l = glm::length(g[c]);
        if (l < 0.95) return true;  // a kink also shows as a finite-difference gradient shorter than 1
        g[c] /= l;
    }
    for (int a = 0; a < 9; ++a)
        for (int b = a + 1; b < 9; ++b)
            if (glm::dot(g[a], g[b]) < 0.866) return true;
    return false;
}

}  // namespace kizamu::adf
