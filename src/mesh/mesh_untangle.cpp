// SPDX-License-Identifier: Apache-2.0
/// @file mesh_untangle.cpp
/// @brief Contact detection (a tree of triangle boxes, exact predicates) and local
/// smoothing until no contact is left.
#include "mesh/mesh_untangle.h"

#include "mesh/box_tree.h"
#include "mesh/exact_predicates.h"
#include "util/thread_pool.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <tuple>
#include <vector>

namespace kizamu::mesh {

namespace {

using exact::orient2d;
using exact::orient3d;
using Point = glm::dvec3;

/// `p` with coordinate `k` dropped (a projection that keeps orientation signs up to one
/// sign per k, the same for every point).
glm::dvec2 drop(const Point& p, int k) {
    return k == 0 ? glm::dvec2(p.y, p.z) : (k == 1 ? glm::dvec2(p.z, p.x) : glm::dvec2(p.x, p.y));
}

/// An axis whose projection keeps triangle abc non-degenerate, or -1 when a, b, c are collinear.
int projectionAxis(const Point& a, const Point& b, const Point& c) {
    for (int k = 2; k >= 0; --k)
        if (orient2d(drop(a, k), drop(b, k), drop(c, k)) != 0) return k;
    return -1;
}

/// r, collinear with p and q, lies on the closed segment pq.
bool onSegment(const glm::dvec2& p, const glm::dvec2& q, const glm::dvec2& r) {
    return std::min(p.x, q.x) <= r.x && r.x <= std::max(p.x, q.x) && std::min(p.y, q.y) <= r.y &&
           r.y <= std::max(p.y, q.y);
}

/// Closed segments pq and rs meet (in the plane).
bool segmentsMeet(const glm::dvec2& p, const glm::dvec2& q, const glm::dvec2& r, const glm::dvec2& s) {
    const int o1 = orient2d(p, q, r), o2 = orient2d(p, q, s), o3 = orient2d(r, s, p), o4 = orient2d(r, s, q);
    if (o1 * o2 < 0 && o3 * o4 < 0) return true;
    return (o1 == 0 && onSegment(p, q, r)) || (o2 == 0 && onSegment(p, q, s)) || (o3 == 0 && onSegment(r, s, p)) ||
           (o4 == 0 && onSegment(r, s, q));
}

/// p lies in the closed, non-degenerate triangle abc (in the plane).
bool inTriangle(const glm::dvec2& p, const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c) {
    const int s = orient2d(a, b, c);
    return orient2d(a, b, p) * s >= 0 && orient2d(b, c, p) * s >= 0 && orient2d(c, a, p) * s >= 0;
}

/// The closed segment pq meets the closed, non-degenerate triangle abc.
bool segmentMeetsTriangle(const Point& p, const Point& q, const Point& a, const Point& b, const Point& c) {
    const int op = orient3d(a, b, c, p), oq = orient3d(a, b, c, q);
    if (op * oq > 0) return false;
    if (op == 0 && oq == 0) {  // in the triangle's plane
        const int k = projectionAxis(a, b, c);
        if (k < 0) return false;
        const glm::dvec2 P = drop(p, k), Q = drop(q, k), A = drop(a, k), B = drop(b, k), C = drop(c, k);
        return inTriangle(P, A, B, C) || inTriangle(Q, A, B, C) || segmentsMeet(P, Q, A, B) ||
               segmentsMeet(P, Q, B, C) || segmentsMeet(P, Q, C, A);
    }
    // The segment reaches the plane at one point: inside where the line passes no edge on the
    // other side from the rest.
    const int s1 = orient3d(p, q, a, b), s2 = orient3d(p, q, b, c), s3 = orient3d(p, q, c, a);
    const bool positive = s1 > 0 || s2 > 0 || s3 > 0, negative = s1 < 0 || s2 < 0 || s3 < 0;
    return !(positive && negative);
}

/// Points p and q lie strictly on one side of the plane through a, b, c.
bool strictlyOneSide(const Point& a, const Point& b, const Point& c, const Point& p, const Point& q) {
    const int sp = orient3d(a, b, c, p);
    return sp != 0 && sp == orient3d(a, b, c, q);
}
bool strictlyOneSide(const Point& a, const Point& b, const Point& c, const Point& p, const Point& q, const Point& r) {
    const int sp = orient3d(a, b, c, p);
    return sp != 0 && sp == orient3d(a, b, c, q) && sp == orient3d(a, b, c, r);
}

/// The axis whose projection shows triangle abc largest (any axis is sound; this one keeps
/// the planar tests away from degeneracy).
int widestAxis(const Point& a, const Point& b, const Point& c) {
    const glm::dvec3 n = glm::abs(glm::cross(b - a, c - a));
    return n.x >= n.y && n.x >= n.z ? 0 : (n.y >= n.z ? 1 : 2);
}

/// The closed segment pq meets the closed, non-degenerate triangle abc (in the plane).
bool segmentMeetsTriangle(const glm::dvec2& p, const glm::dvec2& q, const glm::dvec2& a, const glm::dvec2& b,
                          const glm::dvec2& c) {
    return inTriangle(p, a, b, c) || inTriangle(q, a, b, c) || segmentsMeet(p, q, a, b) || segmentsMeet(p, q, b, c) ||
           segmentsMeet(p, q, c, a);
}

/// Two triangles whose shadows along one axis meet only where the triangles share vertices
/// meet only there in space (the shadow of a contact is a contact of the shadows): exact, and
/// decisive for nearly every neighbouring pair that lies in one plane (where the side tests fail).
/// `shared` is 0 or 1; for 1, s[0] == t[0] is the shared vertex.
bool shadowsApart(const std::array<Point, 3>& s, const std::array<Point, 3>& t, int shared) {
    const int k = widestAxis(s[0], s[1], s[2]);
    std::array<glm::dvec2, 3> S, T;
    for (int i = 0; i < 3; ++i) {
        S[i] = drop(s[i], k);
        T[i] = drop(t[i], k);
    }
    if (orient2d(S[0], S[1], S[2]) == 0 || orient2d(T[0], T[1], T[2]) == 0) return false;
    if (shared == 1) return !segmentMeetsTriangle(S[1], S[2], T[0], T[1], T[2]) && !segmentMeetsTriangle(T[1], T[2], S[0], S[1], S[2]);
    for (int i = 0; i < 3; ++i)
        if (segmentMeetsTriangle(S[i], S[(i + 1) % 3], T[0], T[1], T[2])) return false;
    return !inTriangle(T[0], S[0], S[1], S[2]);
}

using Triangle = std::array<uint32_t, 3>;

/// The mesh's positions in doubles (exact) and its triangles.
struct Geometry {
    const MeshBuffers& mesh;
    WrittenPosition written;  ///< or null: the positions as they are
    glm::vec3 position(uint32_t v) const { return written ? written(mesh.positions[v]) : mesh.positions[v]; }
    Point at(uint32_t v) const { return Point(position(v)); }
    Triangle triangle(std::size_t t) const {
        return {mesh.indices[3 * t], mesh.indices[3 * t + 1], mesh.indices[3 * t + 2]};
    }
    bool degenerate(const Triangle& t) const { return projectionAxis(at(t[0]), at(t[1]), at(t[2])) < 0; }

