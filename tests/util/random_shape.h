// SPDX-License-Identifier: Apache-2.0
/// @file random_shape.h
/// @brief Test helper: random CSG shapes for the mesher's property tests.
#pragma once

#include "adf/distance_source.h"

#include <glm/gtc/quaternion.hpp>

#include <random>

namespace kizamu::test {

/// A random CSG tree of 1 to 6 primitives inside the domain, with sharp and blended seams and
/// thin parts that drive cells to the maximum level with several sheets.
inline adf::SourcePtr randomShape(std::mt19937_64& rng) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    using namespace adf;
    auto primitive = [&]() -> SourcePtr {
        const double s = 0.03 + 0.17 * u(rng);
        SourcePtr p;
        switch (int(u(rng) * 6)) {
        case 0: p = makeSphere(s); break;
        case 1: p = makeBox({s, s * (0.1 + u(rng)), s * (0.05 + u(rng))}); break;
        case 2: p = makeCapsule({-s, 0, 0}, {s, 0, 0}, s * (0.02 + 0.3 * u(rng))); break;
        case 3: p = makeCylinder(s * 0.4, s); break;
        case 4: p = makeTorus(s, s * (0.05 + 0.3 * u(rng))); break;
        default: p = makeRoundedBox({s, s * 0.6, s * 0.3}, s * 0.1); break;
        }
        const glm::dquat q = glm::normalize(glm::dquat(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5));
        return makeTransformed(p, {0.3 + 0.4 * u(rng), 0.3 + 0.4 * u(rng), 0.3 + 0.4 * u(rng)}, q);
    };
    SourcePtr shape = primitive();
    const int n = 1 + int(u(rng) * 6);
    for (int i = 1; i < n; ++i) {
        const double r = u(rng);
        const CsgOp op = r < 0.5 ? CsgOp::Union : (r < 0.85 ? CsgOp::Difference : CsgOp::Intersection);
        shape = makeCsg(op, shape, primitive(), u(rng) < 0.3 ? 0.02 * u(rng) : 0.0);
    }
    return shape;
}

}  // namespace kizamu::test
