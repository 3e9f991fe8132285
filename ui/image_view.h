// The rendered image on screen: a float texture updated tile by tile (only the tiles the driver
// copied this frame) and drawn with shaders/image.* (exposure, tone curve and sRGB are display-only).
#pragma once

#include "ui/gl_program.h"
#include "ui/image_layout.h"
#include "ui/preview_driver.h"
#include "ui/view_model.h"

#include <cstddef>

namespace caustica::ui {

/// The GL side of the shown image (needs a current context for its whole life).
class ImageView {
public:
    ImageView();
    ~ImageView();
    ImageView(const ImageView&) = delete;
    ImageView& operator=(const ImageView&) = delete;

    /// Uploads the tiles the last PreviewDriver::update() copied (everything after a resize), one
    /// glTexSubImage2D per run of neighbouring tiles in a tile row.
    void upload(const PreviewDriver& driver);

    /// Replaces the reference image (B) compared against (an empty image removes it).
    void set_reference(const Image& reference);
    /// Whether a reference of the shown image's size is loaded.
    bool reference_matches() const { return reference_width_ > 0 && reference_width_ == width_ && reference_height_ == height_; }

    /// Draws the image where `layout` puts it in a window of `window` pixels, clipped to the
    /// framebuffer rectangle `clip` (x, y from the bottom-left, width, height), through `view`
    /// (exposure, tone curve, encoding: ui/view_transform.h), with `compare`
    /// (shaders/image.frag's u_mode: 0 the image, 1 split, 2 difference, 3 relative error; modes
    /// other than 0 need a matching reference).
    struct Compare {
        int mode = 0;
        float split = 0.5f, gain = 1.0f, epsilon = 1e-3f;
    };
    void draw(const ImageLayout& layout, glm::vec2 window, const ViewTransform& view, const Compare& compare,
              glm::ivec4 clip) const;

    /// Tiles and glTexSubImage2D calls of the last upload (for statistics and benchmarks).
    std::size_t uploaded_tiles() const { return uploaded_tiles_; }
    std::size_t upload_calls() const { return upload_calls_; }

private:
    void upload_rect(const Image& image, int x0, int y0, int x1, int y1);

    GlProgram programs_[3];      ///< shaders/image.frag: the plain image, one program per tone curve (tone_curve_index)
    GlProgram compare_program_;  ///< shaders/image_compare.frag: the A/B modes, only while they are shown
    GLuint texture_ = 0, reference_ = 0, vertex_array_ = 0;
    int width_ = 0, height_ = 0;
    int reference_width_ = 0, reference_height_ = 0;
    std::size_t uploaded_tiles_ = 0, upload_calls_ = 0;
};

}  // namespace caustica::ui
