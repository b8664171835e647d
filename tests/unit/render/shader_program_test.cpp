// SPDX-License-Identifier: Apache-2.0
/// @file shader_program_test.cpp
/// @brief Every shader in shaders/ compiles and the renderer's programs link; a broken shader's
/// error names its file and line; driver logs of several vendors are rewritten to file:line.
#include "render/shader_program.h"
#include "render/clay_renderer.h"
#include "tests/unit/render/render_fixture.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace kizamu::render {
namespace {

namespace fs = std::filesystem;

class ShaderTest : public test::RenderTest {};

TEST_F(ShaderTest, EveryShaderFileCompiles) {
    const ShaderLibrary lib = shaders();
    const std::vector<std::string> files = lib.files();
    ASSERT_GE(files.size(), 4u) << "no shaders found in " << lib.directory();
    for (const std::string& f : files) {
        SCOPED_TRACE(f);
        GLuint s = 0;
        EXPECT_NO_THROW(s = lib.compile(f));
        if (s) glDeleteShader(s);
    }
}

TEST_F(ShaderTest, RendererProgramsLink) {
    EXPECT_NO_THROW(ClayRenderer renderer(shaders()));
}

/// A directory holding the source tree's shaders, for tests that break one of them.
fs::path copyOfShaders(const std::string& name) {
    const fs::path dir =
        fs::temp_directory_path() / ("kizamu-shaders-" + name + "-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    for (const fs::directory_entry& e : fs::directory_iterator(KIZAMU_SOURCE_SHADER_DIR))
        fs::copy_file(e.path(), dir / e.path().filename());
    return dir;
}

TEST_F(ShaderTest, CorruptShaderNamesFileAndLine) {
    const fs::path dir = copyOfShaders("corrupt");
    {
        std::ofstream out(dir / "clay.frag", std::ios::trunc);
        out << "#version 330 core\n"                    // 1
               "out vec4 fragColour;\n"                 // 2
               "void main() {\n"                        // 3
               "    fragColour = vec4(1.0);\n"          // 4
               "    float x = undefinedThing * 2.0;\n"  // 5: the error
               "}\n";
    }
    const std::string expected = (dir / "clay.frag").string() + ":5: ";
    try {
        ClayRenderer renderer{ShaderLibrary(dir)};
        ADD_FAILURE() << "a corrupt clay.frag built";
    } catch (const ShaderError& e) {
        const std::string what = e.what();
        EXPECT_EQ(what.rfind(expected, 0), 0u)
            << "the error does not start with '" << expected << "': " << what;
        EXPECT_NE(what.find("error"), std::string::npos) << what;
        EXPECT_NE(what.find("undefinedThing"), std::string::npos) << what;
    }
    fs::remove_all(dir);
}

TEST_F(ShaderTest, MissingShaderNamesFile) {
    const fs::path dir = copyOfShaders("missing");
    fs::remove(dir / "matcap.frag");
    try {
        ClayRenderer renderer{ShaderLibrary(dir)};
        ADD_FAILURE() << "built without matcap.frag";
    } catch (const ShaderError& e) {
        EXPECT_NE(std::string(e.what()).find((dir / "matcap.frag").string() + ": cannot open"),
                  std::string::npos)
            << e.what();
    }
    fs::remove_all(dir);
}

TEST_F(ShaderTest, LinkErrorNamesTheProgram) {
    const fs::path dir = copyOfShaders("link");
    {
        // Compiles on its own, but a program needs a main() in each stage.
        std::ofstream out(dir / "wire.frag", std::ios::trunc);
        out << "#version 330 core\nout vec4 fragColour;\nvoid notMain() { fragColour = vec4(1.0); "
               "}\n";
    }
    try {
        ClayRenderer renderer{ShaderLibrary(dir)};
        ADD_FAILURE() << "linked a fragment stage without main()";
    } catch (const ShaderError& e) {
        EXPECT_NE(std::string(e.what()).find("clay.vert + wire.frag"), std::string::npos)
            << e.what();
    }
    fs::remove_all(dir);
}

TEST(ShaderLog, VendorFormatsBecomeFileAndLine) {
    using detail::formatShaderLog;
    EXPECT_EQ(formatShaderLog("shaders/clay.frag",
                              "0:12(5): error: syntax error, unexpected IDENTIFIER\n"),
              "shaders/clay.frag:12: error: syntax error, unexpected IDENTIFIER");
    EXPECT_EQ(formatShaderLog("a.frag", "0(7) : error C1008: undefined variable \"x\"\n"),
              "a.frag:7: error C1008: undefined variable \"x\"");
    EXPECT_EQ(formatShaderLog("a.vert", "ERROR: 0:3: 'foo' : undeclared identifier\n"),
              "a.vert:3: error: 'foo' : undeclared identifier");
    EXPECT_EQ(formatShaderLog("a.vert", "0:1(1): warning: w\n\n0:2(3): error: e\n"),
              "a.vert:1: warning: w\na.vert:2: error: e");
    EXPECT_EQ(formatShaderLog("p", "error: linking failed\n"), "p: error: linking failed");
    // Near misses keep their text, with the file in front.
    EXPECT_EQ(formatShaderLog("a", "0:12 error\n"), "a: 0:12 error");
    EXPECT_EQ(formatShaderLog("a", "12(x): e\n"), "a: 12(x): e");
    EXPECT_EQ(formatShaderLog("a", "  0:4(10): error: indented\r\n"), "a:4: error: indented");
    EXPECT_EQ(formatShaderLog("p", ""), "p: failed with no message from the driver");
}

TEST(ShaderLibraryDefault, EnvironmentWins) {
    setenv("KIZAMU_SHADER_DIR", "/some/where", 1);
    EXPECT_EQ(ShaderLibrary::defaultDirectory(), fs::path("/some/where"));
    unsetenv("KIZAMU_SHADER_DIR");
    EXPECT_TRUE(fs::is_directory(ShaderLibrary::defaultDirectory()))
        << ShaderLibrary::defaultDirectory();
}

}  // namespace
}  // namespace kizamu::render
