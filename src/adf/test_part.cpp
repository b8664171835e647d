// SPDX-License-Identifier: Apache-2.0
/// @file test_part.cpp
/// @brief The fixed test part.
#include "adf/test_part.h"

#include <glm/gtc/quaternion.hpp>

#include <cmath>

namespace kizamu::adf {

SourcePtr makeTestPart(const Domain& domain) {
    const double s = domain.sizeWorld;
    const glm::dvec3 centre = domain.originWorld + glm::dvec3(0.5 * s);
    const double half = 0.3 * s;
    // Cylinders run past the box on both sides so their caps never reach the band.
    const double cylHalf = 0.45 * s, cylR = 0.1 * s;
    const auto cylZ = makeCylinder(cylR, cylHalf);
    const glm::dquat toX = glm::angleAxis(M_PI / 2, glm::dvec3(0, 1, 0));
    const glm::dquat toY = glm::angleAxis(M_PI / 2, glm::dvec3(1, 0, 0));
    SourcePtr part = makeRoundedBox(glm::dvec3(half), 0.05 * s);
    part = makeCsg(CsgOp::Difference, {part, makeTransformed(cylZ, glm::dvec3(0), toX),
                                       makeTransformed(cylZ, glm::dvec3(0), toY), cylZ});
    part = makeCsg(CsgOp::Union, part, makeTranslated(makeSphere(0.15 * s), glm::dvec3(0, 0, half)));
    return makeTranslated(part, centre);
}

Domain testPartDomain(int maxLevel) {
    Domain d;
    d.maxLevel = maxLevel;
    return d;
}

GenerationSettings testPartSettings() { return GenerationSettings{}; }

}  // namespace kizamu::adf
