#include "ui/gl_program.h"

#include "ui/shader_sources.h"

#include <stdexcept>
#include <string>

namespace caustica::ui {
namespace {

GLuint compile(GLenum kind, std::string_view name) {
    const std::string_view text = shader_source(name);
    const GLuint shader = glCreateShader(kind);
    const GLchar* data = text.data();
    const GLint length = static_cast<GLint>(text.size());
    glShaderSource(shader, 1, &data, &length);
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

GlProgram::GlProgram(std::string_view vertex, std::string_view fragment) {
    const GLuint vs = compile(GL_VERTEX_SHADER, vertex);
    GLuint fs = 0;
    try {
        fs = compile(GL_FRAGMENT_SHADER, fragment);
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
