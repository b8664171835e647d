// SPDX-License-Identifier: Apache-2.0
/// @file triangle_bvh.cpp
/// @brief BVH build (median split on the longest axis), closest-point and winding-number queries.
#include "mesh/triangle_bvh.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace kizamu::mesh {

namespace {

constexpr uint32_t kLeafSize = 4;

/// Closest point on triangle abc to p (Ericson, Real-Time Collision Detection, 5.1.5).
glm::dvec3 closestOnTriangle(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
    const glm::dvec3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
    if (d1 <= 0.0 && d2 <= 0.0) return a;
    const glm::dvec3 bp = p - b;
    const double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
    if (d3 >= 0.0 && d4 <= d3) return b;
    const double vc = d1 * d4 - d3 * d2;
    // The divisions below guard against 0/0: a triangle with two equal corners (common after
    // welding) has a zero-length edge, and its other edges still need answers.
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 && d1 - d3 > 0.0) return a + ab * (d1 / (d1 - d3));
    const glm::dvec3 cp = p - c;
    const double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
    if (d6 >= 0.0 && d5 <= d6) return c;
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 && d2 - d6 > 0.0) return a + ac * (d2 / (d2 - d6));
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 && (d4 - d3) + (d5 - d6) > 0.0)
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    const double denom = va + vb + vc;
    if (!(denom > 0.0)) {
        // Degenerate (zero area): the closest point lies on one of its edges as segments.
        auto onSegment = [&](const glm::dvec3& s, const glm::dvec3& e) {
            const glm::dvec3 d = e - s;
            const double len2 = glm::dot(d, d);
            const double t = len2 > 0.0 ? std::clamp(glm::dot(p - s, d) / len2, 0.0, 1.0) : 0.0;
            return s + d * t;
        };
        glm::dvec3 best = onSegment(a, b);
        for (const glm::dvec3& q : {onSegment(b, c), onSegment(c, a)})
            if (glm::dot(q - p, q - p) < glm::dot(best - p, best - p)) best = q;
        return best;
    }
    const double v = vb / denom, w = vc / denom;
    return a + ab * v + ac * w;
}

/// Signed solid angle of triangle abc seen from p, over 4π (van Oosterom and Strackee 1983).
double solidAngleOver4Pi(const glm::dvec3& p, const glm::dvec3& a0, const glm::dvec3& b0, const glm::dvec3& c0) {
    const glm::dvec3 a = a0 - p, b = b0 - p, c = c0 - p;
    const double la = glm::length(a), lb = glm::length(b), lc = glm::length(c);
    const double det = glm::dot(a, glm::cross(b, c));
    const double div = la * lb * lc + glm::dot(a, b) * lc + glm::dot(b, c) * la + glm::dot(c, a) * lb;
    return 2.0 * std::atan2(det, div) / (4.0 * std::numbers::pi);
}

inline double boxDistanceSquared(const glm::dvec3& p, const glm::dvec3& lo, const glm::dvec3& hi) {
    const glm::dvec3 d = glm::max(glm::max(lo - p, p - hi), glm::dvec3(0.0));
    return glm::dot(d, d);
}

}  // namespace

TriangleBvh::TriangleBvh(const MeshBuffers& mesh) {
    mTriangles.reserve(mesh.triangleCount());
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t)
        mTriangles.push_back({glm::dvec3(mesh.positions[mesh.indices[3 * t]]),
                              glm::dvec3(mesh.positions[mesh.indices[3 * t + 1]]),
                              glm::dvec3(mesh.positions[mesh.indices[3 * t + 2]])});
    if (mTriangles.empty()) return;
    mNodes.reserve(2 * mTriangles.size() / kLeafSize + 2);
    build(0, uint32_t(mTriangles.size()));
    const double magnitude = std::max(glm::length(mNodes[0].lo), glm::length(mNodes[0].hi));
    mTolerance = 64.0 * std::numeric_limits<double>::epsilon() * magnitude;
}

