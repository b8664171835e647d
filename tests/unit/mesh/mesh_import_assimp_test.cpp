// SPDX-License-Identifier: Apache-2.0
// Formats only assimp reads, imported through the helper process (kizamu-import): assimp's own
// exports of a generated mesh come back with the same triangles, volume and bounds; files assimp
// cannot read, and helpers that crash, hang, fail or reply nonsense, give one-line errors and
// leave this process running; the reply decoder refuses every malformed reply.
#include "mesh/mesh_export.h"
#include "mesh/mesh_import.h"
#include "mesh/mesh_import_assimp.h"
#include "mesh/mesh_import_reply.h"

#include "tests/util/uv_sphere.h"
#include "util/file_error.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <string>
#include <thread>
#include <unistd.h>
#include <vector>

using namespace kizamu;
using namespace kizamu::mesh;

namespace {

/// A closed UV sphere stretched to an ellipsoid and moved off the origin, so that a swapped
/// axis, a lost transform or a unit scale shows in the bounds.
MeshBuffers ellipsoid(int rings, int segments) {
    return test::uvEllipsoid(glm::vec3(0.5f, -0.25f, 1.5f), glm::vec3(0.3f, 0.5f, 0.7f), rings, segments);
}

double signedVolume(const MeshBuffers& m) {
    double v = 0.0;
    for (std::size_t t = 0; t < m.indices.size(); t += 3)
        v += glm::dot(glm::dvec3(m.positions[m.indices[t]]),
                      glm::cross(glm::dvec3(m.positions[m.indices[t + 1]]), glm::dvec3(m.positions[m.indices[t + 2]]))) /
             6.0;
    return v;
}

void bounds(const MeshBuffers& m, glm::vec3& lo, glm::vec3& hi) {
    lo = glm::vec3(std::numeric_limits<float>::max());
    hi = -lo;
    for (const glm::vec3& p : m.positions) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
}

std::string errorOf(const std::function<void()>& f) {
    try {
        f();
    } catch (const FileError& e) {
        const std::string msg = e.what();
        EXPECT_EQ(msg.find('\n'), std::string::npos) << "one line: " << msg;
        return msg;
    }
    ADD_FAILURE() << "no FileError";
    return "";
}

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

bool anyOf(const std::vector<std::string>& lines, const std::string& part) {
    for (const std::string& l : lines)
        if (contains(l, part)) return true;
    return false;
}

class AssimpImport : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        // The helper built beside the app (tests/CMakeLists.txt); an explicit setting wins.
        ::setenv("KIZAMU_IMPORT_HELPER", KIZAMU_IMPORT_HELPER_PATH, 0);
        sDir = std::filesystem::temp_directory_path() / ("kizamu_assimp_" + std::to_string(::getpid()));
        std::filesystem::create_directories(sDir);
    }
    static void TearDownTestSuite() { std::filesystem::remove_all(sDir); }
    static std::string path(const std::string& name) { return (sDir / name).string(); }
    static std::string write(const std::string& name, const std::string& bytes, bool executable = false) {
        const std::string p = path(name);
        std::ofstream(p, std::ios::binary) << bytes;
        if (executable) std::filesystem::permissions(p, std::filesystem::perms::owner_all);
        return p;
    }
    /// A stand-in helper: a shell script.
    static AssimpImportSettings fakeHelper(const std::string& name, const std::string& script, double timeoutS = 0.0) {
        return {write(name, "#!/bin/sh\n" + script + "\n", true), timeoutS};
    }
    static std::filesystem::path sDir;
};
std::filesystem::path AssimpImport::sDir;

