// SPDX-License-Identifier: Apache-2.0
/// @file swept_tool.cpp
/// @brief SweptTool: segment distances and the segment hierarchy.
#include "sculpt/swept_tool.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace kizamu::sculpt {

namespace {

constexpr double kMaxStepRadians = 5.0 * 3.14159265358979323846 / 180.0;

inline double boxDistance(const glm::dvec3& p, const glm::dvec3& lo, const glm::dvec3& hi) {
    const glm::dvec3 d = glm::max(glm::max(lo - p, p - hi), glm::dvec3(0.0));
    return glm::length(d);
}

/// Minimum of a unimodal function on [lo, hi] by golden-section search (to 1e-5 of the
/// interval: a thousandth of a finest cell for any stroke segment shorter than 100 cells).
template <class F>
double goldenMinimum(F&& f, double lo, double hi) {
    const double r = 0.6180339887498949;
    double x1 = hi - r * (hi - lo), x2 = lo + r * (hi - lo);
    double f1 = f(x1), f2 = f(x2);
    double best = std::min({f(lo), f(hi), f1, f2});
    for (int i = 0; i < 24; ++i) {
        if (f1 < f2) {
            hi = x2;
            x2 = x1;
            f2 = f1;
            x1 = hi - r * (hi - lo);
            f1 = f(x1);
        } else {
            lo = x1;
            x1 = x2;
            f1 = f2;
            x2 = lo + r * (hi - lo);
            f2 = f(x2);
        }
        best = std::min({best, f1, f2});
    }
    return best;
}

}  // namespace

void validateStroke(const Tool& tool, const std::vector<ToolSample>& samples) {
    tool.validate();
    if (samples.empty()) throw std::invalid_argument("a stroke needs at least one tool sample");
    for (const ToolSample& s : samples) {
        const glm::dvec3& p = s.position;
        const glm::dquat& q = s.orientation;
        if (!std::isfinite(p.x + p.y + p.z) || !std::isfinite(q.w + q.x + q.y + q.z) || glm::length(q) < 1e-9)
            throw std::invalid_argument("a tool sample has a non-finite position or orientation");
    }
}

SweptTool::SweptTool(const Tool& tool, std::vector<ToolSample> samples) : mTool(tool), mBoundingRadius(tool.boundingRadius()) {
    validateStroke(tool, samples);
    for (ToolSample& s : samples) s.orientation = glm::normalize(s.orientation);
    if (samples.size() == 1) samples.push_back(samples.front());  // a dab: a segment of length 0
    for (std::size_t i = 0; i + 1 < samples.size(); ++i) {
        Segment s{samples[i], samples[i + 1], glm::mat3_cast(glm::conjugate(samples[i].orientation)), glm::dvec3(0.0), 0.0,
                  glm::dvec3(0.0, 0.0, 1.0), 0.0, false, 1};
        s.moveA = s.inverseA * (s.b.position - s.a.position);
        s.moveA2 = glm::dot(s.moveA, s.moveA);
        s.move = s.b.position - s.a.position;
        s.move2 = glm::dot(s.move, s.move);
        // The turn from a to b as a world rotation r = b a^-1, the short way round.
        glm::dquat r = s.b.orientation * glm::conjugate(s.a.orientation);
        if (r.w < 0.0) r = -r;
        const double sinHalf = glm::length(glm::dvec3(r.x, r.y, r.z));
        s.angle = 2.0 * std::atan2(sinHalf, r.w);
        if (sinHalf > 0.0) s.axis = glm::dvec3(r.x, r.y, r.z) / sinHalf;
        s.fixedOrientation = s.angle < 1e-9;
        s.angleSteps = std::max(8, int(std::ceil(s.angle / kMaxStepRadians)) + 1);
        mSegments.push_back(s);
    }
    mNodes.reserve(2 * mSegments.size());
    build(0, uint32_t(mSegments.size()));
    mBounds = {mNodes[0].lo, mNodes[0].hi};
    mSmallestFeature = tool.smallestDimension();
}

uint32_t SweptTool::build(uint32_t first, uint32_t count) {
    const auto index = uint32_t(mNodes.size());
    mNodes.emplace_back();
    Node n{glm::dvec3(std::numeric_limits<double>::max()), glm::dvec3(-std::numeric_limits<double>::max()), 0, 0, 0, 0};
    const double r = mBoundingRadius;
    for (uint32_t i = first; i < first + count; ++i)
        for (const glm::dvec3& p : {mSegments[i].a.position, mSegments[i].b.position}) {
            n.lo = glm::min(n.lo, p - r);
            n.hi = glm::max(n.hi, p + r);
        }
    if (count <= 4) {
        n.first = first;
        n.count = count;
    } else {
        // Strokes are ordered along their path: halving the index range keeps boxes tight.
        const uint32_t half = count / 2;
        n.left = build(first, half);
        n.right = build(first + half, count - half);
    }
    mNodes[index] = n;
    return index;
}

double SweptTool::capsuleDistance(const Segment& s, const glm::dvec3& p) const {
    const glm::dvec3 q = p - s.a.position;
    const double t = s.move2 > 0.0 ? std::clamp(glm::dot(q, s.move) / s.move2, 0.0, 1.0) : 0.0;
    return sphereDistance(mTool, q - t * s.move);
}