    /// Triangles s and t (neither degenerate) meet other than along what they share.
    bool inContact(const Triangle& s, const Triangle& t) const {
        int shared = 0, si = -1, ti = -1;
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
                if (s[i] == t[j]) {
                    ++shared;
                    si = i;
                    ti = j;
                }
        if (shared == 3) return true;  // the same triangle twice
        if (shared == 2) {
            // Across a shared edge they meet elsewhere only folded flat onto each other: in one
            // plane, with their third vertices on one side of the edge.
            int sOther = 0, tOther = 0;
            for (int i = 0; i < 3; ++i) {
                if (s[i] != t[0] && s[i] != t[1] && s[i] != t[2]) sOther = i;
                if (t[i] != s[0] && t[i] != s[1] && t[i] != s[2]) tOther = i;
            }
            const Point u = at(s[(sOther + 1) % 3]), w = at(s[(sOther + 2) % 3]), a = at(s[sOther]),
                        b = at(t[tOther]);
            // Opposite sides in a shadow where s is not flat: opposite sides in its plane too,
            // if t lies in it (and no contact otherwise).
            const int k = projectionAxis(u, w, a);
            if (orient2d(drop(u, k), drop(w, k), drop(a, k)) * orient2d(drop(u, k), drop(w, k), drop(b, k)) < 0)
                return false;
            return orient3d(u, w, a, b) == 0;
        }
        if (shared == 1) {
            // Around one shared vertex: they meet elsewhere exactly where the edge opposite it
            // in one meets the other.
            const Point a = at(s[(si + 1) % 3]), b = at(s[(si + 2) % 3]), c = at(t[(ti + 1) % 3]),
                        d = at(t[(ti + 2) % 3]);
            const Point v = at(s[si]);
            if (strictlyOneSide(v, a, b, c, d) || strictlyOneSide(v, c, d, a, b)) return false;
            if (shadowsApart({v, a, b}, {v, c, d}, 1)) return false;
            return segmentMeetsTriangle(a, b, v, c, d) || segmentMeetsTriangle(c, d, v, a, b);
        }
        const Point s0 = at(s[0]), s1 = at(s[1]), s2 = at(s[2]), t0 = at(t[0]), t1 = at(t[1]), t2 = at(t[2]);
        if (strictlyOneSide(s0, s1, s2, t0, t1, t2) || strictlyOneSide(t0, t1, t2, s0, s1, s2)) return false;
        if (shadowsApart({s0, s1, s2}, {t0, t1, t2}, 0)) return false;
        return segmentMeetsTriangle(s0, s1, t0, t1, t2) || segmentMeetsTriangle(s1, s2, t0, t1, t2) ||
               segmentMeetsTriangle(s2, s0, t0, t1, t2) || segmentMeetsTriangle(t0, t1, s0, s1, s2) ||
               segmentMeetsTriangle(t1, t2, s0, s1, s2) || segmentMeetsTriangle(t2, t0, s0, s1, s2);
    }
};

/// What one detection pass found: the vertices to move and the counts.
struct Found {
    std::vector<uint32_t> vertices;
    std::size_t coincident = 0, contacts = 0;
};

/// Vertices sharing a position (compared as floats, so -0 and +0 are one position).
void findCoincident(const Geometry& g, Found& out) {
    std::vector<uint32_t> order(g.mesh.positions.size());
    for (uint32_t i = 0; i < order.size(); ++i) order[i] = i;
    auto key = [&](uint32_t v) {
        const glm::vec3 p = g.position(v);
        return std::make_tuple(p.x, p.y, p.z);
    };
    std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return key(a) < key(b); });
    for (std::size_t i = 0; i < order.size();) {
        std::size_t j = i + 1;
        while (j < order.size() && key(order[j]) == key(order[i])) ++j;
        if (j - i > 1) {
            out.coincident += j - i;
            out.vertices.insert(out.vertices.end(), order.begin() + std::ptrdiff_t(i), order.begin() + std::ptrdiff_t(j));
        }
        i = j;
    }
}

