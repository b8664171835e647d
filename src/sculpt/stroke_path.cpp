// SPDX-License-Identifier: Apache-2.0
/// @file stroke_path.cpp
/// @brief Stroke poses from Bezier curves, surface following and keep-out fields.
#include "sculpt/stroke_path.h"

#include "sculpt/bezier_path.h"
#include "sculpt/force_field.h"

#include <glm/geometric.hpp>

#include <cmath>

namespace kizamu::sculpt {

std::vector<ToolSample> densify(const std::vector<ToolSample>& samples, double spacing) {
    std::vector<ToolSample> out;
    if (samples.empty()) return out;
    out.push_back(samples.front());
    for (std::size_t i = 1; i < samples.size(); ++i) {
        const ToolSample& a = samples[i - 1];
        const ToolSample& b = samples[i];
        const double len = glm::length(b.position - a.position);
        const int pieces = int(std::min(1e5, std::ceil(len / spacing)));
        for (int k = 1; k < pieces; ++k) {
            const double t = double(k) / pieces;
            // A fixed orientation stays bit-exact (slerp of equal quaternions is not), so the
            // path can be thinned again later.
            const glm::dquat q = a.orientation == b.orientation ? a.orientation
                                                                 : glm::normalize(glm::slerp(a.orientation, b.orientation, t));
            out.push_back({a.position + t * (b.position - a.position), q});
        }
        out.push_back(b);
    }
    return out;
}

glm::dvec3 projectOntoOffsetSurface(const adf::Adf& clay, glm::dvec3 p, double offset) {
    adf::AdfAccessor acc(clay);
    const double tolerance = 1e-3 * clay.domain().finestCellSize();
    for (int step = 0; step < 16; ++step) {
        const adf::Sample s = acc.sample(glm::vec3(p));
        const double error = double(s.distance) - offset;
        const glm::dvec3 g(s.gradient);
        const double g2 = glm::dot(g, g);
        if (std::abs(error) <= tolerance || !(g2 > 1e-12)) break;
        p -= error * g / g2;
    }
    return p;
}

namespace {

/// Douglas-Peucker: marks the poses of [first, last] that must stay for the chords to be within
/// `tolerance` of the poses dropped.
void keepFarthest(const std::vector<ToolSample>& path, std::size_t first, std::size_t last, double tolerance, std::vector<bool>& keep) {
    double worst = 0.0;
    std::size_t at = first;
    for (std::size_t i = first + 1; i < last; ++i) {
        const double d = distanceToSegment(path[i].position, path[first].position, path[last].position);
        if (d > worst) worst = d, at = i;
    }
    if (worst <= tolerance) return;
    keep[at] = true;
    keepFarthest(path, first, at, tolerance, keep);
    keepFarthest(path, at, last, tolerance, keep);
}

}  // namespace

std::vector<ToolSample> simplify(const std::vector<ToolSample>& path, double tolerance) {
    if (path.size() < 3) return path;
    for (const ToolSample& s : path)
        if (s.orientation != path.front().orientation) return path;  // a turning tool keeps every pose
    std::vector<bool> keep(path.size(), false);
    keep.front() = keep.back() = true;
    keepFarthest(path, 0, path.size() - 1, tolerance, keep);
    std::vector<ToolSample> out;
    for (std::size_t i = 0; i < path.size(); ++i)
        if (keep[i]) out.push_back(path[i]);
    return out;
}

std::vector<ToolSample> resolvePath(const Stroke& stroke, const adf::Adf& clay, double tolerance) {
    std::vector<ToolSample> path = stroke.bezier ? bezierSamples(stroke.samples, tolerance) : stroke.samples;
    const StrokeConstraints& c = stroke.constraints;
    if (!c.followOffset && c.keepOut.empty()) return path;
    path = densify(path, 0.25 * stroke.tool.radius);
    if (c.followOffset)
        for (ToolSample& s : path) s.position = projectOntoOffsetSurface(clay, s.position, *c.followOffset);
    if (!c.keepOut.empty()) {
        std::vector<adf::SourcePtr> regions;
        for (const Shape& sh : c.keepOut) regions.push_back(sh.source(clay.domain()));
        const ForceField field(std::move(regions));
        for (ToolSample& s : path) s.position = field.constrain(s.position, stroke.tool.boundingRadius());
    }
    // The dense path served the constraints; the sweep only needs its shape (every dropped
    // pose within the tolerance of a chord), and a sweep costs per segment.
    return simplify(path, tolerance);
}

}  // namespace kizamu::sculpt
