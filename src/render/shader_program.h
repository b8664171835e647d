// SPDX-License-Identifier: Apache-2.0
/// @file shader_program.h
/// @brief GLSL programs built from files in `shaders/`, loaded at run time, with compile and
/// link errors that name the file and line ("shaders/clay.frag:12: error: ...").
///
/// A stage's kind comes from its file's extension: .vert, .geom, .frag. Each file is one
/// complete GLSL source starting with its own `#version`; nothing is prepended, so the line
/// numbers a driver reports are the file's own.
///
/// Threading: GL objects of the context current when built; use them on its thread only.
#pragma once

#include <epoxy/gl.h>
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <filesystem>
#include <initializer_list>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace kizamu::render {

/// A shader failed to compile or a program failed to link. what() is one line per driver
/// message, each starting with the file and, where the driver gave one, the line:
/// "shaders/clay.frag:12: error: syntax error, unexpected ...".
class ShaderError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// A linked GL program. Owned by its renderer; move-only; not thread-safe.
class ShaderProgram {
public:
    ShaderProgram() = default;
    /// Takes ownership of a linked program object.
    explicit ShaderProgram(GLuint program, std::string name)
        : mId(program), mName(std::move(name)) {}
    ShaderProgram(ShaderProgram&& other) noexcept;
    ShaderProgram& operator=(ShaderProgram&& other) noexcept;
    ShaderProgram(const ShaderProgram&) = delete;
    ShaderProgram& operator=(const ShaderProgram&) = delete;
    ~ShaderProgram();

    GLuint id() const { return mId; }
    /// The stage files it was built from, joined with " + ".
    const std::string& name() const { return mName; }
    /// glUseProgram.
    void use() const { glUseProgram(mId); }

    /// Uniform setters on the program in use. A name the program lacks (unused uniforms are
    /// optimised away) is ignored, as GL ignores location -1. Each looks the location up by
    /// name (a driver string lookup): cheap at a few uniforms per draw; cache locations before
    /// setting many per frame.
    void set(const char* name, float v) const { glUniform1f(location(name), v); }
    void set(const char* name, int v) const { glUniform1i(location(name), v); }
    void set(const char* name, const glm::vec2& v) const;
    void set(const char* name, const glm::vec3& v) const;
    void set(const char* name, const glm::vec4& v) const;
    void set(const char* name, const glm::mat3& m) const;
    void set(const char* name, const glm::mat4& m) const;

private:
    GLint location(const char* name) const { return glGetUniformLocation(mId, name); }
    GLuint mId = 0;
    std::string mName;
};

/// Finds shader files in one directory and builds programs from them.
/// Cheap to copy (a path); holds no GL objects.
class ShaderLibrary {
public:
    /// Shaders read from `directory`.
    explicit ShaderLibrary(std::filesystem::path directory) : mDirectory(std::move(directory)) {}
    /// Shaders from the default directory (defaultDirectory()).
    ShaderLibrary() : ShaderLibrary(defaultDirectory()) {}

    /// Where the shaders are by default: $KIZAMU_SHADER_DIR when set; else `shaders/` beside the
    /// executable when present (an installed app); else the source tree's `shaders/` (a build
    /// run in place; KIZAMU_SOURCE_SHADER_DIR, set by CMake).
    static std::filesystem::path defaultDirectory();

    const std::filesystem::path& directory() const { return mDirectory; }
    /// The shader files in the directory (extensions .vert .geom .frag), sorted by name.
    std::vector<std::string> files() const;

    /// Compiles one stage from `file` (a name in the directory) and returns the shader object
    /// (the caller deletes it).
    /// @throw ShaderError naming the file and line when it does not compile, or the file when
    ///        it cannot be read or its extension names no stage.
    /// Complexity: the driver's compiler. Threading: a current GL context.
    GLuint compile(const std::string& file) const;

    /// Compiles and links `stageFiles` (e.g. {"clay.vert", "clay.frag"}) into a program.
    /// @throw ShaderError as compile(), or naming the files and the linker's messages.
    ShaderProgram build(std::initializer_list<std::string> stageFiles) const;
    ShaderProgram build(const std::vector<std::string>& stageFiles) const;

private:
    std::filesystem::path mDirectory;
};

namespace detail {
/// Rewrites a driver's info log so each message names `file` and its line: Mesa's "0:12(5): "
/// and NVIDIA's "0(12) : " prefixes, and the "ERROR: 0:12: " form, become "file:12: ";
/// other lines become "file: ...". Blank lines are dropped; lines are joined with '\n'.
std::string formatShaderLog(const std::string& file, const std::string& log);
}  // namespace detail

}  // namespace kizamu::render
