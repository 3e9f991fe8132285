#include "ui/overlay_renderer.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace caustica::ui {

OverlayRenderer::OverlayRenderer() : program_("overlay.vert", "overlay.frag") {
    glGenVertexArrays(1, &vertex_array_);
    glGenBuffers(1, &buffer_);
    glBindVertexArray(vertex_array_);
    glBindBuffer(GL_ARRAY_BUFFER, buffer_);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, sizeof(OverlayVertex),
                          reinterpret_cast<const void*>(offsetof(OverlayVertex, position)));
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 4, GL_FLOAT, GL_FALSE, sizeof(OverlayVertex),
                          reinterpret_cast<const void*>(offsetof(OverlayVertex, colour)));
    glBindVertexArray(0);
}

OverlayRenderer::~OverlayRenderer() {
    glDeleteBuffers(1, &buffer_);
    glDeleteVertexArrays(1, &vertex_array_);
}

void OverlayRenderer::set_triangles(const std::vector<OverlayVertex>& triangles) {
    glBindBuffer(GL_ARRAY_BUFFER, buffer_);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(triangles.size() * sizeof(OverlayVertex)),
                 triangles.data(), GL_DYNAMIC_DRAW);
    count_ = static_cast<GLsizei>(triangles.size());
}

void OverlayRenderer::draw(const ImageLayout& layout, glm::vec2 window, glm::vec2 pixel_scale, glm::ivec4 area) const {
    if (count_ == 0 || layout.image_width <= 0) return;
    const glm::vec2 size = layout.size();
    glUseProgram(program_.id());
    glUniform4f(program_.uniform("u_rect"), layout.origin.x, layout.origin.y, size.x, size.y);
    glUniform2f(program_.uniform("u_image_size"), static_cast<float>(layout.image_width),
                static_cast<float>(layout.image_height));
    glUniform2f(program_.uniform("u_window"), window.x, window.y);
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    glEnable(GL_SCISSOR_TEST);  // in framebuffer pixels, with the origin at the bottom-left
    const int x0 = static_cast<int>(std::floor(layout.origin.x * pixel_scale.x));
    const int y0 = static_cast<int>(std::floor((window.y - layout.origin.y - size.y) * pixel_scale.y));
    const int x1 = x0 + static_cast<int>(std::ceil(size.x * pixel_scale.x));
    const int y1 = y0 + static_cast<int>(std::ceil(size.y * pixel_scale.y));
    const int cx0 = std::max(x0, area.x), cy0 = std::max(y0, area.y);
    const int cx1 = std::min(x1, area.x + area.z), cy1 = std::min(y1, area.y + area.w);
    if (cx1 <= cx0 || cy1 <= cy0) {
        glDisable(GL_SCISSOR_TEST);
        glDisable(GL_BLEND);
        return;
    }
    glScissor(cx0, cy0, cx1 - cx0, cy1 - cy0);
    glBindVertexArray(vertex_array_);
    glDrawArrays(GL_TRIANGLES, 0, count_);
    glBindVertexArray(0);
    glDisable(GL_SCISSOR_TEST);
    glDisable(GL_BLEND);
}

}  // namespace caustica::ui
