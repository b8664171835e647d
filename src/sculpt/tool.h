// SPDX-License-Identifier: Apache-2.0
/// @file tool.h
/// @brief Sculpting tools: a shape, a size, a strength and what they do to the clay.
///
/// SI units everywhere (metres). A tool is posed by a ToolSample (position and orientation, the
/// tool's local frame to world); its shape is centred on the pose, the cylinder and the chisel
/// along local z. Plain values; any thread.
#pragma once

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_precision.hpp>
#include <glm/vec3.hpp>

#include <cstdint>
#include <string>

namespace kizamu::sculpt {

enum class ToolShape : uint8_t { Sphere, Cube, Cylinder };
/// Carve and add are CSG with the swept tool. The others change the clay gradually, by a weight
/// that falls smoothly from the tool's core (1) to its boundary (0): build and heat gun offset
/// the field (raise, melt); smooth moves it toward its local average (sandpaper: ridges wear,
/// valleys fill); flatten moves it toward the plane through the stroke's first pose, normal to
/// that pose's z axis. Paint leaves the field alone and colours the surface inside the tool
/// (sculpt/paint.h), with the same kind of weight times the strength (its opacity).
enum class ToolOp : uint8_t { Carve, Add, Build, HeatGun, Smooth, Flatten, Paint };

struct Tool {
    ToolShape shape = ToolShape::Sphere;
    ToolOp op = ToolOp::Carve;
    double radius = 0.01;      ///< m: sphere radius, half edge of the cube, cylinder radius
    double halfLength = 0.01;  ///< m: half length of the cylinder along local z
    double strength = 1.0;     ///< (0, 1]: how much of the tool bites (it shrinks by (1 - s) * radius); paint: opacity
    double amount = 0.0;       ///< m, build: how far one stroke raises the surface at the tool's core
    double rate = 0.0;         ///< m/s, heat gun: how fast the surface melts at the core while it dwells
    glm::u8vec3 colour{255, 255, 255};  ///< paint: sRGB colour laid on the surface

    /// Largest distance from the pose to a point of the tool, m.
    double boundingRadius() const;
    /// Smallest dimension, m (what generation must resolve: DistanceSource::featureSize).
    double smallestDimension() const;
    /// Throws std::invalid_argument with a readable message if a size is not positive and finite
    /// or the strength is outside (0, 1].
    void validate() const;
};

/// A tool pose at one instant of a stroke.
struct ToolSample {
    glm::dvec3 position{0.0};                ///< m, world
    glm::dquat orientation{1.0, 0.0, 0.0, 0.0};  ///< tool frame to world, unit
};

/// Signed distance (m, negative inside) from `local` (tool frame, m) to the tool, with its
/// strength applied. Exact for the sphere and the cylinder, exact outside and a lower bound
/// inside the cube (the usual box distance). Convex in `local` for every shape.
double toolDistance(const Tool& tool, const glm::dvec3& local);
/// toolDistance of a sphere (inline: a swept sphere's loops run it per point). Strength shrinks
/// the tool uniformly inward, by (1 - strength) * radius.
inline double sphereDistance(const Tool& tool, const glm::dvec3& local) {
    const double shrink = (1.0 - tool.strength) * tool.radius;
    return glm::length(local) - tool.radius + shrink;
}

/// The gradual tools' weight at depth `inside` (m, positive inside the tool): 0 at the tool's
/// boundary (and outside), 1 at depth `core` (m) and deeper, a smoothstep between, so what a
/// tool does grows continuously as it arrives.
double toolWeight(double inside, double core);

const char* shapeName(ToolShape s);
const char* opName(ToolOp o);
/// Parses "sphere" / "cube" / "cylinder" (also "chisel" for the cylinder). Throws
/// std::invalid_argument naming the accepted words otherwise.
ToolShape parseShape(const std::string& s);
/// Parses "carve" / "add" / "build" / "heat-gun" / "smooth" / "flatten" / "paint".
ToolOp parseOp(const std::string& s);

}  // namespace kizamu::sculpt
