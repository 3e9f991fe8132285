// Draws the projection-map overlay (triangles from overlay_geometry) over the shown image with
// shaders/overlay.*; a GL overlay, never baked into the render.
#pragma once

#include "ui/gl_program.h"
#include "ui/image_layout.h"
#include "ui/overlay_geometry.h"

#include <vector>

namespace caustica::ui {

/// The GL side of the overlay (needs a current context for its whole life).
class OverlayRenderer {
public:
    OverlayRenderer();
    ~OverlayRenderer();
    OverlayRenderer(const OverlayRenderer&) = delete;
    OverlayRenderer& operator=(const OverlayRenderer&) = delete;

    /// Replaces the triangles drawn (image pixel coordinates).
    void set_triangles(const std::vector<OverlayVertex>& triangles);
    /// Draws them over an image placed by `layout`, clipped to the image and to the framebuffer
    /// rectangle `area` (x, y from the bottom-left, width, height: the image area when zoomed in);
    /// `pixel_scale` is framebuffer pixels per window pixel (above 1 on high-density screens).
    void draw(const ImageLayout& layout, glm::vec2 window, glm::vec2 pixel_scale, glm::ivec4 area) const;

private:
    GlProgram program_;
    GLuint vertex_array_ = 0, buffer_ = 0;
    GLsizei count_ = 0;
};

}  // namespace caustica::ui
