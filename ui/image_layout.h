// Where the rendered image sits in the window, and the mapping between window and image pixels.
#pragma once

#include <glm/glm.hpp>

namespace caustica::ui {

/// The image's placement: window pixels = origin + scale x image pixels (both y down).
struct ImageLayout {
    glm::vec2 origin{0.0f};
    float scale = 1.0f;
    int image_width = 0, image_height = 0;

    /// Image pixel coordinates of a window point.
    glm::vec2 to_image(glm::vec2 window) const { return (window - origin) / scale; }
    /// Window coordinates of an image point.
    glm::vec2 to_window(glm::vec2 image) const { return origin + image * scale; }
    /// The image's size in window pixels.
    glm::vec2 size() const { return glm::vec2(image_width, image_height) * scale; }
    /// Whether a window point lies on the image.
    bool contains(glm::vec2 window) const {
        const glm::vec2 p = to_image(window);
        return p.x >= 0.0f && p.y >= 0.0f && p.x < image_width && p.y < image_height;
    }
};

/// Centres a width x height image in an area: magnified by the largest whole factor that fits
/// (pixels stay sharp and 1:1 when the image fits), or shrunk to fit when it does not.
ImageLayout fit_image(glm::vec2 area_origin, glm::vec2 area_size, int width, int height);

}  // namespace caustica::ui
