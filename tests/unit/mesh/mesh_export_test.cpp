// SPDX-License-Identifier: Apache-2.0
// Every export is re-read by tools that share no code with ours (assimp for OBJ, STL, PLY and
// glTF, admesh for STL, lib3mf for 3MF) and compared by counts and bounds. A missing reader fails
// the test. Units: an export in millimetres measures a thousand times its export in metres, read
// back from the files (STL bytes, lib3mf).
#include "mesh/mesh_export.h"

#include "adf/generate.h"
#include "adf/test_part.h"
#include "mesh/surface_nets.h"

#include "mesh/mesh_export_3mf.h"
#include "mesh/mesh_import.h"
#include "tests/support/mesh_intersections.h"
#include "tests/util/painted.h"
#include "tests/util/uv_sphere.h"
#include "util/file_error.h"

#include <Model/COM/NMR_DLLInterfaces.h>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <random>
#include <string>
#include <vector>

using namespace kizamu;
using namespace kizamu::mesh;

namespace {

/// A closed UV sphere with normals and a colour gradient.
MeshBuffers uvSphere(float radius, int rings, int segments) {
    MeshBuffers m = test::uvEllipsoid(glm::vec3(0.5f, 0.25f, -0.125f), glm::vec3(radius), rings, segments);
    for (const glm::vec3& n : m.normals)
        m.colours.push_back(glm::u8vec3(uint8_t(127.5f * (n.x + 1)), uint8_t(127.5f * (n.y + 1)), 200));
    return m;
}

std::string run(const std::string& command) {
    std::string out;
    FILE* p = popen((command + " 2>&1").c_str(), "r");
    if (!p) return out;
    char buf[4096];
    while (std::size_t n = std::fread(buf, 1, sizeof buf, p)) out.append(buf, n);
    pclose(p);
    return out;
}

/// The number after the first `label` in `text`, past spaces, colons and an opening parenthesis
/// (what assimp and admesh print), or NaN. Plain string search: GCC 12 warns inside std::regex
/// under the sanitizers, and -Werror stopped the ASan build of this file.
double field(const std::string& text, const std::string& label) {
    std::size_t at = text.find(label);
    if (at == std::string::npos) return std::nan("");
    at = text.find_first_not_of(" \t:(", at + label.size());
    if (at == std::string::npos) return std::nan("");
    const char* begin = text.c_str() + at;
    char* end = nullptr;
    const double value = std::strtod(begin, &end);
    return end == begin ? std::nan("") : value;
}

class MeshExport : public ::testing::TestWithParam<const char*> {
protected:
    void SetUp() override {
        mDir = std::filesystem::temp_directory_path() / ("kizamu_export_" + std::to_string(::getpid()));
        std::filesystem::create_directories(mDir);
    }
    void TearDown() override { std::filesystem::remove_all(mDir); }
    std::filesystem::path mDir;
};

/// Exports `mesh` as `path` in its format's default unit and checks what assimp reads back: the
/// face count, the vertex count where the format keeps indexing (STL repeats vertices per facet
/// and assimp de-indexes OBJ faces: only PLY and glTF keep them), and the x extent, `minX` and
/// `maxX` in metres: millimetres in the file but for glTF.
void expectAssimpReadsBack(const MeshBuffers& mesh, const std::string& path, const std::string& format, double minX,
                           double maxX) {
    ASSERT_EQ(std::system("command -v assimp >/dev/null 2>&1"), 0) << "assimp (assimp-utils) is required";
    exportMesh(mesh, path);
    const double scale = format == "glb" ? 1.0 : 1000.0;
    minX *= scale;
    maxX *= scale;
    // -ptv etc. off: plain import, so counts are the file's own.
    const std::string info = run("assimp info '" + path + "' --raw");
    ASSERT_NE(info.find("Importing file ...                   OK"), std::string::npos) << info;
    EXPECT_EQ(field(info, "Faces:"), double(mesh.triangleCount())) << info;
    if (format == "ply" || format == "glb") {
        EXPECT_EQ(field(info, "Vertices:"), double(mesh.vertexCount())) << info;
    }
    EXPECT_NEAR(field(info, "Minimum point"), minX, 1e-5 * scale) << info;
    EXPECT_NEAR(field(info, "Maximum point"), maxX, 1e-5 * scale) << info;
}

/// Exports `mesh` as STL and checks that admesh finds it closed and consistently oriented.
void expectAdmeshFindsItClosed(const MeshBuffers& mesh, const std::string& path) {
    ASSERT_EQ(std::system("command -v admesh >/dev/null 2>&1"), 0) << "admesh is required";
    exportMesh(mesh, path);
    const std::string report = run("admesh '" + path + "'");
    EXPECT_EQ(field(report, "Number of facets"), double(mesh.triangleCount())) << report;
    EXPECT_EQ(field(report, "Edges fixed"), 0.0) << report;
    EXPECT_EQ(field(report, "Backwards edges"), 0.0) << report;
}

TEST_P(MeshExport, AssimpReadsBackTheSameMesh) {
    expectAssimpReadsBack(uvSphere(0.2f, 12, 16), (mDir / (std::string("sphere.") + GetParam())).string(), GetParam(),
                          0.5 - 0.2, 0.5 + 0.2);
}

/// The mesher's output for the test part: what users export.
MeshBuffers testPartMesh() {
    const adf::Domain d = adf::testPartDomain(7);
    return meshAdf(adf::generate(*adf::makeTestPart(d), d, adf::testPartSettings()));
}

TEST_P(MeshExport, AssimpReadsBackTheSurfaceNetsMesh) {
    const MeshBuffers mesh = testPartMesh();
    ASSERT_GT(mesh.triangleCount(), 1000u);
    glm::vec3 lo(1e9f), hi(-1e9f);
    for (const glm::vec3& p : mesh.positions) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    expectAssimpReadsBack(mesh, (mDir / (std::string("part.") + GetParam())).string(), GetParam(), lo.x, hi.x);
}

TEST_F(MeshExport, AdmeshFindsTheSurfaceNetsStlClosed) {
    const MeshBuffers mesh = testPartMesh();
    const std::string path = (mDir / "part.stl").string();
    expectAdmeshFindsItClosed(mesh, path);
    EXPECT_EQ(field(run("admesh '" + path + "'"), "Number of parts"), 1.0);
}

TEST_F(MeshExport, AdmeshFindsAClosedStl) { expectAdmeshFindsItClosed(uvSphere(0.2f, 10, 12), (mDir / "sphere.stl").string()); }

/// A painted mesh's colours, re-read by assimp: present, and each vertex's the colour we wrote
/// (GLB stores linear floats: converted back to sRGB bytes; OBJ repeats vertices per face, so
/// each read vertex is matched to the nearest written one).
TEST_F(MeshExport, AssimpReadsBackPaintedVertexColours) {
    adf::Domain d;
    d.maxLevel = 5;
    d.tileSpanLevels = 3;
    const adf::Rgb8 paint(30, 60, 220);
    const adf::AdfPtr a = test::paintedAbove(
        adf::generate(*adf::makeTranslated(adf::makeSphere(0.3), glm::dvec3(0.5)), d, adf::GenerationSettings{}), paint, 0.5);
    const MeshBuffers mesh = meshAdf(a);
    ASSERT_EQ(mesh.colours.size(), mesh.vertexCount());
    for (const std::string format : {"ply", "glb", "obj"}) {  // binary STL has no vertex colours
        SCOPED_TRACE(format);
        const std::string path = (mDir / ("painted." + format)).string();
        exportMesh(mesh, path, {.unit = LengthUnit::Metre});  // compared with the positions
        const test::AssimpColours read = test::assimpColours(path);
        ASSERT_EQ(read.colours.size(), read.positions.size());
        ASSERT_GE(read.positions.size(), mesh.vertexCount());
        const bool linear = format == "glb";
        std::size_t painted = 0, base = 0;
        for (std::size_t i = 0; i < read.positions.size(); ++i) {
            std::size_t best = 0;
            float bestD = 1e9f;
            for (std::size_t j = 0; j < mesh.vertexCount(); ++j) {
                const float dist = glm::distance(read.positions[i], mesh.positions[j]);
                if (dist < bestD) {
                    bestD = dist;
                    best = j;
                }
            }
            ASSERT_LT(bestD, 1e-5f) << "read vertex " << i << " matches no written vertex";
            glm::vec3 c = read.colours[i];
            c = linear ? glm::vec3(test::srgbByteOfLinear(c.x), test::srgbByteOfLinear(c.y), test::srgbByteOfLinear(c.z)) : c * 255.0f;
            const glm::vec3 want(mesh.colours[best]);
            EXPECT_LE(glm::length(c - want), 1.0f) << "vertex " << i << " of " << path;
            painted += mesh.colours[best] == paint;
            base += mesh.colours[best] == adf::kClayColour;
        }
        EXPECT_GT(painted, 20u) << "painted vertices carry the paint colour";
        EXPECT_GT(base, 20u) << "unpainted vertices carry the clay colour";
    }
}

/// assimp (Debian's 5.2.5) drops a line feed that starts a binary PLY's data and reads the rest
/// one byte off (assimp issue #5341): the writer puts first a vertex whose first byte is no line
/// end or blank (older versions skipped those too). The first byte of every other value was
/// checked against this assimp: only the line feed breaks it.
TEST_F(MeshExport, AssimpReadsBackAPlyWhoseFirstVertexStartsWithALineEnd) {
    adf::Domain d;
    d.maxLevel = 5;
    d.tileSpanLevels = 3;
    MeshBuffers mesh = meshAdf(test::paintedAbove(
        adf::generate(*adf::makeTranslated(adf::makeSphere(0.3), glm::dvec3(0.5)), d, adf::GenerationSettings{}),
        adf::Rgb8(30, 60, 220), 0.5));
    const uint32_t bits = std::bit_cast<uint32_t>(mesh.positions[0].x);
    mesh.positions[0].x = std::bit_cast<float>((bits & ~0xffu) | uint8_t('\n'));  // a few ulps off
    const std::string path = (mDir / "first.ply").string();
    exportMesh(mesh, path, {.unit = LengthUnit::Metre});  // unscaled: the crafted first byte stays
    const test::AssimpColours read = test::assimpColours(path);
    ASSERT_EQ(read.positions.size(), mesh.vertexCount());
    for (std::size_t i = 0; i < read.positions.size(); ++i) {  // the dump prints 6 digits
        std::size_t found = mesh.vertexCount();
        for (std::size_t j = 0; j < mesh.vertexCount() && found == mesh.vertexCount(); ++j)
            if (glm::distance(read.positions[i], mesh.positions[j]) < 1e-5f) found = j;
        ASSERT_LT(found, mesh.vertexCount()) << "read vertex " << i << " is none written";
        EXPECT_EQ(glm::vec3(mesh.colours[found]), glm::round(read.colours[i] * 255.0f)) << "vertex " << i;
    }
}

INSTANTIATE_TEST_SUITE_P(Formats, MeshExport, ::testing::Values("obj", "stl", "ply", "glb"));

TEST_F(MeshExport, RejectsUnknownFormatsAndInvalidMeshes) {
    MeshBuffers mesh = uvSphere(0.2f, 6, 8);
    EXPECT_THROW(exportMesh(mesh, (mDir / "sphere.fbx").string()), FileError);
    EXPECT_THROW(exportMesh(mesh, (mDir / "sphere.off").string()), FileError);  // read only
    EXPECT_THROW(exportMesh(MeshBuffers{}, (mDir / "empty.glb").string()), FileError);
    mesh.indices.push_back(99999);
    mesh.indices.push_back(0);
    mesh.indices.push_back(1);
    EXPECT_THROW(exportMesh(mesh, (mDir / "sphere.obj").string()), FileError);
    EXPECT_FALSE(std::filesystem::exists(mDir / "sphere.obj"));
}

// ---- units ----

/// The x, y, z of every vertex of every facet of a binary STL file, as written.
std::vector<float> stlCoordinates(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::vector<float> xyz;
    if (bytes.size() < 84) return xyz;
    uint32_t facets = 0;
    std::memcpy(&facets, bytes.data() + 80, 4);
    if (bytes.size() != 84 + 50 * std::size_t(facets)) return xyz;
    xyz.resize(9 * std::size_t(facets));
    for (std::size_t f = 0; f < facets; ++f)  // after the facet's normal
        std::memcpy(&xyz[9 * f], bytes.data() + 84 + 50 * f + 12, 36);
    return xyz;
}

struct Box {
    glm::dvec3 lo{1e30}, hi{-1e30};
    void add(glm::dvec3 p) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
};

/// What lib3mf (the 3MF Consortium's reader) finds in a 3MF file: the model's unit, and the
/// first mesh object's counts and bounding box.
struct ThreeMfContent {
    DWORD unit = 99;
    DWORD vertices = 0, triangles = 0;
    Box box;
    MeshBuffers mesh;  ///< the positions and triangles as read
};

ThreeMfContent readThreeMf(const std::string& path) {
    struct Release {
        void operator()(NMR::PLib3MFBase* p) const { NMR::lib3mf_release(p); }
    };
    using Handle = std::unique_ptr<NMR::PLib3MFBase, Release>;
    ThreeMfContent c;
    NMR::PLib3MFModel* rawModel = nullptr;
    EXPECT_EQ(NMR::lib3mf_createmodel(&rawModel), LIB3MF_OK);
    const Handle model(rawModel);
    NMR::PLib3MFModelReader* rawReader = nullptr;
    EXPECT_EQ(NMR::lib3mf_model_queryreader(model.get(), "3mf", &rawReader), LIB3MF_OK);
    const Handle reader(rawReader);
    NMR::lib3mf_reader_setstrictmodeactive(reader.get(), true);
    if (NMR::lib3mf_reader_readfromfileutf8(reader.get(), path.c_str()) != LIB3MF_OK) {
        ADD_FAILURE() << "lib3mf cannot read " << path;
        return c;
    }
    NMR::lib3mf_model_getunit(model.get(), &c.unit);
    NMR::PLib3MFModelResourceIterator* rawIt = nullptr;
    EXPECT_EQ(NMR::lib3mf_model_getmeshobjects(model.get(), &rawIt), LIB3MF_OK);
    const Handle it(rawIt);
    BOOL has = false;
    NMR::lib3mf_resourceiterator_movenext(it.get(), &has);
    if (!has) {
        ADD_FAILURE() << path << " holds no mesh object";
        return c;
    }
    NMR::PLib3MFModelResource* rawMesh = nullptr;
    EXPECT_EQ(NMR::lib3mf_resourceiterator_getcurrent(it.get(), &rawMesh), LIB3MF_OK);
    const Handle meshObject(rawMesh);
    NMR::lib3mf_meshobject_getvertexcount(meshObject.get(), &c.vertices);
    NMR::lib3mf_meshobject_gettrianglecount(meshObject.get(), &c.triangles);
    std::vector<NMR::MODELMESHVERTEX> v(c.vertices);
    NMR::lib3mf_meshobject_getvertices(meshObject.get(), v.data(), DWORD(v.size()), nullptr);
    for (const NMR::MODELMESHVERTEX& p : v) {
        c.box.add({p.m_fPosition[0], p.m_fPosition[1], p.m_fPosition[2]});
        c.mesh.positions.push_back({p.m_fPosition[0], p.m_fPosition[1], p.m_fPosition[2]});
    }
    std::vector<NMR::MODELMESHTRIANGLE> t(c.triangles);
    NMR::lib3mf_meshobject_gettriangleindices(meshObject.get(), t.data(), DWORD(t.size()), nullptr);
    for (const NMR::MODELMESHTRIANGLE& tri : t)
        c.mesh.indices.insert(c.mesh.indices.end(), {tri.m_nIndices[0], tri.m_nIndices[1], tri.m_nIndices[2]});
    return c;
}

TEST_F(MeshExport, StlInMillimetresMeasuresAThousandTimesItsExportInMetres) {
    const MeshBuffers mesh = testPartMesh();
    const std::string mm = (mDir / "part_mm.stl").string(), m = (mDir / "part_m.stl").string(),
                      cm = (mDir / "part_cm.stl").string();
    const std::string byDefault = (mDir / "part.stl").string();
    exportMesh(mesh, mm, {.unit = LengthUnit::Millimetre});
    exportMesh(mesh, m, {.unit = LengthUnit::Metre});
    exportMesh(mesh, cm, {.unit = LengthUnit::Centimetre});
    exportMesh(mesh, byDefault);
    const std::vector<float> a = stlCoordinates(mm), b = stlCoordinates(m), c = stlCoordinates(cm);
    ASSERT_EQ(a.size(), 9 * mesh.triangleCount());
    ASSERT_EQ(b.size(), a.size());
    ASSERT_EQ(c.size(), a.size());
    EXPECT_EQ(stlCoordinates(byDefault), a) << "STL's default unit is the millimetre";
    Box boxMm, boxM;
    for (std::size_t i = 0; i < a.size(); ++i) {
        // Each is the float nearest to the metre value times the factor: within half an ulp.
        EXPECT_NEAR(a[i], 1000.0 * double(b[i]), 1e-7 * std::abs(a[i])) << "coordinate " << i;
        EXPECT_NEAR(c[i], 100.0 * double(b[i]), 1e-7 * std::abs(c[i])) << "coordinate " << i;
        if (i % 3 == 2) {
            boxMm.add({a[i - 2], a[i - 1], a[i]});
            boxM.add({b[i - 2], b[i - 1], b[i]});
        }
    }
    for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(boxMm.hi[k] - boxMm.lo[k], 1000.0 * (boxM.hi[k] - boxM.lo[k]), 1e-3)
            << "axis " << k;
        EXPECT_GT(boxM.hi[k] - boxM.lo[k], 0.1) << "the test part is tens of centimetres";
    }
}

