// SPDX-License-Identifier: Apache-2.0
// Mesh import: round trips through our exporters, hand-written files in every variant the
// readers accept, and damaged files that must give a one-line FileError.
#include "mesh/mesh_import.h"

#include "util/file_error.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <string>

using namespace kizamu;
using namespace kizamu::mesh;

namespace {

MeshBuffers octahedron() {
    MeshBuffers m;
    m.positions = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    m.colours = {{255, 0, 0}, {0, 255, 0}, {0, 0, 255}, {10, 20, 30}, {200, 100, 50}, {1, 2, 3}};
    m.indices = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};
    for (auto& p : m.positions) m.normals.push_back(glm::normalize(p));
    return m;
}

std::string errorOf(std::string_view bytes, MeshFormat f) {
    try {
        decodeMesh(bytes, f, "x");
    } catch (const FileError& e) {
        const std::string msg = e.what();
        EXPECT_EQ(msg.find('\n'), std::string::npos) << "one line: " << msg;
        return msg;
    }
    return "";
}

TEST(MeshImport, RoundTripsThroughOurExporters) {
    const auto dir = std::filesystem::temp_directory_path() / ("kizamu_import_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    const MeshBuffers mesh = octahedron();
    for (const char* ext : {"obj", "stl", "ply"}) {
        SCOPED_TRACE(ext);
        const std::string path = (dir / (std::string("oct.") + ext)).string();
        exportMesh(mesh, path);
        const MeshBuffers back = importMesh(path);
        ASSERT_EQ(back.triangleCount(), mesh.triangleCount());
        ASSERT_EQ(back.vertexCount(), mesh.vertexCount());  // STL facets weld back to 6 vertices
        for (std::size_t t = 0; t < mesh.indices.size(); ++t)
            EXPECT_EQ(back.positions[back.indices[t]], mesh.positions[mesh.indices[t]]);
        if (std::string(ext) != "stl") {
            EXPECT_EQ(back.colours, mesh.colours);
        }
    }
    std::filesystem::remove_all(dir);
}

TEST(MeshImport, ReadsEveryVariant) {
    // OFF with comments and a quad.
    const MeshBuffers off = decodeMesh("OFF\n# a square\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n", MeshFormat::Off, "x");
    EXPECT_EQ(off.triangleCount(), 2u);
    // ASCII STL.
    const MeshBuffers stl = decodeMesh("solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n"
                                       "endloop\nendfacet\nendsolid t\n", MeshFormat::Stl, "x");
    EXPECT_EQ(stl.triangleCount(), 1u);
    // ASCII PLY with an extra element and a quad.
    const MeshBuffers ply = decodeMesh("ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                                       "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                                       "element edge 1\nproperty int a\nproperty int b\nend_header\n"
                                       "0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n0 1\n", MeshFormat::Ply, "x");
    EXPECT_EQ(ply.triangleCount(), 2u);
    // Big-endian binary PLY with double coordinates and a ushort list count.
    std::string be = "ply\nformat binary_big_endian 1.0\nelement vertex 3\nproperty double x\nproperty double y\n"
                     "property double z\nelement face 1\nproperty list ushort uint vertex_index\nend_header\n";
    auto putBE = [&](const void* p, std::size_t n) {
        for (std::size_t i = 0; i < n; ++i) be.push_back(static_cast<const char*>(p)[n - 1 - i]);
    };
    for (double v : {0.0, 0.0, 0.0, 2.0, 0.0, 0.0, 0.0, 3.0, 0.0}) putBE(&v, 8);
    const uint16_t three = 3;
    putBE(&three, 2);
    for (uint32_t i : {0u, 1u, 2u}) putBE(&i, 4);
    const MeshBuffers bply = decodeMesh(be, MeshFormat::Ply, "x");
    ASSERT_EQ(bply.triangleCount(), 1u);
    EXPECT_EQ(bply.positions[2], glm::vec3(0, 3, 0));
    // OBJ with negative indices, texture/normal references and a pentagon.
    const MeshBuffers obj = decodeMesh("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv -1 0.5 0\nvt 0 0\n"
                                       "f -5/1/1 -4/1/1 -3//1 2 5\n", MeshFormat::Obj, "x");
    EXPECT_EQ(obj.triangleCount(), 3u);
}

TEST(MeshImport, DamagedFilesNameTheProblem) {
    EXPECT_NE(errorOf("", MeshFormat::Obj).find("empty"), std::string::npos);
    EXPECT_NE(errorOf("v 0 0 0\nv 1 0 0\nf 1 2 3\n", MeshFormat::Obj).find("line 3: face index 3 out of range"),
              std::string::npos);
    EXPECT_NE(errorOf("v 0 0 zero\n", MeshFormat::Obj).find("line 1"), std::string::npos);
    EXPECT_NE(errorOf("# only comments\n", MeshFormat::Obj).find("no triangles"), std::string::npos);
    std::string binary(84 + 50, '\0');
    const uint32_t two = 2;
    std::memcpy(binary.data() + 80, &two, 4);  // claims 2 facets, holds 1
    EXPECT_NE(errorOf(binary, MeshFormat::Stl).find("does not match"), std::string::npos);
    EXPECT_NE(errorOf("solid x\nouter loop\nvertex 0 0 0\n", MeshFormat::Stl).find("incomplete"), std::string::npos);
    EXPECT_NE(errorOf("ply\nformat ascii 1.0\nelement vertex 3\n", MeshFormat::Ply).find("end_header"), std::string::npos);
    EXPECT_NE(errorOf("ply\nformat ascii 1.0\nelement vertex 99999999999\nproperty float x\nend_header\n1\n", MeshFormat::Ply)
                  .find("claims more entries"),
              std::string::npos);
    EXPECT_NE(errorOf("ply\nformat weird 1.0\nend_header\n", MeshFormat::Ply).find("unknown PLY format"), std::string::npos);
    EXPECT_NE(errorOf("OFF\n99999999 1 0\n0 0 0\n", MeshFormat::Off).find("exceed"), std::string::npos);
    EXPECT_NE(errorOf("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n", MeshFormat::Off).find("out of range"), std::string::npos);
    EXPECT_NE(errorOf("PLY\n", MeshFormat::Off).find("not an OFF file"), std::string::npos);
    EXPECT_THROW(importMesh("/nonexistent/dir/x.obj"), FileError);
    // Hostile PLY headers: entries without properties, repeated elements, NaN or fractional indices.
    const std::string head = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n";
    EXPECT_NE(errorOf("ply\nformat ascii 1.0\nelement vertex 99999\nend_header\n", MeshFormat::Ply).find("no properties"),
              std::string::npos);
    EXPECT_NE(errorOf(head + "element vertex 3\nproperty float x\nend_header\n", MeshFormat::Ply).find("appears twice"),
              std::string::npos);
    const std::string tri = "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n";
    EXPECT_NE(errorOf(head + tri + "3 0 1 nan\n", MeshFormat::Ply).find("out of range"), std::string::npos);
    EXPECT_NE(errorOf(head + tri + "3 0 1 1.5\n", MeshFormat::Ply).find("out of range"), std::string::npos);
    EXPECT_NE(errorOf(head + tri + "nan 0 1 2\n", MeshFormat::Ply).find("items"), std::string::npos);
}

TEST(MeshImport, LongPolygonsOptionalWAndCommentsInObj) {
    std::string obj = "v 0 0 0 1  # w is optional\n";
    for (int i = 1; i < 100; ++i)
        obj += "v " + std::to_string(std::cos(i * 0.063)) + " " + std::to_string(std::sin(i * 0.063)) + " 0\n";
    obj += "f";
    for (int i = 1; i <= 100; ++i) obj += " " + std::to_string(i);
    obj += "  # a 100-gon\n";
    EXPECT_EQ(decodeMesh(obj, MeshFormat::Obj, "x").triangleCount(), 98u);
}

TEST(MeshImport, StlWeldsPlusAndMinusZero) {
    std::string stl(84, '\0');
    const uint32_t count = 2;
    std::memcpy(stl.data() + 80, &count, 4);
    auto facet = [&](std::initializer_list<float> v) {
        float rec[12] = {};
        std::copy(v.begin(), v.end(), rec + 3);
        stl.append(reinterpret_cast<const char*>(rec), 48);
        stl.append(2, '\0');
    };
    facet({0.0f, 0.0f, 0.0f, 1, 0, 0, 0, 1, 0});
    facet({-0.0f, 0.0f, -0.0f, 0, 0, 1, 1, 0, 0});
    EXPECT_EQ(decodeMesh(stl, MeshFormat::Stl, "x").vertexCount(), 4u);
}

}  // namespace
