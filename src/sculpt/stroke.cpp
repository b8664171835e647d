// SPDX-License-Identifier: Apache-2.0
/// @file stroke.cpp
/// @brief Validation of strokes and shapes, and a shape's distance source.
#include "sculpt/stroke.h"

#include "adf/adf_source.h"
#include "adf/test_part.h"
#include "sculpt/swept_tool.h"

#include <glm/common.hpp>

#include <cmath>
#include <stdexcept>
#include <string>

namespace kizamu::sculpt {

namespace {

/// LiveRecord's rules. The dwell sum is exact: the Sculptor adds the same values in the same order.
void validateLive(const Stroke& s) {
    const LiveRecord& r = *s.live;
    const std::size_t n = s.samples.size();
    if (s.bezier) throw std::invalid_argument("a live stroke is a polyline: it cannot be a Bezier curve");
    if (r.cuts.empty()) throw std::invalid_argument("a live record needs at least one segment (cuts)");
    if (r.cuts.size() != r.dwells.size())
        throw std::invalid_argument("a live record needs one dwell per cut (" + std::to_string(r.cuts.size()) + " cuts, " +
                                    std::to_string(r.dwells.size()) + " dwells)");
    if (r.cuts.front() < 1) throw std::invalid_argument("a live stroke's first segment must apply a sample (cuts[0] >= 1)");
    for (std::size_t i = 1; i < r.cuts.size(); ++i)
        if (r.cuts[i] < r.cuts[i - 1]) throw std::invalid_argument("a live record's cuts must not decrease");
    if (r.cuts.back() != n)
        throw std::invalid_argument("a live record's last cut must be the number of samples (" + std::to_string(r.cuts.back()) +
                                    " != " + std::to_string(n) + ")");
    double sum = 0.0;
    for (double d : r.dwells) {
        if (!(d >= 0.0) || !std::isfinite(d)) throw std::invalid_argument("a live record's dwells must be finite and >= 0 s");
        sum = sum + d;
    }
    if (sum != s.dwell) throw std::invalid_argument("a live stroke's dwell must be the sum of its segments' dwells");
    if (!r.timesNs.empty()) {
        if (r.timesNs.size() != n) throw std::invalid_argument("a live record needs one time stamp per sample, or none");
        for (std::size_t i = 1; i < n; ++i)
            if (r.timesNs[i] < r.timesNs[i - 1]) throw std::invalid_argument("a live record's time stamps must not decrease");
    }
    if (!r.strengths.empty()) {
        if (r.strengths.size() != n) throw std::invalid_argument("a live record needs one strength per sample, or none");
        for (float v : r.strengths)
            if (!(v >= 0.0f && v <= 1.0f)) throw std::invalid_argument("a live record's strengths must be in [0, 1]");
    }
}

}  // namespace

void Shape::validate() const {
    if (!std::isfinite(centre.x + centre.y + centre.z)) throw std::invalid_argument("a shape's centre must be finite");
    if (kind == Kind::Box && (!(glm::min(halfSize.x, glm::min(halfSize.y, halfSize.z)) > 0.0) || !(rounding >= 0.0) ||
                              !std::isfinite(halfSize.x + halfSize.y + halfSize.z + rounding)))
        throw std::invalid_argument("a box needs positive half sizes and a non-negative rounding");
    if (kind == Kind::Sphere && (!(radius > 0.0) || !std::isfinite(radius))) throw std::invalid_argument("a sphere needs a positive radius");
    if (kind == Kind::File && file.empty() && !clay) throw std::invalid_argument("a file start needs a \"file\" (a .kza path)");
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
    auto simple = [](const std::vector<Shape>& shapes, const char* what) {
        for (const Shape& sh : shapes)
            if (sh.kind == Shape::Kind::File)
                throw std::invalid_argument(std::string(what) + " are simple solids (box, sphere, test-part): a file is a start shape only");
    };
    simple(c.masks, "masks");
    simple(c.keepOut, "keep-out regions");
    if (s.live) validateLive(s);
}

adf::SourcePtr Shape::source(const adf::Domain& domain) const {
    switch (kind) {
    case Kind::Box:
        return adf::makeTranslated(rounding > 0.0 ? adf::makeRoundedBox(halfSize, rounding) : adf::makeBox(halfSize), centre);
    case Kind::Sphere: return adf::makeTranslated(adf::makeSphere(radius), centre);
    case Kind::TestPart: return adf::makeTestPart(domain);
    case Kind::File:
        if (!clay) throw std::logic_error("the clay of the file start '" + file + "' is not loaded (startAdf loads it)");
        return adf::makeAdfSource(clay);
    }
    return nullptr;
}

}  // namespace kizamu::sculpt
