// SPDX-License-Identifier: Apache-2.0
/// @file tool.cpp
/// @brief Tool shapes and their distances.
#include "sculpt/tool.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace kizamu::sculpt {

double Tool::boundingRadius() const {
    switch (shape) {
    case ToolShape::Sphere: return radius;
    case ToolShape::Cube: return radius * std::sqrt(3.0);
    case ToolShape::Cylinder: return std::sqrt(radius * radius + halfLength * halfLength);
    }
    return radius;
}

double Tool::smallestDimension() const {
    const double s = std::max(strength, 1e-3) * radius;
    return shape == ToolShape::Cylinder ? std::min(s, halfLength) : s;
}

void Tool::validate() const {
    auto bad = [](double v) { return !(v > 0.0) || !std::isfinite(v); };
    if (bad(radius)) throw std::invalid_argument("tool radius must be a positive length in metres");
    if (shape == ToolShape::Cylinder && bad(halfLength))
        throw std::invalid_argument("cylinder tool length must be a positive length in metres");
    if (!(strength > 0.0 && strength <= 1.0)) throw std::invalid_argument("tool strength must be in (0, 1]");
    if (op == ToolOp::Build && (bad(amount) || amount > radius))
        throw std::invalid_argument("build needs an amount in metres, positive and at most the radius");
    if (op == ToolOp::HeatGun && bad(rate)) throw std::invalid_argument("the heat gun needs a positive rate in metres per second");
}

double toolDistance(const Tool& tool, const glm::dvec3& q) {
    // Strength shrinks the tool uniformly inward: the same shape, offset by (1 - s) * radius.
    const double shrink = (1.0 - tool.strength) * tool.radius;
    switch (tool.shape) {
    case ToolShape::Sphere: return sphereDistance(tool, q);
    case ToolShape::Cube: {
        const glm::dvec3 d = glm::abs(q) - glm::dvec3(tool.radius);
        return glm::length(glm::max(d, 0.0)) + std::min(std::max(d.x, std::max(d.y, d.z)), 0.0) + shrink;
    }
    case ToolShape::Cylinder: {
        const glm::dvec2 d(std::sqrt(q.x * q.x + q.y * q.y) - tool.radius, std::abs(q.z) - tool.halfLength);
        return glm::length(glm::max(d, 0.0)) + std::min(std::max(d.x, d.y), 0.0) + shrink;
    }
    }
    return 0.0;
}

double toolWeight(double inside, double core) {
    if (!(inside > 0.0)) return 0.0;
    const double t = std::min(1.0, inside / core);
    return t * t * (3.0 - 2.0 * t);
}

const char* shapeName(ToolShape s) {
    switch (s) {
    case ToolShape::Sphere: return "sphere";
    case ToolShape::Cube: return "cube";
    case ToolShape::Cylinder: return "cylinder";
    }
    return "?";
}

const char* opName(ToolOp o) {
    switch (o) {
    case ToolOp::Carve: return "carve";
    case ToolOp::Add: return "add";
    case ToolOp::Build: return "build";
    case ToolOp::HeatGun: return "heat-gun";
    case ToolOp::Smooth: return "smooth";
    case ToolOp::Flatten: return "flatten";
    case ToolOp::Paint: return "paint";
    }
    return "?";
}

ToolShape parseShape(const std::string& s) {
    if (s == "sphere") return ToolShape::Sphere;
    if (s == "cube") return ToolShape::Cube;
    if (s == "cylinder" || s == "chisel") return ToolShape::Cylinder;
    throw std::invalid_argument("unknown tool shape '" + s + "' (sphere, cube, cylinder)");
}

ToolOp parseOp(const std::string& s) {
    if (s == "carve") return ToolOp::Carve;
    if (s == "add") return ToolOp::Add;
    if (s == "build") return ToolOp::Build;
    if (s == "heat-gun") return ToolOp::HeatGun;
    if (s == "smooth") return ToolOp::Smooth;
    if (s == "flatten") return ToolOp::Flatten;
    if (s == "paint") return ToolOp::Paint;
    throw std::invalid_argument("unknown tool operation '" + s + "' (carve, add, build, heat-gun, smooth, flatten, paint)");
}

}  // namespace kizamu::sculpt
