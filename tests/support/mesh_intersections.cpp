// SPDX-License-Identifier: Apache-2.0
/// @file mesh_intersections.cpp
/// @brief Welding by position, a box hierarchy for candidate pairs, and CGAL's exact predicates
/// on each pair. The only file that includes CGAL (its headers are slow to compile).
#include "tests/support/mesh_intersections.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Intersections_3/Segment_3_Triangle_3.h>
#include <CGAL/Intersections_3/Triangle_3_Triangle_3.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <initializer_list>
#include <iomanip>
#include <numeric>
#include <sstream>

namespace kizamu::test {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Segment = Kernel::Segment_3;
using Triangle = Kernel::Triangle_3;

/// Closed axis-aligned box in the mesh's float coordinates: min and max of floats are exact, so
/// two triangles that touch always have touching boxes.
struct Box {
    glm::vec3 lo, hi;
};

bool touches(const Box& a, const Box& b) {
    return a.lo.x <= b.hi.x && b.lo.x <= a.hi.x && a.lo.y <= b.hi.y && b.lo.y <= a.hi.y &&
           a.lo.z <= b.hi.z && b.lo.z <= a.hi.z;
}

Box merged(const Box& a, const Box& b) {
    return {glm::min(a.lo, b.lo), glm::max(a.hi, b.hi)};
}

/// A bounding-volume hierarchy over item boxes: median splits along the longest axis of the
/// box centres, up to kLeafSize items per leaf, nodes in depth-first order (left child next).
class BoxTree {
public:
    BoxTree(const std::vector<Box>& boxes, std::vector<uint32_t> items) : mItems(std::move(items)) {
        mCentres.resize(boxes.size());
        for (uint32_t item : mItems) mCentres[item] = 0.5f * (boxes[item].lo + boxes[item].hi);
        if (!mItems.empty()) build(boxes, 0, uint32_t(mItems.size()));
        mBoxes.resize(mItems.size());
        for (std::size_t i = 0; i < mItems.size(); ++i) mBoxes[i] = boxes[mItems[i]];
        mCentres = {};
    }

    /// Items in leaf order: neighbours in space are mostly neighbours here.
    const std::vector<uint32_t>& items() const { return mItems; }

    /// Calls f(item) for every item whose box touches `query`.
    template <class F>
    void forEachTouching(const Box& query, F&& f) const {
        if (mNodes.empty()) return;
        uint32_t stack[64];
        int top = 0;
        stack[top++] = 0;
        while (top > 0) {
            const Node& n = mNodes[stack[--top]];
            if (!touches(n.box, query)) continue;
            if (n.right == 0) {
                for (uint32_t i = n.begin; i < n.end; ++i)
                    if (touches(mBoxes[i], query)) f(mItems[i]);
            } else {
                stack[top++] = n.right;
                stack[top++] = uint32_t(&n - mNodes.data()) + 1;
            }
        }
    }

private:
    static constexpr uint32_t kLeafSize = 4;
    struct Node {
        Box box;
        uint32_t begin, end;  ///< items of the subtree
        uint32_t right;       ///< right child, 0 for a leaf
    };

    void build(const std::vector<Box>& boxes, uint32_t begin, uint32_t end) {
        const uint32_t self = uint32_t(mNodes.size());
        Box box = boxes[mItems[begin]];
        Box centres{mCentres[mItems[begin]], mCentres[mItems[begin]]};
        for (uint32_t i = begin + 1; i < end; ++i) {
            box = merged(box, boxes[mItems[i]]);
            centres = merged(centres, Box{mCentres[mItems[i]], mCentres[mItems[i]]});
        }
        mNodes.push_back({box, begin, end, 0});
        if (end - begin <= kLeafSize) return;
        const glm::vec3 extent = centres.hi - centres.lo;
        const int axis =
            extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
        const uint32_t mid = begin + (end - begin) / 2;
        std::nth_element(
            mItems.begin() + begin, mItems.begin() + mid, mItems.begin() + end,
            [&](uint32_t a, uint32_t b) { return mCentres[a][axis] < mCentres[b][axis]; });
        build(boxes, begin, mid);
        mNodes[self].right = uint32_t(mNodes.size());
        build(boxes, mid, end);
    }

