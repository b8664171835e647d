// SPDX-License-Identifier: Apache-2.0
/// @file shader_program.cpp
/// @brief Shader files to GL programs, with file:line errors (see shader_program.h).
#include "render/shader_program.h"

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string_view>
#include <system_error>
#include <utility>

#ifndef KIZAMU_SOURCE_SHADER_DIR
#define KIZAMU_SOURCE_SHADER_DIR "shaders"
#endif

namespace kizamu::render {

namespace fs = std::filesystem;

ShaderProgram::ShaderProgram(ShaderProgram&& other) noexcept {
    *this = std::move(other);
}

ShaderProgram& ShaderProgram::operator=(ShaderProgram&& other) noexcept {
    if (this != &other) {
        if (mId) glDeleteProgram(mId);
        mId = std::exchange(other.mId, 0);
        mName = std::move(other.mName);
    }
    return *this;
}

ShaderProgram::~ShaderProgram() {
    if (mId) glDeleteProgram(mId);
}

void ShaderProgram::set(const char* name, const glm::vec2& v) const {
    glUniform2fv(location(name), 1, glm::value_ptr(v));
}
void ShaderProgram::set(const char* name, const glm::vec3& v) const {
    glUniform3fv(location(name), 1, glm::value_ptr(v));
}
void ShaderProgram::set(const char* name, const glm::vec4& v) const {
    glUniform4fv(location(name), 1, glm::value_ptr(v));
}
void ShaderProgram::set(const char* name, const glm::mat3& m) const {
    glUniformMatrix3fv(location(name), 1, GL_FALSE, glm::value_ptr(m));
}
void ShaderProgram::set(const char* name, const glm::mat4& m) const {
    glUniformMatrix4fv(location(name), 1, GL_FALSE, glm::value_ptr(m));
}

namespace {

/// The GL stage an extension names; 0 for none.
GLenum stageOf(const fs::path& file) {
    const std::string ext = file.extension().string();
    if (ext == ".vert") return GL_VERTEX_SHADER;
    if (ext == ".geom") return GL_GEOMETRY_SHADER;
    if (ext == ".frag") return GL_FRAGMENT_SHADER;
    return 0;
}

std::string infoLog(GLuint object, bool program) {
    GLint length = 0;
    if (program)
        glGetProgramiv(object, GL_INFO_LOG_LENGTH, &length);
    else
        glGetShaderiv(object, GL_INFO_LOG_LENGTH, &length);
    std::string log(std::size_t(std::max(length, 1)), '\0');
    GLsizei written = 0;
    if (program)
        glGetProgramInfoLog(object, GLsizei(log.size()), &written, log.data());
    else
        glGetShaderInfoLog(object, GLsizei(log.size()), &written, log.data());
    log.resize(std::size_t(written));
    return log;
}

}  // namespace

namespace detail {

namespace {

/// A cursor over one log line, for the three prefixes formatShaderLog reads.
struct LineCursor {
    std::string_view rest;
    void skipSpaces() {
        while (!rest.empty() && (rest.front() == ' ' || rest.front() == '\t'))
            rest.remove_prefix(1);
    }
    bool eat(std::string_view token) {
        if (rest.substr(0, token.size()) != token) return false;
        rest.remove_prefix(token.size());
        return true;
    }
    /// Digits, as text; empty when there are none.
    std::string_view number() {
        std::size_t n = 0;
        while (n < rest.size() && rest[n] >= '0' && rest[n] <= '9') ++n;
        const std::string_view digits = rest.substr(0, n);
        rest.remove_prefix(n);
        return digits;
    }
};

/// "file:LINE: message" when `line` has one of the prefixes; empty otherwise.
std::string withLine(const std::string& file, std::string_view line) {
    // Mesa "0:12(5): error: ..." and NVIDIA "0(12) : error C0000: ...": the first number is
    // the source string (always 0: one string per file), the next the line.
    LineCursor c{line};
    c.skipSpaces();
    if (!c.number().empty()) {
        std::string_view lineNo;
        if (c.eat(":")) {
            lineNo = c.number();
            if (lineNo.empty() || !c.eat("(") || c.number().empty() || !c.eat(")")) return {};
        } else if (c.eat("(")) {
            lineNo = c.number();
            if (lineNo.empty() || !c.eat(")")) return {};
        } else {
            return {};
        }
        c.skipSpaces();
        if (!c.eat(":")) return {};
        c.skipSpaces();
        return file + ":" + std::string(lineNo) + ": " + std::string(c.rest);
    }
    // AMD, Intel on Windows and glslang: "ERROR: 0:12: message" (and WARNING).
    c = LineCursor{line};
    c.skipSpaces();
    std::string kind;
    if (c.eat("ERROR:"))
        kind = "error";
    else if (c.eat("WARNING:"))
        kind = "warning";
    else
        return {};
    c.skipSpaces();
    if (c.number().empty() || !c.eat(":")) return {};
    const std::string_view lineNo = c.number();
    if (lineNo.empty() || !c.eat(":")) return {};
    c.skipSpaces();
    return file + ":" + std::string(lineNo) + ": " + kind + ": " + std::string(c.rest);
}

}  // namespace

std::string formatShaderLog(const std::string& file, const std::string& log) {
    std::istringstream in(log);
    std::string line, out;
    while (std::getline(in, line)) {
        while (!line.empty() && (line.back() == '\r' || line.back() == ' ' || line.back() == '\0'))
            line.pop_back();
        const std::size_t first = line.find_first_not_of(" \t");
        if (first == std::string::npos) continue;
        std::string formatted = withLine(file, line);
        if (formatted.empty()) formatted = file + ": " + line.substr(first);
        if (!out.empty()) out += '\n';
        out += formatted;
    }
    return out.empty() ? file + ": failed with no message from the driver" : out;
}

}  // namespace detail

fs::path ShaderLibrary::defaultDirectory() {
    if (const char* env = std::getenv("KIZAMU_SHADER_DIR"); env && *env) return fs::path(env);
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (!ec) {
        const fs::path beside = exe.parent_path() / "shaders";
        if (fs::is_directory(beside, ec)) return beside;
    }
    return fs::path(KIZAMU_SOURCE_SHADER_DIR);
}

std::vector<std::string> ShaderLibrary::files() const {
    std::vector<std::string> names;
    std::error_code ec;
    for (const fs::directory_entry& e : fs::directory_iterator(mDirectory, ec))
        if (e.is_regular_file() && stageOf(e.path()) != 0)
            names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
}

GLuint ShaderLibrary::compile(const std::string& file) const {
    const fs::path path = mDirectory / file;
    const std::string shown = path.string();
    const GLenum stage = stageOf(path);
    if (stage == 0) throw ShaderError(shown + ": not a shader stage (.vert, .geom or .frag)");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw ShaderError(shown + ": cannot open the shader");
    std::ostringstream text;
    text << in.rdbuf();
    const std::string source = text.str();
    const GLuint shader = glCreateShader(stage);
    const char* src = source.c_str();
    const GLint length = GLint(source.size());
    glShaderSource(shader, 1, &src, &length);
    glCompileShader(shader);
    GLint ok = GL_FALSE;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        const std::string log = infoLog(shader, false);
        glDeleteShader(shader);
        throw ShaderError(detail::formatShaderLog(shown, log));
    }
    return shader;
}

ShaderProgram ShaderLibrary::build(std::initializer_list<std::string> stageFiles) const {
    return build(std::vector<std::string>(stageFiles));
}

ShaderProgram ShaderLibrary::build(const std::vector<std::string>& stageFiles) const {
    std::string name;
    for (const std::string& f : stageFiles) name += (name.empty() ? "" : " + ") + f;
    std::vector<GLuint> shaders;
    try {
        for (const std::string& f : stageFiles) shaders.push_back(compile(f));
    } catch (...) {
        for (GLuint s : shaders) glDeleteShader(s);
        throw;
    }
    const GLuint program = glCreateProgram();
    for (GLuint s : shaders) glAttachShader(program, s);
    glLinkProgram(program);
    for (GLuint s : shaders) {
        glDetachShader(program, s);
        glDeleteShader(s);
    }
    GLint ok = GL_FALSE;
    glGetProgramiv(program, GL_LINK_STATUS, &ok);
    if (!ok) {
        const std::string log = infoLog(program, true);
        glDeleteProgram(program);
        throw ShaderError(
            detail::formatShaderLog((mDirectory / "").string() + "{" + name + "} (link)", log));
    }
    return ShaderProgram(program, name);
}

}  // namespace kizamu::render
