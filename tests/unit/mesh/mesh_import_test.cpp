// SPDX-License-Identifier: Apache-2.0
// Mesh import: round trips through our exporters, hand-written files in every variant the
// readers accept, and damaged files that must give a one-line FileError.
#include "mesh/mesh_import.h"

#include "util/file_error.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <unistd.h>
#include <vector>

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
        exportMesh(mesh, path, {.unit = LengthUnit::Metre});  // read back as they are written
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

// ---- Files other tools open, read as they read them ----

/// Decodes `bytes` and returns its warnings, each checked to be one line naming the file.
std::vector<std::string> warningsOf(std::string_view bytes, MeshFormat f,
                                    MeshBuffers* out = nullptr) {
    std::vector<std::string> warnings;
    MeshBuffers m = decodeMesh(bytes, f, "x", &warnings);
    for (const std::string& w : warnings) {
        EXPECT_EQ(w.find('\n'), std::string::npos) << "one line: " << w;
        EXPECT_EQ(w.rfind("x: ", 0), 0u) << "names the file: " << w;
    }
    if (out) *out = std::move(m);
    return warnings;
}

bool anyContains(const std::vector<std::string>& lines, std::string_view part) {
    for (const std::string& l : lines)
        if (l.find(part) != std::string::npos) return true;
    return false;
}

/// `ascii` as UTF-16 with a byte-order mark; `extra` code units (non-ASCII) go after the BOM.
std::string utf16(std::string_view ascii, bool littleEndian,
                  std::initializer_list<uint16_t> extra = {}) {
    std::string out = littleEndian ? "\xFF\xFE" : "\xFE\xFF";
    auto put = [&](uint16_t u) {
        const char lo = char(u & 0xFF), hi = char(u >> 8);
        out += littleEndian ? lo : hi;
        out += littleEndian ? hi : lo;
    };
    for (uint16_t u : extra) put(u);
    for (char c : ascii) put(uint16_t(static_cast<unsigned char>(c)));
    return out;
}

const std::string kPlyHead =
    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
    "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";

TEST(MeshImport, SkipsPlyHeaderLinesItDoesNotKnow) {
    // The header old Blender exporters wrote: a bare "Created by" line, and obj_info.
    const std::string ply =
        "ply\nformat ascii 1.0\nCreated by Blender 2.49b - www.blender.org, source file: ''\n"
        "obj_info a scan\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
        "element face 1\nproperty list uchar uint vertex_indices\nend_header\n"
        "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    MeshBuffers m;
    const auto warnings = warningsOf(ply, MeshFormat::Ply, &m);
    ASSERT_EQ(m.triangleCount(), 1u);
    EXPECT_EQ(m.positions[1], glm::vec3(1, 0, 0));
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find("line 3: header line 'Created by Blender"), std::string::npos)
        << warnings[0];
    // Without the out-parameter the same file reads the same (the API callers had).
    EXPECT_EQ(decodeMesh(ply, MeshFormat::Ply, "x").triangleCount(), 1u);
}

TEST(MeshImport, ReadsNumbersWithALeadingPlus) {
    const glm::vec3 expected(1.0f, 1.5e-3f, 0.25f);
    MeshBuffers ply, obj, off, stl;
    EXPECT_TRUE(warningsOf(kPlyHead + "+1 +1.5e-3 +.25\n0 0 0\n0 +1 0\n+3 +0 +1 +2\n",
                           MeshFormat::Ply, &ply)
                    .empty());
    EXPECT_TRUE(
        warningsOf("v +1 +1.5e-3 +0.25\nv 0 0 0\nv 0 +1 0\nf +1 +2/+1 3\n", MeshFormat::Obj, &obj)
            .empty());
    EXPECT_TRUE(warningsOf("OFF\n+3 +1 +0\n+1 +1.5E-3 +0.25\n0 0 0\n0 1 0\n+3 +0 +1 +2\n",
                           MeshFormat::Off, &off)
                    .empty());
    EXPECT_TRUE(
        warningsOf(
            "solid s\nfacet normal +0 +0 +1\nouter loop\nvertex +1 +1.5e-3 +0.25\nvertex 0 0 0\n"
            "vertex 0 +1 0\nendloop\nendfacet\nendsolid s\n",
            MeshFormat::Stl, &stl)
            .empty());
    for (const MeshBuffers* m : {&ply, &obj, &off, &stl}) {
        ASSERT_EQ(m->triangleCount(), 1u);
        EXPECT_EQ(m->positions[m->indices[0]], expected);
    }
    // A sign is one sign: "+-1" and "++1" are not numbers.
    EXPECT_NE(errorOf("v +-1 0 0\n", MeshFormat::Obj).find("line 1: bad vertex coordinate '+-1'"),
              std::string::npos);
    EXPECT_NE(errorOf(kPlyHead + "++1 0 0\n0 0 0\n0 1 0\n3 0 1 2\n", MeshFormat::Ply)
                  .find("line 10: bad number '++1'"),
              std::string::npos);
}

