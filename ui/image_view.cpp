#include "ui/image_view.h"

#include <cmath>

namespace caustica::ui {

ImageView::ImageView() : program_("image.vert", "image.frag") {
    glGenVertexArrays(1, &vertex_array_);  // core profile: a bound VAO even without attributes
    glGenTextures(1, &texture_);
    glBindTexture(GL_TEXTURE_2D, texture_);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
}

ImageView::~ImageView() {
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

void ImageView::draw(const ImageLayout& layout, glm::vec2 window, const DisplaySettings& display) const {
    if (width_ <= 0 || height_ <= 0) return;
    glUseProgram(program_.id());
    const glm::vec2 size = layout.size();
    glUniform4f(program_.uniform("u_rect"), layout.origin.x, layout.origin.y, size.x, size.y);
    glUniform2f(program_.uniform("u_window"), window.x, window.y);
    glUniform1f(program_.uniform("u_exposure"), std::exp2(display.exposure));
    glUniform1i(program_.uniform("u_srgb"), display.srgb ? 1 : 0);
    glUniform1i(program_.uniform("u_image"), 0);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, texture_);
    // Whole magnifications stay sharp (texel fetches); a shrunk image is filtered.
    const bool whole = layout.scale >= 1.0f && layout.scale == std::floor(layout.scale);
    glUniform1i(program_.uniform("u_whole_pixels"), whole ? 1 : 0);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glBindVertexArray(vertex_array_);
    glDisable(GL_BLEND);
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    glBindVertexArray(0);
}

}  // namespace caustica::ui
