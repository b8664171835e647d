// SPDX-License-Identifier: Apache-2.0
// The mesher's parallel phases write vertex references into crossings that other tiles own
// (each slot by exactly one tile) and read their neighbours' vertices after a barrier. Run on
// a pool of 4 under ThreadSanitizer (scripts/test): a full build, incremental updates across
// tile corners, and the serial result for comparison.
#include "adf/adf_source.h"
#include "adf/generate.h"
#include "mesh/surface_nets.h"
#include "tests/util/mesh_check.h"
#include "util/thread_pool.h"

#include <gtest/gtest.h>

using namespace kizamu;
using namespace kizamu::adf;

TEST(SurfaceNetsThreads, ParallelBuildAndUpdatesMatchSerialMeshing) {
    Domain d;
    d.maxLevel = 6;
    d.tileSpanLevels = 2;  // many small tiles: many borders between threads
    util::ThreadPool pool(4);
    const SourcePtr part = makeCsg(CsgOp::Difference, makeTranslated(makeRoundedBox({0.3, 0.2, 0.15}, 0.03), glm::dvec3(0.5)),
                                   makeTranslated(makeCylinder(0.08, 0.3), glm::dvec3(0.5)));
    AdfPtr a = generate(*part, d, GenerationSettings{}, &pool);
    mesh::SurfaceMesher parallel(&pool);
    parallel.build(a);
    for (int i = 0; i < 4; ++i) {
        const glm::dvec3 c(0.25 + 0.125 * i, 0.5, 0.65);  // on tile corners of the top face
        const BoxWorld region{c - glm::dvec3(0.06), c + glm::dvec3(0.06)};
        const SourcePtr old = makeAdfSource(a);
        a = regenerate(*a, *makeRegionLimited(old, makeCsg(CsgOp::Difference, old, makeTranslated(makeSphere(0.04), c)), region),
                       region, &pool);
        parallel.update(a);
        const mesh::MeshBuffers serial = mesh::meshAdf(a, nullptr);
        const mesh::MeshBuffers spliced = parallel.mesh();
        ASSERT_TRUE(test::closedOrientedManifold(spliced)) << "edit " << i;
        EXPECT_TRUE(test::canonical(spliced) == test::canonical(serial)) << "edit " << i;
    }
}
