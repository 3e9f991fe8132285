#include "ui/gl_program.h"

#include "ui/shader_sources.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace caustica::ui {
namespace {

GLuint compile(GLenum kind, std::string_view name, std::string_view defines = {}) {
    const std::string_view text = shader_source(name);
    // The #version line must come first: the defines go right after it.
    const std::size_t first_line = std::min(text.find('\n'), text.size() - 1) + 1;
    const std::string_view parts[3] = {text.substr(0, first_line), defines, text.substr(first_line)};
    const GLchar* data[3];
    GLint length[3];
    for (int i = 0; i < 3; ++i) {
        data[i] = parts[i].empty() ? "" : parts[i].data();  // never a null string, even of length 0
        length[i] = static_cast<GLint>(parts[i].size());
    }
    const GLuint shader = glCreateShader(kind);
    glShaderSource(shader, 3, data, length);
    glCompileShader(shader);
    GLint ok = GL_FALSE;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (ok == GL_TRUE) return shader;
    char log[2048] = {};
    glGetShaderInfoLog(shader, sizeof log, nullptr, log);
    glDeleteShader(shader);
    throw std::runtime_error("shaders/" + std::string(name) + ": " + log);
}

}  // namespace

GlProgram::GlProgram(std::string_view vertex, std::string_view fragment, std::string_view defines) {
    const GLuint vs = compile(GL_VERTEX_SHADER, vertex);
    GLuint fs = 0;
    try {
        fs = compile(GL_FRAGMENT_SHADER, fragment, defines);
    } catch (...) {
        glDeleteShader(vs);
        throw;
    }
    id_ = glCreateProgram();
    glAttachShader(id_, vs);
    glAttachShader(id_, fs);
    glLinkProgram(id_);
    glDeleteShader(vs);
    glDeleteShader(fs);
    GLint ok = GL_FALSE;
    glGetProgramiv(id_, GL_LINK_STATUS, &ok);
    if (ok == GL_TRUE) return;
    char log[2048] = {};
    glGetProgramInfoLog(id_, sizeof log, nullptr, log);
    glDeleteProgram(id_);
    id_ = 0;
    throw std::runtime_error("linking shaders/" + std::string(vertex) + " + " + std::string(fragment) + ": " + log);
}

GlProgram::~GlProgram() {
    if (id_) glDeleteProgram(id_);
}

GlProgram& GlProgram::operator=(GlProgram&& other) noexcept {
    if (this != &other) {
        if (id_) glDeleteProgram(id_);
        id_ = other.id_;
        other.id_ = 0;
    }
    return *this;
}

}  // namespace caustica::ui