TEST(MeshImport, ReadsObjInUtf16AndWithAByteOrderMark) {
    // What Windows Notepad saves as "Unicode": UTF-16 with a BOM and CRLF line ends; the comment
    // holds a character outside the BMP (a surrogate pair) and an unpaired surrogate.
    const std::string ascii = " a triangle\r\nv 0 0 0\r\nv 2 0 0\r\nv 0 3 0\r\nf 1 2 3\r\n";
    for (bool little : {true, false}) {
        SCOPED_TRACE(little ? "UTF-16LE" : "UTF-16BE");
        const std::string bytes = utf16(ascii, little, {'#', 0xD83D, 0xDE00, 0xDC00});
        MeshBuffers m;
        EXPECT_TRUE(warningsOf(bytes, MeshFormat::Obj, &m).empty());
        ASSERT_EQ(m.triangleCount(), 1u);
        EXPECT_EQ(m.positions[2], glm::vec3(0, 3, 0));
        EXPECT_EQ(meshFormatOfContent(bytes), MeshFormat::Obj);
    }
    // UTF-8 with a BOM (the BOM used to glue itself to the first 'v'), and old Mac CR line ends.
    MeshBuffers m;
    EXPECT_TRUE(warningsOf("\xEF\xBB\xBFv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", MeshFormat::Obj, &m)
                    .empty());
    EXPECT_EQ(m.vertexCount(), 3u);
    EXPECT_EQ(
        decodeMesh("v 0 0 0\rv 1 0 0\rv 0 1 0\rf 1 2 3\r", MeshFormat::Obj, "x").triangleCount(),
        1u);
    // A UTF-16 file read from disk, as a user would open it.
    const auto dir =
        std::filesystem::temp_directory_path() / ("kizamu_utf16_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    const std::string path = (dir / "notepad.obj").string();
    std::FILE* f = std::fopen(path.c_str(), "wb");
    const std::string bytes = utf16(ascii, true, {'#'});
    std::fwrite(bytes.data(), 1, bytes.size(), f);
    std::fclose(f);
    EXPECT_EQ(importMesh(path).triangleCount(), 1u);
    std::filesystem::remove_all(dir);
}

TEST(MeshImport, RecognisesTheFormatByContent) {
    const auto dir =
        std::filesystem::temp_directory_path() / ("kizamu_sniff_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    auto write = [&](const std::string& file, const std::string& bytes) {
        const std::string path = (dir / file).string();
        std::FILE* f = std::fopen(path.c_str(), "wb");
        std::fwrite(bytes.data(), 1, bytes.size(), f);
        std::fclose(f);
        return path;
    };
    // A binary STL whose header starts with "solid", as SolidWorks writes them.
    std::string binaryStl = "solid part";
    binaryStl.resize(80, ' ');
    const uint32_t one = 1;
    binaryStl.append(reinterpret_cast<const char*>(&one), 4);
    const float facet[12] = {0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0};
    binaryStl.append(reinterpret_cast<const char*>(facet), 48);
    binaryStl.append(2, '\0');
    const std::string asciiStl =
        "solid t\n  facet normal 0 0 1\n    outer loop\n      vertex 0 0 0\n      vertex 1 0 0\n"
        "      vertex 0 1 0\n    endloop\n  endfacet\nendsolid t\n";
    const std::string off =
        "# from a scanner\nCOFF\n3 1 0\n0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n0 1 0 0 0 255 255\n3 "
        "0 1 2\n";
    const std::string obj =
        "# exported\nmtllib a.mtl\no thing\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nusemtl m\nf 1//1 "
        "2//1 3//1\n";
    const std::string ply = kPlyHead + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    struct Case {
        std::string bytes;
        MeshFormat format;
    };
    const Case cases[] = {{binaryStl, MeshFormat::Stl},
                          {asciiStl, MeshFormat::Stl},
                          {off, MeshFormat::Off},
                          {obj, MeshFormat::Obj},
                          {ply, MeshFormat::Ply}};
    int k = 0;
    for (const Case& c : cases) {
        SCOPED_TRACE(k);
        EXPECT_EQ(meshFormatOfContent(c.bytes), c.format);
        for (const char* file : {"mesh", "mesh.dat", "mesh.bak.OBJ", "mesh.ply"}) {
            SCOPED_TRACE(file);
            std::vector<std::string> warnings;
            const MeshBuffers m = importMesh(write(std::to_string(k) + file, c.bytes), &warnings);
            ASSERT_EQ(m.triangleCount(), 1u);
            EXPECT_EQ(m.positions[m.indices[1]], glm::vec3(1, 0, 0));
            const bool extensionAgrees =
                (std::string(file) == "mesh.bak.OBJ" && c.format == MeshFormat::Obj) ||
                (std::string(file) == "mesh.ply" && c.format == MeshFormat::Ply);
            EXPECT_EQ(anyContains(warnings, "but the content is"), !extensionAgrees);
        }
        ++k;
    }
    // The glb magic is named (and refused as a format not read), whatever the extension says.
    EXPECT_EQ(meshFormatOfContent(std::string("glTF\x02\0\0\0", 8)), MeshFormat::Glb);
    // Neither extension nor content: one line that says so.
    try {
        importMesh(write("notes.txt", "hello\nworld\n"));
        ADD_FAILURE() << "a text file is not a mesh";
    } catch (const FileError& e) {
        EXPECT_NE(std::string(e.what()).find("unknown mesh format"), std::string::npos) << e.what();
    }
    // A known extension and content that names nothing: the extension decides (and names the line).
    try {
        importMesh(write("odd.off", "OFF\n3 1\n0 0 0\n1 0 0\n"));
        ADD_FAILURE() << "truncated";
    } catch (const FileError& e) {
        EXPECT_NE(std::string(e.what()).find("line 4: truncated"), std::string::npos) << e.what();
    }
    EXPECT_FALSE(meshFormatOfContent("hello\nworld\n").has_value());
    EXPECT_FALSE(meshFormatOfContent(std::string(200, '\0')).has_value());
    std::filesystem::remove_all(dir);
}

TEST(MeshImport, StepsOverWhatItDoesNotUnderstandWithAWarning) {
    // OBJ: unknown statements (each kind once, with a count), short faces, extra vertex values.
    MeshBuffers m;
    auto w =
        warningsOf("v 0 0 0\nv 1 0 0\nv 0 1 0 0.5 0.5\nfoo 1\nfoo 2\nfoo 3\nf 1 2\nbar\nf 1 2 3\n",
                   MeshFormat::Obj, &m);
    EXPECT_EQ(m.triangleCount(), 1u);
    ASSERT_EQ(w.size(), 4u);
    EXPECT_TRUE(anyContains(w, "x: line 3: a vertex with 5 values: the extra ones are ignored"));
    EXPECT_TRUE(anyContains(w, "x: line 4: unknown statement 'foo' skipped (and 2 more like it)"));
    EXPECT_TRUE(anyContains(w, "x: line 7: a face with fewer than 3 corners is skipped"));
    EXPECT_TRUE(anyContains(w, "x: line 8: unknown statement 'bar' skipped"));
    // A flood of distinct unknown statements stays a bounded list.
    std::string flood = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    for (int i = 0; i < 100; ++i) flood += "k" + std::to_string(i) + "\n";
    w = warningsOf(flood, MeshFormat::Obj);
    EXPECT_LE(w.size(), 17u);
    EXPECT_TRUE(anyContains(w, "more warnings of other kinds"));
    // ASCII STL: keywords in capitals, a missing endloop, a quad facet, a facet of 2.
    w = warningsOf(
        "SOLID S\nFACET NORMAL 0 0 1\nOUTER LOOP\nVERTEX 0 0 0\nVERTEX 1 0 0\nVERTEX 1 1 0\nVERTEX "
        "0 1 0\n"
        "ENDLOOP\nENDFACET\nfacet normal 0 0 1\nouter loop\nvertex 0 0 1\nvertex 1 0 1\nvertex 0 1 "
        "1\n"
        "endfacet\nfacet\nvertex 0 0 0\nvertex 1 1 1\nendfacet\nendsolid\n",
        MeshFormat::Stl, &m);
    EXPECT_EQ(m.triangleCount(), 3u);
    EXPECT_TRUE(anyContains(w, "x: line 8: a facet with 4 vertices is fanned into triangles"));
    EXPECT_TRUE(anyContains(w, "x: line 19: a facet with fewer than 3 vertices is skipped"));
    // Binary STL: bytes after the last facet, and a count left at 0.
    std::string stl(84, '\0');
    const uint32_t one = 1;
    std::memcpy(stl.data() + 80, &one, 4);
    const float facet[12] = {0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0};
    stl.append(reinterpret_cast<const char*>(facet), 48);
    stl.append(2, '\0');
    w = warningsOf(stl + std::string(7, '\0'), MeshFormat::Stl, &m);
    EXPECT_EQ(m.triangleCount(), 1u);
    EXPECT_TRUE(anyContains(w, "7 bytes after the last of 1 facets are ignored"));
    std::string zeroCount = stl + stl.substr(84);
    std::memset(zeroCount.data() + 80, 0, 4);
    w = warningsOf(zeroCount, MeshFormat::Stl, &m);
    EXPECT_EQ(m.triangleCount(), 2u);
    EXPECT_TRUE(anyContains(w, "the header counts 0 facets; the 2 the file holds are read"));
    // OFF without its (optional) header keyword, and with a face of 2 corners.
    w = warningsOf("3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n2 0 1\n", MeshFormat::Off, &m);
    EXPECT_EQ(m.triangleCount(), 1u);
    EXPECT_TRUE(anyContains(w, "x: line 1: no OFF header keyword"));
    EXPECT_TRUE(anyContains(w, "x: line 6: a face with fewer than 3 corners is skipped"));
    // PLY: float colours in 0..1, a face of 2 corners among good ones.
    const std::string ply =
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
        "property float z\nproperty float red\nproperty float green\nproperty float blue\n"
        "element face 2\nproperty list uchar int vertex_indices\nend_header\n"
        "0 0 0 1 0 0\n1 0 0 0 1 0\n0 1 0 0 0 0.5\n3 0 1 2\n2 0 1\n";
    w = warningsOf(ply, MeshFormat::Ply, &m);
    EXPECT_EQ(m.triangleCount(), 1u);
    ASSERT_EQ(m.colours.size(), 3u);
    EXPECT_EQ(m.colours[0], glm::u8vec3(255, 0, 0));
    EXPECT_EQ(m.colours[2], glm::u8vec3(0, 0, 127));
    EXPECT_TRUE(
        anyContains(w, "x: line 17: a face with fewer than 3 corners is skipped (face 1 of 2)"));
}

TEST(MeshImport, MalformedFilesNameTheLineOrByte) {
    // A truncated binary PLY: the entry and the byte where the data ran out.
    std::string le =
        "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float "
        "y\n"
        "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
    const std::size_t header = le.size();
    for (float v : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f})
        le.append(reinterpret_cast<const char*>(&v), 4);
    std::string msg = errorOf(le, MeshFormat::Ply);
    EXPECT_NE(msg.find("x: vertex 2 of 3, byte " + std::to_string(header + 28) + ": truncated"),
              std::string::npos)
        << msg;
    // A binary PLY face index out of range.
    for (float v : {1.f, 0.f}) le.append(reinterpret_cast<const char*>(&v), 4);
    le += '\3';
    for (int32_t i : {0, 1, 3}) le.append(reinterpret_cast<const char*>(&i), 4);
    msg = errorOf(le, MeshFormat::Ply);
    EXPECT_NE(msg.find("x: face 0 of 1, byte " + std::to_string(le.size()) +
                       ": vertex index 3 out of range (3 vertices)"),
              std::string::npos)
        << msg;
    // ASCII PLY: the line of a bad number, of an index out of range, of the end of the data.
    msg = errorOf(kPlyHead + "0 0 0\n1 abc 0\n0 1 0\n3 0 1 2\n", MeshFormat::Ply);
    EXPECT_NE(msg.find("x: line 11: bad number 'abc' (vertex 1 of 3)"), std::string::npos) << msg;
    msg = errorOf(kPlyHead + "0 0 0\n1 0 0\n0 1 0\n\n3 0 1 9\n", MeshFormat::Ply);
    EXPECT_NE(msg.find("x: line 14: vertex index 9 out of range (3 vertices) (face 0 of 1)"),
              std::string::npos)
        << msg;
    msg = errorOf(kPlyHead + "0 0 0\n1 0 0\n0 1 0\n3 0 1\n", MeshFormat::Ply);
    EXPECT_NE(msg.find("line 13: truncated"), std::string::npos) << msg;
    // Element counts that cannot fit name the element's line.
    msg = errorOf(
        "ply\nformat ascii 1.0\ncomment c\nelement vertex 99999999999\nproperty float "
        "x\nend_header\n1\n",
        MeshFormat::Ply);
    EXPECT_NE(msg.find("x: line 4: element 'vertex' claims more entries"), std::string::npos)
        << msg;
    // OBJ, OFF and ASCII STL: non-numeric coordinates and indices out of range.
    msg = errorOf("v 0 0 0\nv 1 0 0\n# c\nv 0 1,5 0\n", MeshFormat::Obj);
    EXPECT_NE(msg.find("x: line 4: bad vertex coordinate '1,5'"), std::string::npos) << msg;
    msg = errorOf("v 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nf 1 2 -4\r\n", MeshFormat::Obj);
    EXPECT_NE(msg.find("x: line 4: face index -4 out of range"), std::string::npos) << msg;
    msg = errorOf("OFF\n3 1 0\n0 0 0\n1 zero 0\n0 1 0\n3 0 1 2\n", MeshFormat::Off);
    EXPECT_NE(msg.find("x: line 4: bad vertex coordinate 'zero'"), std::string::npos) << msg;
    msg = errorOf("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", MeshFormat::Off);
    EXPECT_NE(msg.find("x: line 6: face index '3' out of range (3 vertices)"), std::string::npos)
        << msg;
    msg = errorOf("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n4 0 1 2\n", MeshFormat::Off);
    EXPECT_NE(msg.find("x: line 6: a face of 4 corners lists 3"), std::string::npos) << msg;
    msg = errorOf("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n18446744073709551615 0 1 2\n", MeshFormat::Off);
    EXPECT_NE(msg.find("x: line 6: a face of"), std::string::npos) << msg;
    msg = errorOf("4OFF\n3 1 0\n", MeshFormat::Off);
    EXPECT_NE(msg.find("x: line 1: the OFF variant '4OFF'"), std::string::npos) << msg;
    msg = errorOf("solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 nan\n",
                  MeshFormat::Stl);
    EXPECT_NE(msg.find("x: line 5: bad vertex coordinate 'nan'"), std::string::npos) << msg;
    msg = errorOf("solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n",
                  MeshFormat::Stl);
    EXPECT_NE(msg.find("x: line 5: truncated: the last facet is incomplete"), std::string::npos)
        << msg;
    // A binary PLY behind a UTF-16 header cannot be read; the one line says why.
    msg =
        errorOf(utf16("ply\nformat binary_little_endian 1.0\nelement vertex 0\nend_header\n", true),
                MeshFormat::Ply);
    EXPECT_NE(msg.find("UTF-16"), std::string::npos) << msg;
}

}  // namespace
