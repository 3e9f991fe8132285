// A float RGB image.
#pragma once

#include <glm/glm.hpp>

#include <cstddef>
#include <vector>

namespace caustica {

/// Linear RGB pixels, row-major, top row first.
struct Image {
    int width = 0, height = 0;
    std::vector<glm::vec3> pixels;

    Image() = default;
    Image(int w, int h) : width(w), height(h), pixels(static_cast<std::size_t>(w) * h, glm::vec3(0.0f)) {}

    /// The pixel at column x, row y.
    glm::vec3& at(int x, int y) { return pixels[static_cast<std::size_t>(y) * width + x]; }
    const glm::vec3& at(int x, int y) const { return pixels[static_cast<std::size_t>(y) * width + x]; }
};

}  // namespace caustica
