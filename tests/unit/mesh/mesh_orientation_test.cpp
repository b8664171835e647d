// SPDX-License-Identifier: Apache-2.0
// Closed parts oriented by nesting depth before the winding number signs them: an inward sphere
// is the same solid as its outward twin, hollow solids keep their cavities whichever way their
// shells face, a sphere in a cavity is solid, crossing parts stay a union, and open or
// inconsistent parts are left as they are.
#include "mesh/mesh_orientation.h"

#include "adf/generate.h"
#include "mesh/mesh_source.h"
#include "mesh/triangle_bvh.h"
#include "tests/util/icosphere.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <random>
#include <string>
#include <utility>
#include <vector>

using namespace kizamu;
using namespace kizamu::mesh;
using kizamu::test::icosphere;

namespace {

MeshBuffers reversed(MeshBuffers m) {
    for (std::size_t t = 0; t < m.triangleCount(); ++t)
        std::swap(m.indices[3 * t + 1], m.indices[3 * t + 2]);
    return m;
}

/// An icosphere of `radius` (m) at `centre`, facing out or in.
MeshBuffers sphere(float radius, bool outward, glm::vec3 centre = glm::vec3(0.0f),
                   int subdivisions = 3) {
    MeshBuffers m = icosphere(radius, subdivisions);
    for (glm::vec3& p : m.positions) p += centre;
    return outward ? m : reversed(std::move(m));
}

void append(MeshBuffers& m, const MeshBuffers& part) {
    const auto base = uint32_t(m.positions.size());
    m.positions.insert(m.positions.end(), part.positions.begin(), part.positions.end());
    for (uint32_t i : part.indices) m.indices.push_back(base + i);
}

MeshBuffers joined(std::initializer_list<MeshBuffers> parts) {
    MeshBuffers m;
    for (const MeshBuffers& p : parts) append(m, p);
    return m;
}

/// A point at `radius` (m) from the origin, off the axes.
glm::dvec3 at(double radius) {
    return radius * glm::normalize(glm::dvec3(1.0, 0.3, 0.2));
}

/// The level-5 ADF of `mesh` over `domain`, sampled on a 9^3 lattice.
std::vector<float> adfSamples(const MeshBuffers& mesh, const adf::Domain& domain) {
    const adf::AdfPtr a = adf::generate(*makeMeshSource(mesh), domain, adf::GenerationSettings{});
    std::vector<float> s;
    for (int i = 0; i < 9 * 9 * 9; ++i) {
        const glm::dvec3 f(i % 9 / 8.0, i / 9 % 9 / 8.0, i / 81 / 8.0);
        s.push_back(
            a->distance(glm::vec3(domain.originWorld + (0.1 + 0.8 * f) * domain.sizeWorld)));
    }
    return s;
}

TEST(MeshOrientation, AnInwardSphereImportsAsItsOutwardTwin) {
    const MeshBuffers outward = sphere(0.3f, true);
    const MeshBuffers inward = reversed(outward);
    MeshBuffers fixed = inward;
    const OrientationReport r = orientClosedComponents(fixed);
    EXPECT_EQ(r.components, 1u);
    EXPECT_EQ(r.closed, 1u);
    EXPECT_EQ(r.nested, 0u);
    EXPECT_EQ(r.flipped, 1u);
    EXPECT_EQ(r.flippedTriangles, outward.triangleCount());
    EXPECT_EQ(fixed.indices, outward.indices);  // the twin, corner for corner

    std::vector<std::string> warnings;
    const adf::SourcePtr src = makeMeshSource(inward, &warnings);
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find("reversed 1 of 1 closed part"), std::string::npos) << warnings[0];
    EXPECT_LT(src->distance({0.0, 0.0, 0.0}), -0.25);
    warnings.clear();
    makeMeshSource(outward, &warnings);
    EXPECT_TRUE(warnings.empty());

    const adf::Domain d = domainAround(outward, 5, 4.0);
    const std::vector<float> a = adfSamples(outward, d), b = adfSamples(inward, d);
    EXPECT_EQ(a, b);
    EXPECT_LT(a[9 * 9 * 4 + 9 * 4 + 4], -0.25f);  // the centre is solid
}