TEST_F(AssimpImport, AssimpExportsComeBackWithTheSameTriangles) {
    const MeshBuffers source = ellipsoid(12, 16);
    const std::string obj = path("source.obj");
    exportMesh(source, obj, {.unit = LengthUnit::Metre});  // assimp reads OBJ numbers as metres
    glm::vec3 lo, hi;
    bounds(source, lo, hi);
    const double volume = signedVolume(source);
    ASSERT_GT(volume, 0.0);
    struct Case {
        const char* exportId;  // `assimp listexport`
        const char* file;
        float scale;           // what the unit the exporter declares makes of the source's numbers
        bool zUp = false;      // (x, y, z) comes back as (x, z, -y)
    };
    // Not binary FBX: Debian's assimp 5.2.5 cannot read its own binary FBX export back
    // ("FBX-Tokenize ... block offset is out of range"); its ASCII FBX it reads.
    const Case cases[] = {{"gltf2", "out.gltf", 1.0f}, {"glb2", "out.glb", 1.0f}, {"collada", "out.dae", 1.0f},
                          {"fbxa", "out.fbx", 0.01f},  // FBX in centimetres (UnitScaleFactor 1)
                          {"3ds", "out.3ds", 1.0f, true},  // Y-up to 3DS's Z-up, not turned back
                              {"x", "out.x", 1.0f},     {"x3d", "out.x3d", 1.0f}};
    for (const Case& c : cases) {
        SCOPED_TRACE(c.file);
        const std::string out = path(c.file);
        const std::string cmd = "assimp export '" + obj + "' '" + out + "' -f" + c.exportId + " >/dev/null 2>&1";
        ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd << " (assimp-utils is required: scripts/install-deps)";
        std::vector<std::string> warnings;
        bool inMetres = false;
        MeshBuffers back = importMesh(out, &warnings, &inMetres);
        const std::string ext = std::filesystem::path(out).extension().string();
        EXPECT_EQ(inMetres, ext == ".gltf" || ext == ".glb" || ext == ".dae" || ext == ".fbx")
            << "only glTF, COLLADA and FBX declare a unit the helper applies";
        if (c.zUp)
            for (glm::vec3& p : back.positions) p = glm::vec3(p.x, -p.z, p.y);
        ASSERT_TRUE(back.valid());
        EXPECT_EQ(back.triangleCount(), source.triangleCount());
        EXPECT_EQ(back.vertexCount(), source.vertexCount());  // joined by position again
        glm::vec3 blo, bhi;
        bounds(back, blo, bhi);
        for (int a = 0; a < 3; ++a) {
            EXPECT_NEAR(blo[a], lo[a] * c.scale, 1e-6f * c.scale) << "axis " << a;
            EXPECT_NEAR(bhi[a], hi[a] * c.scale, 1e-6f * c.scale) << "axis " << a;
        }
        const double s3 = double(c.scale) * c.scale * c.scale;
        EXPECT_NEAR(signedVolume(back), volume * s3, 1e-5 * volume * s3);  // also: the winding kept
        // Every vertex is one of the source's.
        for (const glm::vec3& p : back.positions) {
            float best = std::numeric_limits<float>::max();
            for (const glm::vec3& q : source.positions) best = std::min(best, glm::distance(p, q * c.scale));
            ASSERT_LT(best, 1e-5f * c.scale);
        }
        EXPECT_EQ(anyOf(warnings, "scaled by 0.01 to metres"), c.scale != 1.0f);
    }
}