uint32_t TriangleBvh::build(uint32_t first, uint32_t count) {
    const auto index = uint32_t(mNodes.size());
    mNodes.emplace_back();
    Node node;
    node.lo = glm::dvec3(std::numeric_limits<double>::max());
    node.hi = -node.lo;
    glm::dvec3 cLo = node.lo, cHi = node.hi, weighted(0.0);
    double area = 0.0;
    for (uint32_t i = first; i < first + count; ++i) {
        const Triangle& t = mTriangles[i];
        for (const glm::dvec3& v : {t.a, t.b, t.c}) {
            node.lo = glm::min(node.lo, v);
            node.hi = glm::max(node.hi, v);
        }
        const glm::dvec3 centroid = (t.a + t.b + t.c) / 3.0;
        cLo = glm::min(cLo, centroid);
        cHi = glm::max(cHi, centroid);
        const glm::dvec3 n = 0.5 * glm::cross(t.b - t.a, t.c - t.a);
        node.areaNormal += n;
        const double ar = glm::length(n);
        weighted += centroid * ar;
        area += ar;
    }
    node.centre = area > 0.0 ? weighted / area : 0.5 * (node.lo + node.hi);
    for (uint32_t i = first; i < first + count; ++i)
        for (const glm::dvec3& v : {mTriangles[i].a, mTriangles[i].b, mTriangles[i].c})
            node.radius = std::max(node.radius, glm::distance(v, node.centre));
    if (count <= kLeafSize) {
        node.first = first;
        node.count = count;
        mNodes[index] = node;
        return index;
    }
    const glm::dvec3 extent = cHi - cLo;
    const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
    const uint32_t mid = first + count / 2;
    std::nth_element(mTriangles.begin() + first, mTriangles.begin() + mid, mTriangles.begin() + first + count,
                     [axis](const Triangle& l, const Triangle& r) {
                         return (l.a[axis] + l.b[axis] + l.c[axis]) < (r.a[axis] + r.b[axis] + r.c[axis]);
                     });
    node.left = build(first, mid - first);
    node.right = build(mid, first + count - mid);
    mNodes[index] = node;
    return index;
}

TriangleBvh::Closest TriangleBvh::closest(const glm::dvec3& p, uint32_t hint) const {
    Closest best;
    best.distanceSquared = std::numeric_limits<double>::infinity();
    if (mNodes.empty()) return best;
    auto distanceTo = [&](uint32_t i, glm::dvec3& q) {
        const Triangle& t = mTriangles[i];
        q = closestOnTriangle(p, t.a, t.b, t.c);
        return glm::dot(q - p, q - p);
    };
    // The result is the smallest computed distance (lowest index on ties) over all triangles,
    // whatever the hint: the hint only bounds the search, and pruning keeps a slack larger than
    // the rounding of a computed closest point (absolute, from the coordinates' magnitude), so
    // rounding never hides the minimum.
    const double tolerance = mTolerance + 64.0 * std::numeric_limits<double>::epsilon() * glm::length(p);
    auto bound = [tolerance](double d2) {
        const double r = std::sqrt(d2) + tolerance;
        return r * r;
    };
    double limit = std::numeric_limits<double>::infinity();
    if (hint < mTriangles.size()) {
        glm::dvec3 q;
        limit = bound(distanceTo(hint, q));
    }
    auto consider = [&](uint32_t i) {
        glm::dvec3 q;
        const double d2 = distanceTo(i, q);
        if (d2 < best.distanceSquared || (d2 == best.distanceSquared && i < best.triangle)) {
            best = {d2, q, i};
            limit = std::min(limit, bound(d2));
        }
    };
    struct Entry {
        uint32_t node;
        double boxDistance;  ///< squared, computed once when pushed
    };
    Entry stack[128];
    int top = 0;
    stack[top++] = {0, boxDistanceSquared(p, mNodes[0].lo, mNodes[0].hi)};
    while (top > 0) {
        const Entry e = stack[--top];
        if (e.boxDistance > limit) continue;
        const Node& n = mNodes[e.node];
        if (n.count > 0) {
            for (uint32_t i = n.first; i < n.first + n.count; ++i) consider(i);
            continue;
        }
        const Entry l{n.left, boxDistanceSquared(p, mNodes[n.left].lo, mNodes[n.left].hi)};
        const Entry r{n.right, boxDistanceSquared(p, mNodes[n.right].lo, mNodes[n.right].hi)};
        // Push the farther child first so the nearer one is searched first.
        if (l.boxDistance < r.boxDistance) {
            if (r.boxDistance <= limit) stack[top++] = r;
            stack[top++] = l;
        } else {
            if (l.boxDistance <= limit) stack[top++] = l;
            stack[top++] = r;
        }
    }
    return best;
}

double TriangleBvh::windingNumber(const glm::dvec3& p, double beta) const {
    if (mNodes.empty()) return 0.0;
    double w = 0.0;
    uint32_t stack[128];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const Node& n = mNodes[stack[--top]];
        const glm::dvec3 r = n.centre - p;
        const double dist = glm::length(r);
        if (dist > beta * n.radius && dist > 0.0) {
            w += glm::dot(n.areaNormal, r) / (4.0 * std::numbers::pi * dist * dist * dist);
            continue;
        }
        if (n.count > 0) {
            for (uint32_t i = n.first; i < n.first + n.count; ++i)
                w += solidAngleOver4Pi(p, mTriangles[i].a, mTriangles[i].b, mTriangles[i].c);
            continue;
        }
        stack[top++] = n.left;
        stack[top++] = n.right;
    }
    return w;
}

double TriangleBvh::windingNumberExact(const glm::dvec3& p) const {
    double w = 0.0;
    for (const Triangle& t : mTriangles) w += solidAngleOver4Pi(p, t.a, t.b, t.c);
    return w;
}

}  // namespace kizamu::mesh
