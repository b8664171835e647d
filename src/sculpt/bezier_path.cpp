// SPDX-License-Identifier: Apache-2.0
/// @file bezier_path.cpp
/// @brief Adaptive flattening of cubic Bezier tool paths.
#include "sculpt/bezier_path.h"

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace kizamu::sculpt {

namespace {

constexpr int kMaxDepth = 16;

/// Appends the end parameters of the pieces of [t0, t1] (whose controls are `c`), in order.
void flatten(const BezierControls& c, double t0, double t1, double tolerance, int depth, std::vector<double>& out) {
    const bool flat = std::max(distanceToSegment(c[1], c[0], c[3]), distanceToSegment(c[2], c[0], c[3])) <= tolerance;
    if (flat || depth == kMaxDepth) {
        out.push_back(t1);
        return;
    }
    // de Casteljau at the midpoint: the two halves' control points.
    const glm::dvec3 ab = 0.5 * (c[0] + c[1]), bc = 0.5 * (c[1] + c[2]), cd = 0.5 * (c[2] + c[3]);
    const glm::dvec3 abc = 0.5 * (ab + bc), bcd = 0.5 * (bc + cd), mid = 0.5 * (abc + bcd);
    const double tm = 0.5 * (t0 + t1);
    flatten({c[0], ab, abc, mid}, t0, tm, tolerance, depth + 1, out);
    flatten({mid, bcd, cd, c[3]}, tm, t1, tolerance, depth + 1, out);
}

}  // namespace

double distanceToSegment(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b) {
    const glm::dvec3 ab = b - a;
    const double len2 = glm::dot(ab, ab);
    const double t = len2 > 0.0 ? std::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
    return glm::length(p - (a + t * ab));
}

glm::dvec3 bezierPoint(const BezierControls& c, double t) {
    const double s = 1.0 - t;
    return s * s * s * c[0] + 3.0 * s * s * t * c[1] + 3.0 * s * t * t * c[2] + t * t * t * c[3];
}

std::vector<double> flattenBezier(const BezierControls& c, double tolerance) {
    if (!(tolerance > 0.0)) throw std::invalid_argument("bezier flattening needs a positive tolerance");
    std::vector<double> t{0.0};
    flatten(c, 0.0, 1.0, tolerance, 0, t);
    return t;
}

std::vector<ToolSample> bezierSamples(const std::vector<ToolSample>& controls, double tolerance) {
    if (controls.size() != 4) throw std::invalid_argument("a bezier path has four control points");
    const BezierControls c{controls[0].position, controls[1].position, controls[2].position, controls[3].position};
    std::vector<double> ts = flattenBezier(c, tolerance);
    const bool turning = controls[1].orientation != controls[0].orientation ||
                         controls[2].orientation != controls[0].orientation || controls[3].orientation != controls[0].orientation;
    if (turning) {
        // The orientation is interpolated per third: its knots must be poses, or a straight
        // curve (two poses) would lose the turn through the middle controls.
        for (double knot : {1.0 / 3.0, 2.0 / 3.0})
            if (std::find(ts.begin(), ts.end(), knot) == ts.end()) ts.insert(std::upper_bound(ts.begin(), ts.end(), knot), knot);
    }
    std::vector<ToolSample> out;
    for (std::size_t k = 0; k < ts.size(); ++k) {
        const double t = ts[k];
        glm::dquat q = k + 1 == ts.size() ? controls[3].orientation : controls[0].orientation;
        if (turning && k > 0 && k + 1 < ts.size()) {
            const int i = std::min(int(t * 3.0), 2);
            q = glm::normalize(glm::slerp(controls[i].orientation, controls[i + 1].orientation, t * 3.0 - i));
        }
        // The ends are exactly the first and last control points.
        out.push_back({k == 0 ? c[0] : k + 1 == ts.size() ? c[3] : bezierPoint(c, t), q});
    }
    return out;
}

}  // namespace kizamu::sculpt