/// Triangle pairs in contact where at least one is `dirty`, and degenerate dirty triangles:
/// each dirty triangle's box is looked up in a tree of all boxes; a pair of dirty triangles is
/// examined once, from the smaller number.
void findContacts(const Geometry& g, const std::vector<uint8_t>& dirty, util::ThreadPool* pool, Found& out) {
    const std::size_t nt = g.mesh.triangleCount();
    std::vector<Box3> boxes(nt);
    for (std::size_t t = 0; t < nt; ++t)
        for (const uint32_t v : g.triangle(t)) boxes[t].add(g.at(v));
    std::vector<uint8_t> degenerate(nt, 0);
    for (std::size_t t = 0; t < nt; ++t)
        if (dirty[t] && g.degenerate(g.triangle(t))) {
            degenerate[t] = 1;
            ++out.contacts;
            const Triangle tri = g.triangle(t);
            out.vertices.insert(out.vertices.end(), tri.begin(), tri.end());
        }
    const BoxTree tree(boxes);
    // Blocks of triangles in parallel, each into its own list; the lists join in block order.
    constexpr std::size_t kBlock = 4096;
    const std::size_t blocks = (nt + kBlock - 1) / kBlock;
    std::vector<Found> perBlock(blocks);
    util::parallelFor(pool, blocks, [&](std::size_t blk) {
        Found& f = perBlock[blk];
        const uint32_t end = uint32_t(std::min(nt, (blk + 1) * kBlock));
        for (uint32_t s = uint32_t(blk * kBlock); s < end; ++s) {
            if (!dirty[s] || degenerate[s]) continue;
            const Triangle a = g.triangle(s);
            tree.visit([&](const Box3& b) { return b.meets(boxes[s]); }, [&](uint32_t t) {
                if (t == s || degenerate[t] || (dirty[t] && t < s)) return;
                const Triangle b = g.triangle(t);
                if (!g.inContact(a, b)) return;
                ++f.contacts;
                f.vertices.insert(f.vertices.end(), a.begin(), a.end());
                f.vertices.insert(f.vertices.end(), b.begin(), b.end());
            });
        }
    });
    for (const Found& f : perBlock) {
        out.contacts += f.contacts;
        out.vertices.insert(out.vertices.end(), f.vertices.begin(), f.vertices.end());
    }
}

