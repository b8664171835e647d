// SPDX-License-Identifier: Apache-2.0
/// @file stroke.cpp
/// @brief Validation of strokes and shapes, and a shape's distance source.
#include "sculpt/stroke.h"

#include "adf/test_part.h"
#include "sculpt/swept_tool.h"

#include <glm/common.hpp>

#include <cmath>
#include <stdexcept>
#include <string>

namespace kizamu::sculpt {

void Shape::validate() const {
    if (!std::isfinite(centre.x + centre.y + centre.z)) throw std::invalid_argument("a shape's centre must be finite");
    if (kind == Kind::Box && (!(glm::min(halfSize.x, glm::min(halfSize.y, halfSize.z)) > 0.0) || !(rounding >= 0.0) ||
                              !std::isfinite(halfSize.x + halfSize.y + halfSize.z + rounding)))
        throw std::invalid_argument("a box needs positive half sizes and a non-negative rounding");
    if (kind == Kind::Sphere && (!(radius > 0.0) || !std::isfinite(radius))) throw std::invalid_argument("a sphere needs a positive radius");
}

void validate(const Stroke& s) {
    s.tool.validate();
    validateStroke(s.tool, s.samples);
    if (s.bezier && s.samples.size() != 4) throw std::invalid_argument("bezier must be four control points [p0, p1, p2, p3]");
    const StrokeConstraints& c = s.constraints;
    auto length = [](double v, const char* what) {
        if (!(v >= 0.0) || !std::isfinite(v)) throw std::invalid_argument(std::string(what) + " must be a non-negative length in metres");
    };
    if (c.followOffset && !std::isfinite(*c.followOffset)) throw std::invalid_argument("follow offset must be a finite length in metres");
    if (c.depthLimit) {
        if (s.tool.op != ToolOp::Carve) throw std::invalid_argument("depth limits carving; use height for add and build");
        length(*c.depthLimit, "depth");
    }
    if (c.heightLimit) {
        if (s.tool.op != ToolOp::Add && s.tool.op != ToolOp::Build)
            throw std::invalid_argument("height limits add and build; use depth for carving");
        length(*c.heightLimit, "height");
    }
    for (const Shape& m : c.masks) m.validate();
    for (const Shape& k : c.keepOut) k.validate();
}

adf::SourcePtr Shape::source(const adf::Domain& domain) const {
    switch (kind) {
    case Kind::Box:
        return adf::makeTranslated(rounding > 0.0 ? adf::makeRoundedBox(halfSize, rounding) : adf::makeBox(halfSize), centre);
    case Kind::Sphere: return adf::makeTranslated(adf::makeSphere(radius), centre);
    case Kind::TestPart: return adf::makeTestPart(domain);
    }
    return nullptr;
}

}  // namespace kizamu::sculpt
