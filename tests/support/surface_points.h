// SPDX-License-Identifier: Apache-2.0
/// @file surface_points.h
/// @brief Reference points on and near a source's surface, for tests and benchmarks.
///
/// Random points projected onto the zero set, coherent walks along it (the haptic thread's
/// access pattern), and a crease detector: trilinear cells cannot follow a gradient jump, so
/// accuracy figures treat points near creases separately. Deterministic for a given seed.
/// Not for the haptic thread (allocates). Any thread.
///
/// Part of kizamu_testing (tests/support/), the library that tests and benchmarks link: nothing
/// in src/ uses these. They keep namespace kizamu::adf because they are queries of an
/// adf::DistanceSource, the way the core's own are.
#pragma once

#include "adf/distance_source.h"
#include "adf/generate.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <vector>

namespace kizamu::adf {

/// Central-difference gradient of `source` at `p` with step `step` (m).
glm::dvec3 sourceGradient(const DistanceSource& source, const glm::dvec3& p, double step);

/// Newton steps p -= d * grad / |grad|^2 until |d| < tolerance (m) or 32 steps.
glm::dvec3 projectToSurface(const DistanceSource& source, glm::dvec3 p, double step, double tolerance);

/// `count` points on the surface, from uniform random points in `box` projected onto it.
/// Points whose projection leaves `box` are redrawn.
std::vector<glm::dvec3> randomSurfacePoints(const DistanceSource& source, const BoxWorld& box,
                                            std::size_t count, uint64_t seed, double step);

/// A walk of `count` points along the surface, each `stepLength` (m) from the last, turning
/// slowly and re-projected onto the surface after every step, starting at `start`.
std::vector<glm::dvec3> surfaceWalk(const DistanceSource& source, glm::dvec3 start, std::size_t count,
                                    double stepLength, uint64_t seed, double step);

/// True when the source's gradient turns by more than ~30 degrees within `radius` of `p` (any
/// two of the gradients at p and the 8 corners of the cube of half-width `radius` about it):
/// a box edge, a CSG seam, a medial sheet, where trilinear cells cannot be within ε̂.
bool nearCrease(const DistanceSource& source, const glm::dvec3& p, double radius);

}  // namespace kizamu::adf