/// Each vertex's neighbours (the other vertices of its triangles), as offsets into one list.
struct Rings {
    std::vector<uint32_t> begin, list;
    explicit Rings(const MeshBuffers& m) {
        const std::size_t nv = m.positions.size();
        std::vector<std::pair<uint32_t, uint32_t>> edges;
        edges.reserve(m.indices.size() * 2);
        for (std::size_t t = 0; t < m.triangleCount(); ++t)
            for (int i = 0; i < 3; ++i) {
                const uint32_t a = m.indices[3 * t + i], b = m.indices[3 * t + (i + 1) % 3];
                edges.emplace_back(a, b);
                edges.emplace_back(b, a);
            }
        std::sort(edges.begin(), edges.end());
        edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
        begin.assign(nv + 1, 0);
        for (const auto& e : edges) ++begin[e.first + 1];
        for (std::size_t v = 0; v < nv; ++v) begin[v + 1] += begin[v];
        list.resize(edges.size());
        for (std::size_t i = 0; i < edges.size(); ++i) list[i] = edges[i].second;
    }
};

}  // namespace

UntangleReport untangle(MeshBuffers& mesh, util::ThreadPool* pool, int maxRounds, WrittenPosition written) {
    UntangleReport report;
    const std::size_t nt = mesh.triangleCount(), nv = mesh.positions.size();
    if (nt == 0) return report;
    const Rings rings(mesh);
    std::vector<uint32_t> vertexTriBegin(nv + 1, 0), vertexTris(3 * nt);
    for (uint32_t idx : mesh.indices) ++vertexTriBegin[idx + 1];
    for (std::size_t v = 0; v < nv; ++v) vertexTriBegin[v + 1] += vertexTriBegin[v];
    {
        std::vector<uint32_t> fill(vertexTriBegin.begin(), vertexTriBegin.end() - 1);
        for (std::size_t t = 0; t < nt; ++t)
            for (int i = 0; i < 3; ++i) vertexTris[fill[mesh.indices[3 * t + i]]++] = uint32_t(t);
    }
    std::vector<uint8_t> dirty(nt, 1), moved(nv, 0);
    std::vector<std::pair<uint32_t, glm::vec3>> original;  // moved vertices' first positions
    const Geometry g{mesh, written};
    for (int round = 0; round <= maxRounds; ++round) {
        Found found;
        findCoincident(g, found);
        findContacts(g, dirty, pool, found);
        if (round == 0) {
            report.coincidentVertices = found.coincident;
            report.contacts = found.contacts;
        }
        report.remaining = found.coincident + found.contacts;
        if (found.vertices.empty() || round == maxRounds) break;
        ++report.rounds;
        // The patch to smooth: the vertices in contact, widened by a ring every few rounds
        // where contacts persist.
        std::vector<uint32_t> region = found.vertices;
        std::sort(region.begin(), region.end());
        region.erase(std::unique(region.begin(), region.end()), region.end());
        for (int ring = 0; ring < std::min(3, round / 4); ++ring) {
            const std::size_t n = region.size();
            for (std::size_t i = 0; i < n; ++i)
                for (uint32_t k = rings.begin[region[i]]; k < rings.begin[region[i] + 1]; ++k)
                    region.push_back(rings.list[k]);
            std::sort(region.begin(), region.end());
            region.erase(std::unique(region.begin(), region.end()), region.end());
        }
        // Half-way to the neighbours' mean, all from the positions before this round;
        // neighbours summed in the order of their positions (numbering-independent bits).
        std::vector<glm::vec3> next(region.size());
        std::vector<glm::vec3> ring;
        for (std::size_t i = 0; i < region.size(); ++i) {
            const uint32_t v = region[i];
            ring.clear();
            for (uint32_t k = rings.begin[v]; k < rings.begin[v + 1]; ++k) ring.push_back(mesh.positions[rings.list[k]]);
            std::sort(ring.begin(), ring.end(), [](const glm::vec3& a, const glm::vec3& b) {
                return std::tie(a.x, a.y, a.z) < std::tie(b.x, b.y, b.z);
            });
            glm::dvec3 sum(0.0);
            for (const glm::vec3& p : ring) sum += glm::dvec3(p);
            const glm::dvec3 p(mesh.positions[v]);
            next[i] = ring.empty() ? mesh.positions[v] : glm::vec3(p + 0.5 * (sum / double(ring.size()) - p));
        }
        std::fill(dirty.begin(), dirty.end(), 0);
        for (std::size_t i = 0; i < region.size(); ++i) {
            const uint32_t v = region[i];
            if (!moved[v]) original.emplace_back(v, mesh.positions[v]);
            moved[v] = 1;
            mesh.positions[v] = next[i];
            for (uint32_t k = vertexTriBegin[v]; k < vertexTriBegin[v + 1]; ++k) dirty[vertexTris[k]] = 1;
        }
    }
    report.verticesMoved = original.size();
    for (const auto& [v, p] : original)
        report.largestMove = std::max(report.largestMove, double(glm::distance(mesh.positions[v], p)));
    return report;
}

}  // namespace kizamu::mesh
