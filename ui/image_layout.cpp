#include "ui/image_layout.h"

#include <algorithm>
#include <cmath>

namespace caustica::ui {

ImageLayout fit_image(glm::vec2 area_origin, glm::vec2 area_size, int width, int height) {
    ImageLayout layout;
    layout.image_width = width;
    layout.image_height = height;
    if (width <= 0 || height <= 0 || area_size.x <= 0.0f || area_size.y <= 0.0f) {
        layout.origin = area_origin;
        return layout;
    }
    const float fit = std::min(area_size.x / width, area_size.y / height);
    layout.scale = fit >= 1.0f ? std::floor(fit) : fit;
    // Whole-pixel origin, so that a 1:1 image maps pixel centres to pixel centres.
    layout.origin = glm::floor(area_origin + 0.5f * (area_size - glm::vec2(width, height) * layout.scale));
    return layout;
}

}  // namespace caustica::ui
