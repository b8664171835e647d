// SPDX-License-Identifier: Apache-2.0
// Real meshes from Debian's libcgal-demo (extracted from the installed package, never
// downloaded): they import, and become ADFs whose inside agrees with the exact winding number,
// holes included, and whose meshes are closed and embedded. A missing package fails the test.
#include "adf/generate.h"
#include "mesh/mesh_import.h"
#include "mesh/mesh_source.h"
#include "mesh/mesh_untangle.h"
#include "mesh/surface_nets.h"
#include "mesh/triangle_bvh.h"
#include "tests/support/mesh_intersections.h"
#include "tests/util/mesh_check.h"
#include "util/thread_pool.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <random>
#include <string>

using namespace kizamu;
using namespace kizamu::mesh;

namespace {

constexpr const char* kCgalData = "/usr/share/doc/libcgal-dev/data.tar.gz";

class RealMesh : public ::testing::TestWithParam<const char*> {
protected:
    static void SetUpTestSuite() {
        sDir = std::filesystem::temp_directory_path() / ("kizamu_cgal_" + std::to_string(::getpid()));
        std::filesystem::create_directories(sDir);
    }
    static void TearDownTestSuite() { std::filesystem::remove_all(sDir); }
    /// Extracts data/meshes/NAME from the CGAL data archive; empty if that fails.
    static std::string extract(const std::string& name) {
        const std::string cmd = std::string("tar -xzf ") + kCgalData + " -C '" + sDir.string() + "' data/meshes/" + name;
        if (std::system(cmd.c_str()) != 0) return "";
        return (sDir / "data" / "meshes" / name).string();
    }
    static std::filesystem::path sDir;
};
std::filesystem::path RealMesh::sDir;

TEST_P(RealMesh, BecomesAnAdfWhoseInsideMatchesTheWindingNumber) {
    ASSERT_TRUE(std::filesystem::exists(kCgalData)) << "libcgal-demo is required (scripts/install-deps)";
    const std::string path = extract(GetParam());
    ASSERT_FALSE(path.empty()) << "could not extract " << GetParam();
    const MeshBuffers mesh = importMesh(path);
    ASSERT_GT(mesh.triangleCount(), 1000u);
    ASSERT_TRUE(mesh.valid());

    const adf::Domain d = domainAround(mesh, 7, 10.0);
    util::ThreadPool pool(2);
    const adf::AdfPtr a = adf::generate(*makeMeshSource(mesh), d, adf::GenerationSettings{}, &pool);
    const TriangleBvh bvh(mesh);
    const double h = d.finestCellSize();
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    int checked = 0, agree = 0, inside = 0;
    for (int i = 0; i < 400; ++i) {
        const glm::dvec3 p = bvh.boundsMin() + (bvh.boundsMax() - bvh.boundsMin()) * glm::dvec3(u(rng), u(rng), u(rng));
        if (std::sqrt(bvh.closest(p).distanceSquared) < 3.0 * h) continue;  // sign is only asked away from the surface
        const bool exactInside = bvh.windingNumberExact(p) > 0.5;
        ++checked;
        inside += exactInside;
        agree += (a->distance(glm::vec3(p)) < 0.0f) == exactInside;
    }
    EXPECT_GT(checked, 200);
    EXPECT_GT(inside, 10) << "the sample should hit the inside";
    EXPECT_GE(agree, checked - checked / 100) << "inside/outside disagreements with the exact winding number";
}

TEST_P(RealMesh, BatchSignsEqualPointSigns) {
    // Batches may take a neighbour's sign (closed meshes): never a different answer.
    ASSERT_TRUE(std::filesystem::exists(kCgalData)) << "libcgal-demo is required (scripts/install-deps)";
    const std::string path = extract(GetParam());
    ASSERT_FALSE(path.empty());
    const MeshBuffers mesh = importMesh(path);
    const adf::SourcePtr src = makeMeshSource(mesh);
    const adf::Domain d = domainAround(mesh, 8, 10.0);
    const TriangleBvh bvh(mesh);
    const double h = d.finestCellSize();
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    int negative = 0, positive = 0;
    for (int cell = 0; cell < 300; ++cell) {
        const glm::dvec3 c = bvh.boundsMin() + (bvh.boundsMax() - bvh.boundsMin()) * glm::dvec3(u(rng), u(rng), u(rng));
        const double size = h * double(1 << (cell % 5));  // cells of 1 to 16 finest cells
        std::vector<glm::dvec3> pts;
        for (int i = 0; i < 27; ++i) pts.push_back(c + size * 0.5 * glm::dvec3(i % 3, (i / 3) % 3, i / 9));
        std::vector<double> batch(pts.size());
        src->distances(pts, batch);
        for (std::size_t i = 0; i < pts.size(); ++i) {
            const double single = src->distance(pts[i]);
            ASSERT_EQ(batch[i], single) << "cell " << cell << " point " << i;
            (single < 0.0 ? negative : positive)++;
        }
    }
    EXPECT_GT(negative, 100);
    EXPECT_GT(positive, 100);
}

TEST_P(RealMesh, MeshesAtLevelEightClosedManifoldAndEmbedded) {
    ASSERT_TRUE(std::filesystem::exists(kCgalData)) << "libcgal-demo is required (scripts/install-deps)";
    const std::string path = extract(GetParam());
    ASSERT_FALSE(path.empty());
    const MeshBuffers mesh = importMesh(path);
    const adf::Domain d = domainAround(mesh, 8, 10.0);
    util::ThreadPool pool(2);
    MeshBuffers m = meshAdf(adf::generate(*makeMeshSource(mesh), d, adf::GenerationSettings{}, &pool), &pool);
    ASSERT_GT(m.triangleCount(), 10000u);
    EXPECT_TRUE(test::closedOrientedManifold(m));
    // What an export writes: the mesh untangled (mesh/mesh_untangle.h).
    const UntangleReport untangled = untangle(m, &pool);
    std::printf("untangling: %zu contacts, %zu coincident vertices, %zu vertices moved, the largest %.2f cells\n",
                untangled.contacts, untangled.coincidentVertices, untangled.verticesMoved,
                untangled.largestMove / d.finestCellSize());
    EXPECT_EQ(untangled.remaining, 0u);
    EXPECT_LT(untangled.largestMove, 2.0 * d.finestCellSize());
    const auto start = std::chrono::steady_clock::now();
    const std::clock_t startCpu = std::clock();  // the pool's threads are idle meanwhile
    const test::MeshIntersections r = test::findMeshIntersections(m);
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    const double cpuMs = 1000.0 * double(std::clock() - startCpu) / CLOCKS_PER_SEC;
    std::printf("%zu triangles, %zu candidate pairs, checked in %.0f ms (%.0f ms CPU): %zu coincident vertex groups, "
                "%zu degenerate triangles, %zu duplicate pairs, %zu folded edges, %zu meeting beside a shared vertex, "
                "%zu intersecting\n",
                m.triangleCount(), r.candidatePairs, ms, cpuMs, r.coincidentVertexGroups, r.degenerateTriangles,
                r.duplicateTriangles, r.foldedEdges, r.meetingAtSharedVertex, r.intersecting);
    EXPECT_TRUE(r.clean()) << r.describe(m);
    EXPECT_TRUE(test::weldsToClosedManifold(m));
}

INSTANTIATE_TEST_SUITE_P(Cgal, RealMesh, ::testing::Values("bunny00.off", "elephant-with-holes.off"),
                         [](const auto& param) {
                             std::string n = param.param;
                             for (char& c : n)
                                 if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                             return n;
                         });

}  // namespace
