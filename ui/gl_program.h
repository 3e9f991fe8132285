// A linked GLSL program built from two of the embedded shaders.
#pragma once

#include "ui/gl_api.h"

#include <string_view>

namespace caustica::ui {

/// Owns a GL program object (needs a current context to build and to destroy).
class GlProgram {
public:
    GlProgram() = default;
    /// Compiles and links shaders/<vertex> and shaders/<fragment>, the fragment shader with `defines`
    /// (lines such as "#define TONE_CURVE 1\n") after its #version line; throws std::runtime_error
    /// with the compiler's log on failure.
    GlProgram(std::string_view vertex, std::string_view fragment, std::string_view defines = {});
    ~GlProgram();
    GlProgram(GlProgram&& other) noexcept : id_(other.id_) { other.id_ = 0; }
    GlProgram& operator=(GlProgram&& other) noexcept;
    GlProgram(const GlProgram&) = delete;
    GlProgram& operator=(const GlProgram&) = delete;

    /// The program object.
    GLuint id() const { return id_; }
    /// The location of a uniform (-1 when the shader has none of that name).
    GLint uniform(const char* name) const { return glGetUniformLocation(id_, name); }

private:
    GLuint id_ = 0;
};

}  // namespace caustica::ui
