// SPDX-License-Identifier: Apache-2.0
/// @file exact_predicates.h
/// @brief Exact orientation signs of points given in doubles: the untangling pass's answers
/// to "which side", "on the plane" and "on the line", which rounding must never flip.
///
/// Each sign is first computed in doubles with Shewchuk's forward error bound (Adaptive
/// Precision Floating-Point Arithmetic and Fast Robust Geometric Predicates, 1997: orient2d
/// and orient3d, bound A); only where the result lies inside that bound is it recomputed in
/// exact integers (boost::multiprecision::cpp_int, every coordinate scaled by the power of two
/// of the smallest among them), which is rare off degenerate input. Every finite double converts
/// exactly, so the sign is that of the real determinant of the given points, provided no product
/// of coordinate differences underflows (the filter's bound is relative): true for any float32
/// coordinates, which is what the untangling passes (the smallest product of three differences
/// of floats is about 2^-447, far above double's 2^-1022).
/// Pure functions; any thread.
#pragma once

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace kizamu::mesh::exact {

/// Sign of the determinant |a-d, b-d, c-d|: +1 where d lies below the plane through a, b, c
/// (a, b, c counter-clockwise seen from above), -1 above, 0 on it.
int orient3d(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d);

/// Sign of the determinant |a-c, b-c|: +1 where a, b, c turn counter-clockwise, -1
/// clockwise, 0 collinear.
int orient2d(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c);

}  // namespace kizamu::mesh::exact
