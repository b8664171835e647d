// SPDX-License-Identifier: Apache-2.0
/// @file identity_probe.cpp
/// @brief Hashes of the test part's full mesh and of the meshes after 40 mixed dabs (updates
/// and fresh builds), at levels 8 and 10: a change meant to keep the output shows the same lines
/// before and after (scripts/identity-hashes adds the .kza bytes of the example scripts).
///
/// "raw" hashes the buffers as they are (vertex order included); "canon" sorts vertices by
/// their bits and triangles (each rotated to start at its smallest vertex, so orientation is
/// kept) by their vertex numbers, so it holds when only the numbering changes. Not a test: its
/// output is compared between two builds.
#include "adf/generate.h"
#include "adf/test_part.h"
#include "mesh/surface_nets.h"
#include "util/thread_pool.h"
#include "tests/util/dabbed.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <vector>

using namespace kizamu;

static uint64_t fnv(const void* p, size_t n, uint64_t h = 1469598103934665603ull) {
    auto* b = static_cast<const unsigned char*>(p);
    for (size_t i = 0; i < n; ++i) { h ^= b[i]; h *= 1099511628211ull; }
    return h;
}

// Raw hash (order-sensitive) and canonical hash (vertices sorted, triangles as sorted vertex rows).
static void hashMesh(const mesh::MeshBuffers& m, uint64_t& raw, uint64_t& canon) {
    raw = fnv(m.positions.data(), m.positions.size() * sizeof(m.positions[0]));
    raw = fnv(m.normals.data(), m.normals.size() * sizeof(m.normals[0]), raw);
    raw = fnv(m.indices.data(), m.indices.size() * sizeof(m.indices[0]), raw);
    const size_t nv = m.positions.size();
    struct V { std::array<uint32_t, 6> bits; };
    std::vector<V> vs(nv);
    for (size_t i = 0; i < nv; ++i) {
        std::memcpy(&vs[i].bits[0], &m.positions[i], 12);
        std::memcpy(&vs[i].bits[3], &m.normals[i], 12);
    }
    std::vector<uint32_t> order(nv);
    for (size_t i = 0; i < nv; ++i) order[i] = uint32_t(i);
    std::sort(order.begin(), order.end(),
              [&](uint32_t a, uint32_t b) { return vs[a].bits < vs[b].bits; });
    std::vector<uint32_t> rank(nv);
    for (size_t i = 0; i < nv; ++i) rank[order[i]] = uint32_t(i);
    canon = 1469598103934665603ull;
    for (uint32_t i : order) canon = fnv(vs[i].bits.data(), 24, canon);
    std::vector<std::array<uint32_t, 3>> tris(m.indices.size() / 3);
    for (size_t t = 0; t < tris.size(); ++t) {
        std::array<uint32_t, 3> r{rank[m.indices[3 * t]], rank[m.indices[3 * t + 1]],
                                  rank[m.indices[3 * t + 2]]};
        std::rotate(r.begin(), std::min_element(r.begin(), r.end()), r.end());  // keep orientation
        tris[t] = r;
    }
    std::sort(tris.begin(), tris.end());
    canon = fnv(tris.data(), tris.size() * 12, canon);
}

int main() {
    util::ThreadPool pool(2);
    for (int level : {8, 10}) {
        const adf::Domain d = adf::testPartDomain(level);
        adf::AdfPtr a = adf::generate(*adf::makeTestPart(d), d, adf::testPartSettings(), &pool);
        mesh::SurfaceMesher mesher(&pool);
        mesher.build(a);
        uint64_t raw, canon;
        hashMesh(mesher.mesh(), raw, canon);
        std::printf("level %d full: raw %016llx canon %016llx tris %zu\n", level,
                    (unsigned long long)raw, (unsigned long long)canon,
                    mesher.mesh().indices.size() / 3);
        uint64_t seq = 88172645463325252ull;
        auto rnd = [&] {  // xorshift64: the same dabs on every machine
            seq ^= seq << 13;
            seq ^= seq >> 7;
            seq ^= seq << 17;
            return double(seq >> 11) / double(1ull << 53);
        };
        uint64_t accRaw = 0, accCanon = 0, accFresh = 0;
        for (int i = 0; i < 40; ++i) {
            const glm::dvec3 c(0.2 + 0.6 * rnd(), 0.2 + 0.6 * rnd(), 0.2 + 0.6 * rnd());
            const double r = (0.01 + 0.05 * rnd());
            const auto op = (i % 3 == 2) ? adf::CsgOp::Union : adf::CsgOp::Difference;
            a = adf::dabbed(a, op, c, r, &pool);
            if (i % 7 == 6) mesher.build(a); else mesher.update(a);
            hashMesh(mesher.mesh(), raw, canon);
            accRaw = fnv(&raw, 8, accRaw ^ uint64_t(i));
            accCanon = fnv(&canon, 8, accCanon ^ uint64_t(i));
            if (i % 10 == 9) {
                uint64_t fr, fc;
                hashMesh(mesh::meshAdf(a, &pool), fr, fc);
                accFresh = fnv(&fc, 8, accFresh);
                if (fc != canon) std::printf("  !! update != build at dab %d\n", i);
            }
        }
        std::printf("level %d dabs: raw %016llx canon %016llx fresh %016llx\n", level,
                    (unsigned long long)accRaw, (unsigned long long)accCanon,
                    (unsigned long long)accFresh);
    }
}
