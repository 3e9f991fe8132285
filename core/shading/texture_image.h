// Image textures: PNG texels as linear RGB, nearest-texel lookups, the bump-map gradient, and the
// process-wide image cache. The rules are in docs/TEXTURES.md.
#pragma once

#include <glm/glm.hpp>

#include <memory>
#include <string>
#include <vector>

namespace caustica {

struct Png8;

/// One texel of an image: column from the left, row from the top.
struct TexelIndex {
    int column = 0, row = 0;
};

/// An image texture: linear RGB texels and their intensity (the luma of a bump map).
/// Texture space: u = 0 at the left edge, u = 1 at the right edge, v = 0 at the bottom row,
/// v = 1 at the top row.
class TextureImage {
public:
    /// Wraps texels given in linear RGB, row-major, top row first.
    TextureImage(int width, int height, std::vector<glm::vec3> texels);

    /// Converts a decoded PNG: each 8-bit value b becomes b / 255, without any gamma curve;
    /// grey (with or without alpha) gives r = g = b; alpha is ignored.
    static TextureImage from_png(const Png8& png);

    /// Image width in texels.
    int width() const { return width_; }
    /// Image height in texels.
    int height() const { return height_; }
    /// The texel at column x, row y (row 0 is the top row).
    glm::vec3 texel(int x, int y) const { return texels_[index(x, y)]; }

    /// The texel a lookup at (u, v) reads: column = floor(clamp(u W, 0, W - 1)),
    /// row = floor(clamp((1 - v) H, 0, H - 1)) (nearest, clamped, no wrap). NaN reads texel (0, 0).
    TexelIndex nearest(glm::vec2 uv) const;

    /// The colour of the nearest texel at (u, v).
    glm::vec3 colour(glm::vec2 uv) const;

    /// The bump-map gradient at the nearest texel, in intensity per pixel: g_x = (I(col + 1) -
    /// I(col - 1)) / 2, g_y = (I(row - 1) - I(row + 1)) / 2 (towards +u and +v), one-sided
    /// (I(next) - I(here)) at the image's borders and zero across a single row or column.
    glm::vec2 bump_gradient(glm::vec2 uv) const;

    /// Intensity of the texel at column x, row y: the luma 0.299 r + 0.587 g + 0.114 b.
    float intensity(int x, int y) const { return intensity_[index(x, y)]; }

private:
    std::size_t index(int x, int y) const { return static_cast<std::size_t>(y) * width_ + x; }

    int width_ = 0, height_ = 0;
    std::vector<glm::vec3> texels_;
    std::vector<float> intensity_;
};

/// Loads a PNG texture through a process-wide cache keyed by absolute path: every caller (any
/// thread, any render) gets the same object until the file's size or modification time
/// changes. Throws std::runtime_error from read_png when the file cannot be read.
std::shared_ptr<const TextureImage> load_texture_image(const std::string& path);

/// The texture for an image the scene loader decoded: converted once while the decoded image is
/// alive (every render of a scene shares it).
std::shared_ptr<const TextureImage> texture_image_from(const std::shared_ptr<const Png8>& png);

}  // namespace caustica
