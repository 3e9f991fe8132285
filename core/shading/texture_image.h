// Image textures: PNG texels as linear RGB, bilinear lookups, and the process-wide image cache.
// The rules (colour handling, filtering, wrap and clamp) are written out in docs/TEXTURES.md.
#pragma once

#include <glm/glm.hpp>

#include <memory>
#include <string>
#include <vector>

namespace caustica {

struct Png8;

/// A rectangle of texture space [lo, hi] that a lookup must not leave (one cell of the cube
/// unwrap), so that bilinear filtering never blends in a neighbouring cell. The default is
/// the whole image; u wraps around only when the window spans the full width.
struct TextureWindow {
    glm::vec2 lo{0.0f};
    glm::vec2 hi{1.0f};
};

/// An image texture: linear RGB texels and their luminance (the height of a bump map).
/// Texture space: u = 0 at the left edge, v = 0 at the top edge, u = v = 1 at the far edges.
class TextureImage {
public:
    /// Wraps texels given in linear RGB, row-major, top row first.
    TextureImage(int width, int height, std::vector<glm::vec3> texels);

    /// Converts a PNG: each 8-bit value b becomes b / 255, without any gamma curve (the seed's
    /// convention); gray images give r = g = b; alpha is ignored.
    static TextureImage from_png(const Png8& png);

    /// Image width in texels.
    int width() const { return width_; }
    /// Image height in texels.
    int height() const { return height_; }
    /// The texel at column x, row y (row 0 is the top row).
    glm::vec3 texel(int x, int y) const { return texels_[index(x, y)]; }

    /// Bilinearly filtered colour at (u, v): u wraps around, v is clamped to the edge texels.
    glm::vec3 colour(glm::vec2 uv, const TextureWindow& window = {}) const;

    /// Bilinearly filtered luminance (Rec. 709 weights on linear RGB) at (u, v), same rules.
    float height(glm::vec2 uv, const TextureWindow& window = {}) const;

    /// Gradient (dh/du, dh/dv) of `height` by central differences one texel either side.
    glm::vec2 height_gradient(glm::vec2 uv, const TextureWindow& window = {}) const;

private:
    /// The four texels around (u, v) and their bilinear weights.
    struct Footprint {
        int index[4];
        float weight[4];
    };
    Footprint footprint(glm::vec2 uv, const TextureWindow& window) const;
    std::size_t index(int x, int y) const { return static_cast<std::size_t>(y) * width_ + x; }

    int width_ = 0, height_ = 0;
    std::vector<glm::vec3> texels_;
    std::vector<float> luminance_;
};

/// Loads a PNG texture through a process-wide cache keyed by absolute path: every caller (any
/// thread, any render) gets the same object until the file's size or modification time
/// changes. Throws std::runtime_error from read_png when the file cannot be read.
std::shared_ptr<const TextureImage> load_texture_image(const std::string& path);

/// The texture for an image the scene loader decoded: converted once while the decoded image is
/// alive (every render of a scene shares it).
std::shared_ptr<const TextureImage> texture_image_from(const std::shared_ptr<const Png8>& png);

}  // namespace caustica