TEST(MeshOrientation, AHollowSphereKeepsItsCavityWhicheverWayItsShellsFace) {
    const MeshBuffers correct = joined({sphere(0.4f, true), sphere(0.2f, false)});
    const adf::Domain d = domainAround(correct, 5, 4.0);
    const std::vector<float> reference = adfSamples(correct, d);
    for (int c = 0; c < 4; ++c) {
        SCOPED_TRACE("outer " + std::string(c & 1 ? "in" : "out") + "ward, inner " +
                     (c & 2 ? "in" : "out") + "ward");
        const MeshBuffers m = joined({sphere(0.4f, !(c & 1)), sphere(0.2f, !(c & 2))});
        MeshBuffers fixed = m;
        const OrientationReport r = orientClosedComponents(fixed);
        EXPECT_EQ(r.closed, 2u);
        EXPECT_EQ(r.nested, 1u);
        EXPECT_EQ(fixed.indices, correct.indices);
        const adf::SourcePtr src = makeMeshSource(m);
        EXPECT_GT(src->distance(at(0.0)), 0.0) << "the cavity";
        EXPECT_LT(src->distance(at(0.3)), 0.0) << "the shell";
        EXPECT_GT(src->distance(at(0.5)), 0.0) << "outside";
        EXPECT_EQ(adfSamples(m, d), reference);
    }
}

TEST(MeshOrientation, DisjointSpheresFacingOppositeWaysAreBothSolid) {
    const MeshBuffers m =
        joined({sphere(0.3f, true, {-0.5f, 0.0f, 0.0f}), sphere(0.3f, false, {0.5f, 0.0f, 0.0f})});
    MeshBuffers fixed = m;
    const OrientationReport r = orientClosedComponents(fixed);
    EXPECT_EQ(r.closed, 2u);
    EXPECT_EQ(r.nested, 0u);
    EXPECT_EQ(r.flipped, 1u);
    const adf::SourcePtr src = makeMeshSource(m);
    EXPECT_LT(src->distance({-0.5, 0.0, 0.0}), -0.25);
    EXPECT_LT(src->distance({0.5, 0.0, 0.0}), -0.25);
    EXPECT_GT(src->distance({0.0, 0.0, 0.0}), 0.15);
}

TEST(MeshOrientation, ASphereInACavityInASphereIsSolid) {
    for (int c = 0; c < 8; ++c) {
        SCOPED_TRACE("orientations " + std::to_string(c));
        const MeshBuffers m =
            joined({sphere(0.5f, c & 1), sphere(0.35f, c & 2), sphere(0.2f, c & 4)});
        MeshBuffers fixed = m;
        const OrientationReport r = orientClosedComponents(fixed);
        EXPECT_EQ(r.closed, 3u);
        EXPECT_EQ(r.nested, 2u);
        const adf::SourcePtr src = makeMeshSource(m);
        EXPECT_LT(src->distance(at(0.0)), 0.0) << "the core (depth 2)";
        EXPECT_GT(src->distance(at(0.27)), 0.0) << "the cavity (depth 1)";
        EXPECT_LT(src->distance(at(0.42)), 0.0) << "the outer shell";
        EXPECT_GT(src->distance(at(0.6)), 0.0) << "outside";
    }
}

TEST(MeshOrientation, CrossingPartsAreNotNestedAndStayAUnion) {
    // The small sphere's box lies inside the large one's, but it pokes out through its surface.
    const glm::vec3 c(0.3f, 0.3f, 0.0f);
    for (bool smallOutward : {true, false}) {
        const MeshBuffers m = joined({sphere(0.4f, true), sphere(0.1f, smallOutward, c)});
        MeshBuffers fixed = m;
        const OrientationReport r = orientClosedComponents(fixed);
        EXPECT_EQ(r.closed, 2u);
        EXPECT_EQ(r.nested, 0u);
        EXPECT_EQ(r.flipped, smallOutward ? 0u : 1u);
        const adf::SourcePtr src = makeMeshSource(m);
        EXPECT_LT(src->distance(glm::dvec3(c) * 1.1), 0.0)
            << "the small part outside the large one";
        EXPECT_LT(src->distance(glm::dvec3(c) * 0.85), 0.0) << "both parts";
        EXPECT_LT(src->distance({0.0, 0.0, 0.0}), 0.0);
    }
}