TEST_F(MeshExport, ThreeMfCarriesItsUnitAndMeasuresAThousandTimesItsExportInMetres) {
    const MeshBuffers mesh = testPartMesh();
    Box want;
    for (const glm::vec3& p : mesh.positions) want.add(glm::dvec3(p));
    const std::string mm = (mDir / "part_mm.3mf").string(), m = (mDir / "part_m.3mf").string(),
                      cm = (mDir / "part_cm.3MF").string();
    const std::string byDefault = (mDir / "part.3mf").string();
    exportMesh(mesh, mm, {.unit = LengthUnit::Millimetre});
    exportMesh(mesh, m, {.unit = LengthUnit::Metre});
    exportMesh(mesh, cm, {.unit = LengthUnit::Centimetre});
    exportMesh(mesh, byDefault);
    const ThreeMfContent a = readThreeMf(mm), b = readThreeMf(m), c = readThreeMf(cm),
                         d = readThreeMf(byDefault);
    EXPECT_EQ(a.unit, DWORD(NMR::MODELUNIT_MILLIMETER));
    EXPECT_EQ(b.unit, DWORD(NMR::MODELUNIT_METER));
    EXPECT_EQ(c.unit, DWORD(NMR::MODELUNIT_CENTIMETER));
    EXPECT_EQ(d.unit, DWORD(NMR::MODELUNIT_MILLIMETER)) << "3MF's default unit is the millimetre";
    for (const ThreeMfContent* r : {&a, &b, &c, &d}) {
        EXPECT_EQ(r->vertices, mesh.vertexCount());
        EXPECT_EQ(r->triangles, mesh.triangleCount());
    }
    // lib3mf writes coordinates with 6 decimals: 1e-6 of the file's unit.
    for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(b.box.lo[k], want.lo[k], 1e-6) << "axis " << k;
        EXPECT_NEAR(b.box.hi[k], want.hi[k], 1e-6) << "axis " << k;
        EXPECT_NEAR(a.box.lo[k], 1000.0 * b.box.lo[k], 1e-3) << "axis " << k;
        EXPECT_NEAR(a.box.hi[k], 1000.0 * b.box.hi[k], 1e-3) << "axis " << k;
        EXPECT_NEAR(c.box.hi[k] - c.box.lo[k], 100.0 * (b.box.hi[k] - b.box.lo[k]), 1e-4)
            << "axis " << k;
        EXPECT_EQ(d.box.lo[k], a.box.lo[k]);
    }
}

