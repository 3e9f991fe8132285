#include "ui/image_view.h"

#include <algorithm>
#include <cmath>

namespace caustica::ui {

namespace {

// Magnified pixels stay sharp squares (nearest), a shrunk image is filtered.
void set_texture_parameters() {
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
}

}  // namespace

ImageView::ImageView()
    : programs_{GlProgram("image.vert", "image.frag", "#define TONE_CURVE 0\n"),
                GlProgram("image.vert", "image.frag", "#define TONE_CURVE 1\n"),
                GlProgram("image.vert", "image.frag", "#define TONE_CURVE 2\n")},
      compare_program_("image.vert", "image_compare.frag") {
    glGenVertexArrays(1, &vertex_array_);  // core profile: a bound VAO even without attributes
    glGenTextures(1, &texture_);
    glBindTexture(GL_TEXTURE_2D, texture_);
    set_texture_parameters();
    glGenTextures(1, &reference_);
    glBindTexture(GL_TEXTURE_2D, reference_);
    set_texture_parameters();
}

ImageView::~ImageView() {
    glDeleteTextures(1, &reference_);
    glDeleteTextures(1, &texture_);
    glDeleteVertexArrays(1, &vertex_array_);
}

void ImageView::upload_rect(const Image& image, int x0, int y0, int x1, int y1) {
    glTexSubImage2D(GL_TEXTURE_2D, 0, x0, y0, x1 - x0, y1 - y0, GL_RGB, GL_FLOAT, &image.at(x0, y0));
    ++upload_calls_;
}

void ImageView::upload(const PreviewDriver& driver) {
    uploaded_tiles_ = upload_calls_ = 0;
    const Image& image = driver.image();
    if (image.width <= 0 || image.height <= 0) return;
    glBindTexture(GL_TEXTURE_2D, texture_);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glPixelStorei(GL_UNPACK_ROW_LENGTH, image.width);
    if (image.width != width_ || image.height != height_ || driver.size_changed()) {
        width_ = image.width;
        height_ = image.height;
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB32F, width_, height_, 0, GL_RGB, GL_FLOAT, image.pixels.data());
        uploaded_tiles_ = driver.tiles().size();
        upload_calls_ = 1;
    } else {
        const std::vector<Tile>& tiles = driver.tiles();
        const std::vector<std::size_t>& changed = driver.changed_tiles();
        for (std::size_t k = 0; k < changed.size();) {
            // Tiles are numbered row by row: a run of consecutive numbers in one tile row is one rectangle.
            const Tile& first = tiles[changed[k]];
            std::size_t end = k + 1;
            while (end < changed.size() && changed[end] == changed[end - 1] + 1 &&
                   tiles[changed[end]].y0 == first.y0 && tiles[changed[end]].x0 == tiles[changed[end - 1]].x1)
                ++end;
            upload_rect(image, first.x0, first.y0, tiles[changed[end - 1]].x1, first.y1);
            uploaded_tiles_ += end - k;
            k = end;
        }
    }
    glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
}

void ImageView::set_reference(const Image& reference) {
    glBindTexture(GL_TEXTURE_2D, reference_);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
    if (reference.width <= 0 || reference.height <= 0) {
        reference_width_ = reference_height_ = 0;
        const float black[3] = {0.0f, 0.0f, 0.0f};
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB32F, 1, 1, 0, GL_RGB, GL_FLOAT, black);  // frees the old one
        return;
    }
    reference_width_ = reference.width;
    reference_height_ = reference.height;
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB32F, reference.width, reference.height, 0, GL_RGB, GL_FLOAT,
                 reference.pixels.data());
}

void ImageView::draw(const ImageLayout& layout, glm::vec2 window, const ViewTransform& view, const Compare& compare,
                     glm::ivec4 clip) const {
    if (width_ <= 0 || height_ <= 0) return;
    const int mode = reference_matches() ? compare.mode : 0;
    // The plain image has its own branch-free program: llvmpipe runs every branch of a shader, and
    // the comparison code tripled the cost of every frame's image quad (docs/PERFORMANCE.md).
    // Each tone curve has its own program too (TONE_CURVE in image.frag).
    const GlProgram& program = mode != 0 ? compare_program_ : programs_[tone_curve_index(view.tonemap)];
    glUseProgram(program.id());
    const glm::vec2 size = layout.size();
    glUniform4f(program.uniform("u_rect"), layout.origin.x, layout.origin.y, size.x, size.y);
    glUniform2f(program.uniform("u_window"), window.x, window.y);
    glUniform1f(program.uniform("u_exposure"), std::exp2(view.exposure_stops));
    glUniform1i(program.uniform("u_image"), 0);
    if (mode == 0) {
        glUniform1f(program.uniform("u_srgb"), view.srgb ? 1.0f : 0.0f);
    } else {
        const glm::vec3 curve = tonemap_weights(view.tonemap);
        glUniform3f(program.uniform("u_tonemap"), curve.x, curve.y, curve.z);
        glUniform1i(program.uniform("u_srgb"), view.srgb ? 1 : 0);
        glUniform1i(program.uniform("u_reference"), 1);
        glUniform1i(program.uniform("u_mode"), mode);
        glUniform1f(program.uniform("u_split"), compare.split);
        glUniform1f(program.uniform("u_gain"), compare.gain);
        glUniform1f(program.uniform("u_epsilon"), compare.epsilon);
        // Whole magnifications stay sharp (texel fetches); a shrunk image is filtered.
        const bool whole = layout.scale >= 1.0f && layout.scale == std::floor(layout.scale);
        glUniform1i(program.uniform("u_whole_pixels"), whole ? 1 : 0);
        glActiveTexture(GL_TEXTURE1);
        glBindTexture(GL_TEXTURE_2D, reference_);
    }
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, texture_);
    glBindVertexArray(vertex_array_);
    glDisable(GL_BLEND);
    glEnable(GL_SCISSOR_TEST);  // a zoomed image stays in its area
    glScissor(clip.x, clip.y, std::max(clip.z, 0), std::max(clip.w, 0));
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    glDisable(GL_SCISSOR_TEST);
    glBindVertexArray(0);
}

}  // namespace caustica::ui