double SweptTool::segmentDistance(const Segment& s, const glm::dvec3& p) const {
    if (mTool.shape == ToolShape::Sphere) return capsuleDistance(s, p);  // exact, turning or not: no search
    const glm::dvec3 v = s.b.position - s.a.position;
    if (s.fixedOrientation) {
        const glm::dvec3 q = s.inverseA * (p - s.a.position), w = s.moveA;  // tool frame
        if (s.moveA2 == 0.0) return toolDistance(mTool, q);
        return goldenMinimum([&](double t) { return toolDistance(mTool, q - t * w); }, 0.0, 1.0);
    }
    // Pose at t: turned by angle * t about the axis (Rodrigues), applied after a's orientation,
    // so the tool frame sees a^-1 rot(axis, -angle t) (p - c(t)).
    auto at = [&](double t) {
        const glm::dvec3 w = p - (s.a.position + t * v);
        const double phi = -s.angle * t, c = std::cos(phi), sn = std::sin(phi);
        const glm::dvec3 turned = w * c + glm::cross(s.axis, w) * sn + s.axis * (glm::dot(s.axis, w) * (1.0 - c));
        return toolDistance(mTool, s.inverseA * turned);
    };
    const int n = s.angleSteps;
    int best = 0;
    double bestValue = at(0.0);
    for (int i = 1; i <= n; ++i) {
        const double value = at(double(i) / n);
        if (value < bestValue) {
            bestValue = value;
            best = i;
        }
    }
    const double lo = double(std::max(0, best - 1)) / n, hi = double(std::min(n, best + 1)) / n;
    return std::min(bestValue, goldenMinimum(at, lo, hi));
}

template <class SegmentDistance>
double SweptTool::search(const glm::dvec3& p, double limit, const SegmentDistance& segment) const {
    // One segment (a dab): its box would only skip a segment that cannot come below the limit,
    // which the min does too; the box test cost more than the segment it rarely skipped.
    if (mSegments.size() == 1) return std::min(limit, segment(mSegments[0]));
    double best = limit;
    const double r = mBoundingRadius;
    // Lower bound of a node: distance to its box minus nothing (the box already holds the tool);
    // a point inside the box gets 0 - r, the most the tool could reach inward.
    uint32_t stack[64];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const Node& n = mNodes[stack[--top]];
        // (Inside the box its distance is 0: no square root for the points that matter.)
        const bool inside = glm::all(glm::lessThanEqual(n.lo, p)) && glm::all(glm::lessThanEqual(p, n.hi));
        const double bound = inside ? 0.0 - r : boxDistance(p, n.lo, n.hi);
        if (bound >= best) continue;
        if (n.count > 0) {
            for (uint32_t i = n.first; i < n.first + n.count; ++i) best = std::min(best, segment(mSegments[i]));
            continue;
        }
        if (top + 2 > 64) {  // deep trees are impossible for 2^32 segments, but stay safe
            for (uint32_t i = 0; i < mSegments.size(); ++i) best = std::min(best, segment(mSegments[i]));
            return best;
        }
        stack[top++] = n.right;
        stack[top++] = n.left;
    }
    return best;
}

double SweptTool::distanceBelow(const glm::dvec3& p, double limit) const {
    return search(p, limit, [&](const Segment& s) { return segmentDistance(s, p); });
}

void SweptTool::distancesBelow(std::span<const glm::dvec3> p, std::span<double> limitInOut) const {
    if (mSegments.size() != 1 || mTool.shape != ToolShape::Sphere) {
        for (std::size_t i = 0; i < p.size(); ++i) limitInOut[i] = distanceBelow(p[i], limitInOut[i]);
        return;
    }
    // The capsule per point, without the search and the switch on the shape.
    const Segment& s = mSegments[0];
    for (std::size_t i = 0; i < p.size(); ++i) limitInOut[i] = std::min(limitInOut[i], capsuleDistance(s, p[i]));
}

double SweptTool::lowerBound(const glm::dvec3& p, double limit) const {
    const double r = mBoundingRadius;
    return search(p, limit, [&](const Segment& s) {
        if (mTool.shape == ToolShape::Sphere) return capsuleDistance(s, p);  // exact, whatever the orientations
        // The segment's swept volume lies in the box of its ends grown by the bounding radius.
        const glm::dvec3 lo = glm::min(s.a.position, s.b.position) - r, hi = glm::max(s.a.position, s.b.position) + r;
        return boxDistance(p, lo, hi) - (glm::all(glm::lessThanEqual(lo, p)) && glm::all(glm::lessThanEqual(p, hi)) ? r : 0.0);
    });
}

double SweptTool::featureSize(const glm::dvec3& centre, double radius) const {
    // Near the swept volume the tool's smallest dimension is a feature generation must resolve.
    if (boxDistance(centre, mBounds.min, mBounds.max) > radius) return std::numeric_limits<double>::infinity();
    return mSmallestFeature;
}

std::shared_ptr<const SweptTool> makeSweptTool(const Tool& tool, std::vector<ToolSample> samples) {
    return std::make_shared<SweptTool>(tool, std::move(samples));
}

}  // namespace kizamu::sculpt