TEST_F(MeshExport, GltfIsMetresOnly) {
    const MeshBuffers mesh = uvSphere(0.2f, 6, 8);
    const std::string path = (mDir / "sphere.glb").string();
    EXPECT_EQ(exportUnit(path, {}), LengthUnit::Metre);
    EXPECT_EQ(exportUnit(path, {.unit = LengthUnit::Metre}), LengthUnit::Metre);
    try {
        exportMesh(mesh, path, {.unit = LengthUnit::Millimetre});
        ADD_FAILURE() << "a glTF in millimetres was written";
    } catch (const FileError& e) {
        EXPECT_NE(std::string(e.what()).find("metres by its specification"), std::string::npos)
            << e.what();
    }
    EXPECT_FALSE(std::filesystem::exists(path));
    EXPECT_EQ(exportUnit((mDir / "a.obj").string(), {}), LengthUnit::Millimetre);
    EXPECT_EQ(exportUnit((mDir / "a.PLY").string(), {.unit = LengthUnit::Centimetre}),
              LengthUnit::Centimetre);
    EXPECT_EQ(lengthUnitOf("cm"), LengthUnit::Centimetre);
    EXPECT_FALSE(lengthUnitOf("in").has_value());
}

/// A mesh already in the file's unit (read from a file, written again) keeps its coordinates bit
/// for bit.
TEST_F(MeshExport, EqualUnitsCopyCoordinatesExactly) {
    const MeshBuffers mesh = uvSphere(200.0f, 6, 8);  // millimetres
    const std::string path = (mDir / "sphere.stl").string();
    exportMesh(mesh, path, {.meshUnit = LengthUnit::Millimetre});
    const std::vector<float> xyz = stlCoordinates(path);
    ASSERT_EQ(xyz.size(), 9 * mesh.triangleCount());
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t)
        for (int k = 0; k < 3; ++k) {
            const glm::vec3& p = mesh.positions[mesh.indices[3 * t + k]];
            EXPECT_EQ(std::memcmp(&xyz[9 * t + 3 * k], &p, 12), 0) << "triangle " << t;
        }
}

}  // namespace