TEST(MeshOrientation, APartTouchingItsContainerAtACornerIsStillNested) {
    // A small tetrahedron inside a large one, sharing its corner at the origin (welded: the same
    // position). The large one's winding number there is its corner's solid angle, 1/8: not a
    // sign of being outside, so a shared vertex is not probed.
    MeshBuffers large;
    large.positions = {
        {0.0f, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, {0.0f, 0.0f, 1.0f}};
    large.indices = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
    MeshBuffers small = large;
    const glm::vec3 g(0.25f);
    for (std::size_t i = 1; i < 4; ++i)
        small.positions[i] = glm::mix(0.3f * small.positions[i], g, 0.3f);
    for (bool smallOutward : {true, false}) {
        const MeshBuffers m = joined({large, smallOutward ? small : reversed(small)});
        MeshBuffers fixed = m;
        const OrientationReport r = orientClosedComponents(fixed);
        EXPECT_EQ(r.components, 2u);
        EXPECT_EQ(r.nested, 1u);
        EXPECT_EQ(r.flipped, smallOutward ? 1u : 0u);
        const glm::vec3 c =
            (small.positions[0] + small.positions[1] + small.positions[2] + small.positions[3]) /
            4.0f;
        EXPECT_GT(makeMeshSource(m)->distance(glm::dvec3(c)), 0.0) << "the cavity";
    }
}

TEST(MeshOrientation, OpenInconsistentAndFlatPartsAreLeftAsTheyAre) {
    MeshBuffers holed = sphere(0.3f, false);
    holed.indices.resize(holed.indices.size() * 9 / 10 / 3 * 3);
    MeshBuffers oneWrong = sphere(0.3f, false, {1.0f, 0.0f, 0.0f});
    std::swap(oneWrong.indices[1], oneWrong.indices[2]);
    MeshBuffers sheet;  // one triangle, both sides: closed, no volume
    sheet.positions = {{2.0f, 0.0f, 0.0f}, {2.3f, 0.0f, 0.0f}, {2.0f, 0.3f, 0.0f}};
    sheet.indices = {0, 1, 2, 0, 2, 1};
    const MeshBuffers untouched = joined({holed, oneWrong, sheet});
    MeshBuffers m = untouched;
    OrientationReport r = orientClosedComponents(m);
    EXPECT_EQ(r.components, 3u);
    EXPECT_EQ(r.closed, 1u);
    EXPECT_EQ(r.flipped, 0u);
    EXPECT_EQ(m.indices, untouched.indices);

    // With a closed inward sphere beside them, only that sphere turns.
    const MeshBuffers closedInward = sphere(0.3f, false, {0.0f, 1.0f, 0.0f});
    m = joined({untouched, closedInward});
    r = orientClosedComponents(m);
    EXPECT_EQ(r.components, 4u);
    EXPECT_EQ(r.flipped, 1u);
    EXPECT_EQ(r.flippedTriangles, closedInward.triangleCount());
    EXPECT_TRUE(std::equal(untouched.indices.begin(), untouched.indices.end(), m.indices.begin()));
}

TEST(MeshOrientation, PartsSplitAtSeamsAreWeldedByPosition) {
    // Every triangle with its own corners, as some exporters write them.
    const MeshBuffers shared = sphere(0.3f, false);
    MeshBuffers split;
    for (uint32_t i : shared.indices) {
        split.indices.push_back(uint32_t(split.positions.size()));
        split.positions.push_back(shared.positions[i]);
    }
    const OrientationReport r = orientClosedComponents(split);
    EXPECT_EQ(r.components, 1u);
    EXPECT_EQ(r.closed, 1u);
    EXPECT_EQ(r.flipped, 1u);
    EXPECT_LT(makeMeshSource(split)->distance({0.0, 0.0, 0.0}), -0.25);
}

TEST(MeshOrientation, ManySmallPartsInsideOneAreCavities) {
    // Some 2,000 small closed parts, facing either way, inside a large sphere: each is a cavity.
    std::mt19937_64 rng(3);
    MeshBuffers m = sphere(1.0f, true, glm::vec3(0.0f), 2);
    std::vector<glm::vec3> centres;
    for (int i = 0; i < 16 * 16 * 16; ++i) {
        const glm::vec3 c =
            (glm::vec3(float(i % 16), float(i / 16 % 16), float(i / 256)) - 7.5f) * 0.1f;
        if (glm::length(c) > 0.8f) continue;
        centres.push_back(c);
        append(m, sphere(0.02f, rng() % 2 == 0, c, 0));
    }
    ASSERT_GT(centres.size(), 1500u);
    MeshBuffers fixed = m;
    const OrientationReport r = orientClosedComponents(fixed);
    EXPECT_EQ(r.components, centres.size() + 1);
    EXPECT_EQ(r.closed, centres.size() + 1);
    EXPECT_EQ(r.nested, centres.size());
    const TriangleBvh bvh(fixed);
    for (std::size_t i = 0; i < centres.size(); i += 50)
        ASSERT_NEAR(bvh.windingNumberExact(glm::dvec3(centres[i])), 0.0, 1e-6);
    EXPECT_NEAR(bvh.windingNumberExact({0.85, 0.0, 0.0}), 1.0, 1e-6);
}

}  // namespace