    std::vector<Node> mNodes;
    std::vector<uint32_t> mItems;
    std::vector<Box> mBoxes;          ///< item boxes in leaf order
    std::vector<glm::vec3> mCentres;  ///< during the build only
};

/// The position as a key: bit pattern with -0 taken as +0 (x + 0.0f does that).
std::array<uint32_t, 3> positionKey(const glm::vec3& p) {
    return {std::bit_cast<uint32_t>(p.x + 0.0f), std::bit_cast<uint32_t>(p.y + 0.0f),
            std::bit_cast<uint32_t>(p.z + 0.0f)};
}

/// Welded vertex of each vertex, numbered in order of each group's lowest vertex index, and the
/// number of groups with more than one vertex (with the first such group's two lowest vertices).
struct Welding {
    std::vector<uint32_t> weldedOf;
    std::vector<uint32_t> firstOf;  ///< lowest vertex of each welded vertex
    std::size_t groups = 0;
    std::vector<std::pair<uint32_t, uint32_t>> examples;
};

Welding weld(const mesh::MeshBuffers& mesh) {
    const std::size_t n = mesh.positions.size();
    std::vector<std::pair<std::array<uint32_t, 3>, uint32_t>> keyed(n);
    for (std::size_t i = 0; i < n; ++i) keyed[i] = {positionKey(mesh.positions[i]), uint32_t(i)};
    std::sort(keyed.begin(), keyed.end());
    Welding w;
    w.weldedOf.resize(n);
    std::vector<uint32_t> leader(n);  // lowest vertex of each vertex's group
    for (std::size_t i = 0, j; i < n; i = j) {
        for (j = i + 1; j < n && keyed[j].first == keyed[i].first; ++j)
            leader[keyed[j].second] = keyed[i].second;
        leader[keyed[i].second] = keyed[i].second;
        if (j - i > 1) {
            ++w.groups;
            if (w.examples.size() < MeshIntersections::kExamplesPerKind)
                w.examples.emplace_back(keyed[i].second, keyed[i + 1].second);
        }
    }
    for (std::size_t i = 0; i < n; ++i) {
        if (leader[i] == i) {
            w.weldedOf[i] = uint32_t(w.firstOf.size());
            w.firstOf.push_back(uint32_t(i));
        } else {
            w.weldedOf[i] = w.weldedOf[leader[i]];  // leader[i] < i: numbered already
        }
    }
    std::sort(w.examples.begin(), w.examples.end());
    return w;
}

/// All of `q` strictly on one side of the plane through p0, p1, p2 (exact; a statically filtered
/// orientation each, far cheaper than a full intersection test).
bool oneSide(const Point& p0, const Point& p1, const Point& p2, std::initializer_list<Point> q) {
    const CGAL::Orientation first = CGAL::orientation(p0, p1, p2, *q.begin());
    if (first == CGAL::COPLANAR) return false;
    for (auto it = q.begin() + 1; it != q.end(); ++it)
        if (CGAL::orientation(p0, p1, p2, *it) != first) return false;
    return true;
}

}  // namespace

std::size_t MeshIntersections::count(MeshDefect kind) const {
    switch (kind) {
        case MeshDefect::CoincidentVertices:
            return coincidentVertexGroups;
        case MeshDefect::DegenerateTriangle:
            return degenerateTriangles;
        case MeshDefect::DuplicateTriangle:
            return duplicateTriangles;
        case MeshDefect::FoldedEdge:
            return foldedEdges;
        case MeshDefect::MeetAtSharedVertex:
            return meetingAtSharedVertex;
        case MeshDefect::Intersecting:
            return intersecting;
    }
    return 0;
}

std::size_t MeshIntersections::violations() const {
    return coincidentVertexGroups + degenerateTriangles + duplicateTriangles + foldedEdges +
           meetingAtSharedVertex + intersecting;
}