TEST_F(MeshExport, UntangledExportsAreEmbeddedOnTheirWrittenCoordinates) {
    // A closed sphere with one vertex mirrored across a neighbour: its fan folds over.
    MeshBuffers folded = uvSphere(0.2f, 12, 16);
    const uint32_t v = 40, w = 40 + 16;  // a vertex and the one below it on the next ring
    folded.positions[v] = folded.positions[w] + (folded.positions[w] - folded.positions[v]);
    for (const LengthUnit unit : {LengthUnit::Metre, LengthUnit::Millimetre}) {
        const std::string raw = (mDir / "folded_raw.stl").string(), fixed = (mDir / "folded.stl").string();
        exportMesh(folded, raw, {.unit = unit});
        UntangleReport report;
        exportMesh(folded, fixed, {.unit = unit, .untangle = true, .untangled = &report});
        EXPECT_GT(report.contacts, 0u);
        EXPECT_EQ(report.remaining, 0u);
        // Read back as a slicer would: the STL reader welds vertices by position.
        const test::MeshIntersections before = test::findMeshIntersections(importMesh(raw));
        EXPECT_FALSE(before.clean()) << "the fold is written as it is without untangling";
        const MeshBuffers back = importMesh(fixed);
        const test::MeshIntersections after = test::findMeshIntersections(back);
        EXPECT_TRUE(after.clean()) << unitSymbol(unit) << ": " << after.describe(back);
        EXPECT_TRUE(test::weldsToClosedManifold(back)) << unitSymbol(unit);
        // A 3MF keeps six decimals of its unit: decided on what a reader gets back.
        const std::string threeMf = (mDir / "folded.3mf").string();
        exportMesh(folded, threeMf, {.unit = unit, .untangle = true});
        const MeshBuffers read = readThreeMf(threeMf).mesh;
        const test::MeshIntersections in3mf = test::findMeshIntersections(read);
        EXPECT_TRUE(in3mf.clean()) << "3MF in " << unitSymbol(unit) << ": " << in3mf.describe(read);
    }
}

TEST_F(MeshExport, ThreeMfCoordinatesReadBackAsTheUntanglingAssumes) {
    MeshBuffers m;
    std::mt19937 rng(1);
    std::uniform_real_distribution<float> u(-700.0f, 700.0f);
    for (int i = 0; i < 3000; ++i) m.positions.push_back({u(rng), u(rng) * 1e-3f, u(rng) * 1e-5f});
    for (uint32_t i = 0; i < 3000; ++i) m.indices.push_back(i);
    const std::string path = (mDir / "grid.3mf").string();
    exportMesh(m, path, {.unit = LengthUnit::Millimetre, .meshUnit = LengthUnit::Millimetre});
    const MeshBuffers back = readThreeMf(path).mesh;
    ASSERT_EQ(back.positions.size(), m.positions.size());
    std::size_t changed = 0;
    for (std::size_t i = 0; i < m.positions.size(); ++i) {
        ASSERT_EQ(back.positions[i], detail::threeMfWritten(m.positions[i])) << i;
        changed += back.positions[i] != m.positions[i];
    }
    EXPECT_GT(changed, 1000u) << "the six decimals do round";
}