TEST_F(AssimpImport, ContentDecidesBeforeTheExtension) {
    exportMesh(ellipsoid(6, 8), path("e.glb"));  // our glb, read by assimp
    const MeshBuffers glb = importMesh(path("e.glb"));
    EXPECT_EQ(glb.triangleCount(), ellipsoid(6, 8).triangleCount());
    // glTF binary content under an OBJ name: assimp reads it, and a warning says so.
    std::filesystem::copy_file(path("e.glb"), path("e_glb.obj"));
    std::vector<std::string> warnings;
    EXPECT_EQ(importMesh(path("e_glb.obj"), &warnings).triangleCount(), glb.triangleCount());
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_TRUE(contains(warnings[0], "the extension names OBJ, but the content is glTF binary")) << warnings[0];
    // OBJ content under a COLLADA name: our reader, with a warning.
    warnings.clear();
    const std::string objAsDae = write("tri.dae", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    EXPECT_EQ(importMesh(objAsDae, &warnings).triangleCount(), 1u);
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_TRUE(contains(warnings[0], "the extension is .dae, but the content is OBJ")) << warnings[0];
    // Neither: still one line.
    EXPECT_TRUE(contains(errorOf([&] { importMesh(write("notes.txt", "hello\n")); }), "unknown mesh format"));
}

TEST_F(AssimpImport, AFileAssimpCannotReadIsOneLine) {
    const std::string fbx = write("broken.fbx", "this is not\nan FBX file\n");
    const std::string e = errorOf([&] { importMesh(fbx); });
    EXPECT_EQ(e.rfind(fbx + ": assimp cannot read it: ", 0), 0u) << e;
    const std::string dae = write("broken.dae", "<?xml version=\"1.0\"?>\n<COLLADA><library_geometries>");
    EXPECT_TRUE(contains(errorOf([&] { importMesh(dae); }), dae + ": ")) << dae;
    // A scene without triangles: points only.
    const std::string points = write("points.dae", std::string(R"(<?xml version="1.0"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1"><asset><unit meter="1"/></asset>
</COLLADA>)"));
    EXPECT_TRUE(contains(errorOf([&] { importMesh(points); }), points + ": ")) << points;
}

TEST_F(AssimpImport, AHelperThatCrashesHangsOrFailsIsOneLineAndWeCarryOn) {
    const std::string file = write("any.fbx", "whatever");
    EXPECT_TRUE(contains(errorOf([&] { importWithAssimp(file, fakeHelper("segv.sh", "kill -SEGV $$")); }),
                         "assimp crashed reading it (signal 11"));
    EXPECT_TRUE(contains(errorOf([&] { importWithAssimp(file, fakeHelper("abort.sh", "kill -ABRT $$")); }),
                         "(signal 6"));
    EXPECT_TRUE(contains(errorOf([&] { importWithAssimp(file, fakeHelper("exit7.sh", "echo 'a library is missing' >&2; exit 7")); }),
                         "failed (exit status 7): a library is missing"));
    EXPECT_TRUE(contains(errorOf([&] { importWithAssimp(file, fakeHelper("junk.sh", "printf 'KZIMPRT1junk'")); }),
                         "reply is malformed"));
    EXPECT_TRUE(contains(errorOf([&] { importWithAssimp(file, fakeHelper("silent.sh", "exit 0")); }), "no reply"));
    EXPECT_TRUE(contains(errorOf([&] { importWithAssimp(file, {"/nonexistent/kizamu-import", 0.0}); }),
                         "cannot start the import helper /nonexistent/kizamu-import"));
    // A hang, with a grandchild that holds the pipe open: the whole group is killed at the limit.
    const auto t0 = std::chrono::steady_clock::now();
    EXPECT_TRUE(contains(errorOf([&] { importWithAssimp(file, fakeHelper("hang.sh", "sleep 60 & sleep 60", 0.5)); }),
                         "took longer than 0.5 s"));
    // The limit from the environment.
    ::setenv("KIZAMU_IMPORT_TIMEOUT_S", "0.25", 1);
    EXPECT_TRUE(contains(errorOf([&] { importWithAssimp(file, fakeHelper("hang2.sh", "exec sleep 60")); }),
                         "took longer than 0.25 s"));
    ::unsetenv("KIZAMU_IMPORT_TIMEOUT_S");
    EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(10));
}

TEST_F(AssimpImport, ImportsFromSeveralThreadsAtOnce) {
    // posix_spawn in a process with running threads: every import gets its own child.
    exportMesh(ellipsoid(8, 10), path("t.glb"));
    const std::size_t want = ellipsoid(8, 10).triangleCount();
    std::vector<std::thread> threads;
    std::vector<std::size_t> got(4, 0);
    for (int i = 0; i < 4; ++i)
        threads.emplace_back([&, i] {
            try {
                got[i] = importMesh(path("t.glb")).triangleCount();
            } catch (...) {
            }
        });
    for (auto& t : threads) t.join();
    for (std::size_t n : got) EXPECT_EQ(n, want);
}

TEST(ImportReply, RoundTripsAndRefusesWhatTheLayoutDoesNotAllow) {
    MeshBuffers m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    m.indices = {0, 1, 2};
    std::vector<std::string> warnings;
    const std::string reply = encodeImportReply(m, {"a\nwarning"});
    const MeshBuffers back = decodeImportReply(reply, "f.fbx", &warnings);
    EXPECT_EQ(back.positions, m.positions);
    EXPECT_EQ(back.indices, m.indices);
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_EQ(warnings[0], "f.fbx: a warning");
    EXPECT_EQ(errorOf([&] { decodeImportReply(encodeImportError("no\nreader"), "f.fbx"); }), "f.fbx: no reader");

    const auto malformed = [&](std::string bytes, const std::string& what) {
        SCOPED_TRACE(what);
        const std::string e = errorOf([&] { decodeImportReply(bytes, "f"); });
        EXPECT_TRUE(contains(e, "f: the import helper's reply is malformed: " + what)) << e;
    };
    malformed(reply.substr(0, reply.size() - 1), "3 vertices and 1 triangles need 48 bytes, 47 are left");
    malformed(reply + "x", "3 vertices and 1 triangles need 48 bytes, 49 are left");
    malformed("KZIMPRT2" + reply.substr(8), "no KZIMPRT1 magic");
    malformed(reply.substr(0, 5), "no KZIMPRT1 magic");
    std::string bad = reply;
    bad[8] = 7;
    malformed(bad, "unknown kind 7");
    bad = reply;
    const uint32_t three = 3;
    std::memcpy(bad.data() + bad.size() - 4, &three, 4);
    malformed(bad, "triangle 0 has index 3 of 3 vertices (byte " + std::to_string(reply.size() - 4) + " of");
    bad = reply;
    const float nan = std::nanf("");
    std::memcpy(bad.data() + bad.size() - 12 - 36 + 4, &nan, 4);
    malformed(bad, "vertex 0 is not finite (byte " + std::to_string(reply.size() - 48) + " of");
    bad = reply;
    bad[12 + 4 + 4 + 1] = '\t';  // inside the warning
    malformed(bad, "a control character in a warning");
    std::string err = encodeImportError("x");
    malformed(err + "y", "1 bytes after the error message");
    std::memset(err.data() + 12, 0, 4);
    malformed(err.substr(0, 16), "a message of 0 bytes");
    std::string huge = std::string(kImportReplyMagic) + std::string("\1\0\0\0\0\0\0\0", 8) + std::string("\xff\xff\xff\xff\xff\xff\xff\xff", 8);
    malformed(huge, "4294967295 vertices and 4294967295 triangles need");
    // Found by the fuzzer: no vertices and a triangle (a null copy before the index check).
    malformed(std::string(kImportReplyMagic) + std::string("\1\0\0\0\0\0\0\0\0\0\0\0\1\0\0\0", 16) + "PRT1\1\0\0\0\0\0\0\0",
              "no vertices");
    EXPECT_TRUE(contains(errorOf([&] { decodeImportReply("", "f"); }), "f: the import helper gave no reply"));
}

}  // namespace