std::string MeshIntersections::describe(const mesh::MeshBuffers& mesh) const {
    static constexpr std::array<std::pair<MeshDefect, const char*>, kMeshDefectKinds> kNames{{
        {MeshDefect::CoincidentVertices, "coincident vertex groups"},
        {MeshDefect::DegenerateTriangle, "degenerate triangles"},
        {MeshDefect::DuplicateTriangle, "duplicate triangle pairs"},
        {MeshDefect::FoldedEdge, "folded edge pairs (coplanar, same side)"},
        {MeshDefect::MeetAtSharedVertex, "pairs sharing one vertex that meet elsewhere"},
        {MeshDefect::Intersecting, "pairs sharing no vertex that meet"},
    }};
    std::ostringstream s;
    s << std::setprecision(9);
    auto point = [&](uint32_t v) {
        const glm::vec3 p = mesh.positions[v];
        s << "(" << p.x << ", " << p.y << ", " << p.z << ")";
    };
    auto triangle = [&](uint32_t t) {
        s << "triangle " << t << " [";
        for (int k = 0; k < 3; ++k) {
            s << (k ? " " : "") << mesh.indices[3 * t + k];
            s << " ";
            point(mesh.indices[3 * t + k]);
        }
        s << "]";
    };
    s << violations() << " violations in " << mesh.triangleCount() << " triangles:";
    for (const auto& [kind, name] : kNames) {
        if (count(kind) == 0) continue;
        s << "\n  " << count(kind) << " " << name;
        for (const MeshDefectExample& e : examples) {
            if (e.kind != kind) continue;
            s << "\n    e.g. ";
            if (kind == MeshDefect::CoincidentVertices) {
                s << "vertices " << e.first << " and " << e.second << " at ";
                point(e.first);
            } else {
                triangle(e.first);
                if (e.second != MeshDefectExample::kNone) {
                    s << " and ";
                    triangle(e.second);
                }
            }
        }
    }
    return s.str();
}

MeshIntersections findMeshIntersections(const mesh::MeshBuffers& mesh) {
    MeshIntersections r;
    std::array<std::size_t, kMeshDefectKinds> examplesOf{};
    auto example = [&](MeshDefect kind, uint32_t a, uint32_t b) {
        if (examplesOf[std::size_t(kind)]++ < MeshIntersections::kExamplesPerKind)
            r.examples.push_back({kind, a, b});
    };

    const Welding w = weld(mesh);
    r.coincidentVertexGroups = w.groups;
    for (const auto& [a, b] : w.examples) example(MeshDefect::CoincidentVertices, a, b);

    std::vector<Point> points(w.firstOf.size());
    std::vector<char> finite(w.firstOf.size());
    for (std::size_t v = 0; v < points.size(); ++v) {
        const glm::vec3 p = mesh.positions[w.firstOf[v]];
        points[v] = Point(double(p.x), double(p.y), double(p.z));  // exact
        finite[v] = std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
    }
    const std::size_t nt = mesh.triangleCount();
    std::vector<std::array<uint32_t, 3>> tris(nt);
    std::vector<Box> boxes(nt);
    std::vector<uint32_t> proper;  // non-degenerate triangles
    proper.reserve(nt);
    for (std::size_t t = 0; t < nt; ++t) {
        std::array<uint32_t, 3>& v = tris[t];
        for (int k = 0; k < 3; ++k) v[k] = w.weldedOf[mesh.indices[3 * t + k]];
        if (!finite[v[0]] || !finite[v[1]] || !finite[v[2]] ||
            CGAL::collinear(points[v[0]], points[v[1]], points[v[2]])) {
            ++r.degenerateTriangles;
            example(MeshDefect::DegenerateTriangle, uint32_t(t), MeshDefectExample::kNone);
            continue;
        }
        proper.push_back(uint32_t(t));
        const glm::vec3 &a = mesh.positions[mesh.indices[3 * t]],
                        &b = mesh.positions[mesh.indices[3 * t + 1]],
                        &c = mesh.positions[mesh.indices[3 * t + 2]];
        boxes[t] = {glm::min(a, glm::min(b, c)), glm::max(a, glm::max(b, c))};
    }
    auto triangleOf = [&](uint32_t t) {
        return Triangle(points[tris[t][0]], points[tris[t][1]], points[tris[t][2]]);
    };

    // Pairs in the order the hierarchy gives them; each once (j > i), so examples are
    // deterministic but not sorted.
    const BoxTree tree(boxes, std::move(proper));
    std::vector<std::pair<uint32_t, uint32_t>> candidates;
    for (uint32_t i : tree.items()) {
        candidates.clear();
        tree.forEachTouching(boxes[i], [&](uint32_t j) {
            if (j > i) candidates.emplace_back(i, j);
        });
        r.candidatePairs += candidates.size();
        for (const auto& [a, b] : candidates) {
            const std::array<uint32_t, 3>&ta = tris[a], &tb = tris[b];
            // inA[k]: vertex k of a is also in b; inB likewise.
            std::array<bool, 3> inA{}, inB{};
            int shared = 0;
            for (int k = 0; k < 3; ++k)
                for (int l = 0; l < 3; ++l)
                    if (ta[k] == tb[l]) {
                        inA[k] = inB[l] = true;
                        ++shared;
                    }
            if (shared == 3) {
                ++r.duplicateTriangles;
                example(MeshDefect::DuplicateTriangle, a, b);
            } else if (shared == 2) {
                // Shared edge pq; apex c of a, apex d of b. Coplanar with d on c's side: a fold.
                const int ka = int(std::find(inA.begin(), inA.end(), false) - inA.begin());
                const int kb = int(std::find(inB.begin(), inB.end(), false) - inB.begin());
                const Point &p = points[ta[(ka + 1) % 3]], &q = points[ta[(ka + 2) % 3]],
                            &c = points[ta[ka]], &d = points[tb[kb]];
                if (CGAL::orientation(p, q, c, d) == CGAL::COPLANAR &&
                    CGAL::coplanar_orientation(p, q, c, d) == CGAL::POSITIVE) {
                    ++r.foldedEdges;
                    example(MeshDefect::FoldedEdge, a, b);
                }
            } else if (shared == 1) {
                // Non-degenerate triangles on a common vertex meet elsewhere exactly when the
                // edge of one opposite that vertex meets the other (closed sets). Most pairs are
                // settled before that: the far vertices of one strictly on one side of the
                // other's plane.
                const int ka = int(std::find(inA.begin(), inA.end(), true) - inA.begin());
                const int kb = int(std::find(inB.begin(), inB.end(), true) - inB.begin());
                const Point &a1 = points[ta[(ka + 1) % 3]], &a2 = points[ta[(ka + 2) % 3]];
                const Point &b1 = points[tb[(kb + 1) % 3]], &b2 = points[tb[(kb + 2) % 3]];
                if (oneSide(points[ta[0]], points[ta[1]], points[ta[2]], {b1, b2}) ||
                    oneSide(points[tb[0]], points[tb[1]], points[tb[2]], {a1, a2}))
                    continue;
                if (CGAL::do_intersect(Segment(a1, a2), triangleOf(b)) ||
                    CGAL::do_intersect(Segment(b1, b2), triangleOf(a))) {
                    ++r.meetingAtSharedVertex;
                    example(MeshDefect::MeetAtSharedVertex, a, b);
                }
            } else {
                const Point &a0 = points[ta[0]], &a1 = points[ta[1]], &a2 = points[ta[2]];
                const Point &b0 = points[tb[0]], &b1 = points[tb[1]], &b2 = points[tb[2]];
                if (oneSide(a0, a1, a2, {b0, b1, b2}) || oneSide(b0, b1, b2, {a0, a1, a2}))
                    continue;
                if (CGAL::do_intersect(Triangle(a0, a1, a2), Triangle(b0, b1, b2))) {
                    ++r.intersecting;
                    example(MeshDefect::Intersecting, a, b);
                }
            }
        }
    }
    return r;
}

mesh::MeshBuffers weldByPosition(const mesh::MeshBuffers& mesh) {
    const Welding w = weld(mesh);
    mesh::MeshBuffers out;
    out.positions.resize(w.firstOf.size());
    for (std::size_t v = 0; v < w.firstOf.size(); ++v)
        out.positions[v] = mesh.positions[w.firstOf[v]];
    if (!mesh.normals.empty()) {
        out.normals.resize(w.firstOf.size());
        for (std::size_t v = 0; v < w.firstOf.size(); ++v)
            out.normals[v] = mesh.normals[w.firstOf[v]];
    }
    if (!mesh.colours.empty()) {
        out.colours.resize(w.firstOf.size());
        for (std::size_t v = 0; v < w.firstOf.size(); ++v)
            out.colours[v] = mesh.colours[w.firstOf[v]];
    }
    out.indices.resize(mesh.indices.size());
    for (std::size_t i = 0; i < mesh.indices.size(); ++i)
        out.indices[i] = w.weldedOf[mesh.indices[i]];
    return out;
}

}  // namespace kizamu::test
