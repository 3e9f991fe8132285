#include "core/shading/texture_image.h"

#include "core/io/png_io.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <mutex>
#include <stdexcept>
#include <unordered_map>

namespace caustica {
namespace {

/// The luma the original uses wherever a colour becomes a number (docs/CAUSTICS.md, "luma").
float luma(const glm::vec3& c) { return 0.299f * c.r + 0.587f * c.g + 0.114f * c.b; }

/// floor(clamp(x, 0, size - 1)), with NaN read as 0.
int clamped_texel(float x, int size) {
    if (!(x > 0.0f)) return 0;
    const float last = static_cast<float>(size - 1);
    return static_cast<int>(std::floor(std::min(x, last)));
}

/// Central difference of f at i in [0, size): (f(i + 1) - f(i - 1)) / 2 inside, one-sided at
/// the ends, zero when size is 1.
template <typename F>
float difference(int i, int size, F f) {
    if (size < 2) return 0.0f;
    if (i == 0) return f(1) - f(0);
    if (i == size - 1) return f(size - 1) - f(size - 2);
    return 0.5f * (f(i + 1) - f(i - 1));
}

/// One cached image and the file state it was read from.
struct CacheEntry {
    std::shared_ptr<const TextureImage> image;
    std::filesystem::file_time_type modified;
    std::uintmax_t size = 0;
};

}  // namespace

TextureImage::TextureImage(int width, int height, std::vector<glm::vec3> texels)
    : width_(width), height_(height), texels_(std::move(texels)) {
    if (width_ <= 0 || height_ <= 0 || texels_.size() != static_cast<std::size_t>(width_) * height_)
        throw std::invalid_argument("TextureImage: texel count does not match the size");
    intensity_.reserve(texels_.size());
    for (const glm::vec3& c : texels_) intensity_.push_back(luma(c));
}

TextureImage TextureImage::from_png(const Png8& png) {
    std::vector<glm::vec3> texels(static_cast<std::size_t>(png.width) * png.height);
    const bool grey = png.channels < 3;  // 1: grey, 2: grey + alpha
    for (std::size_t i = 0; i < texels.size(); ++i) {
        const unsigned char* p = png.data.data() + i * static_cast<std::size_t>(png.channels);
        texels[i] = grey ? glm::vec3(p[0] / 255.0f) : glm::vec3(p[0], p[1], p[2]) / 255.0f;
    }
    return TextureImage(png.width, png.height, std::move(texels));
}

TexelIndex TextureImage::nearest(glm::vec2 uv) const {
    return {clamped_texel(uv.x * static_cast<float>(width_), width_),
            clamped_texel((1.0f - uv.y) * static_cast<float>(height_), height_)};
}

glm::vec3 TextureImage::colour(glm::vec2 uv) const {
    const TexelIndex t = nearest(uv);
    return texel(t.column, t.row);
}

glm::vec2 TextureImage::bump_gradient(glm::vec2 uv) const {
    const TexelIndex t = nearest(uv);
    const float g_x = difference(t.column, width_, [&](int x) { return intensity(x, t.row); });
    // Rows count downwards; +v is up the image, so g_y is minus the difference along rows.
    const float g_y = -difference(t.row, height_, [&](int y) { return intensity(t.column, y); });
    return {g_x, g_y};
}

std::shared_ptr<const TextureImage> load_texture_image(const std::string& path) {
    static std::mutex mutex;
    static std::unordered_map<std::string, CacheEntry> cache;
    std::error_code time_error, size_error;
    const auto modified = std::filesystem::last_write_time(path, time_error);
    const auto size = std::filesystem::file_size(path, size_error);
    const bool file_state_known = !time_error && !size_error;

    std::lock_guard lock(mutex);
    if (auto it = cache.find(path); it != cache.end()) {
        if (file_state_known && it->second.modified == modified && it->second.size == size) return it->second.image;
        cache.erase(it);
    }
    auto image = std::make_shared<const TextureImage>(TextureImage::from_png(read_png(path)));
    if (file_state_known) cache[path] = {image, modified, size};
    return image;
}

std::shared_ptr<const TextureImage> texture_image_from(const std::shared_ptr<const Png8>& png) {
    struct Entry {
        std::weak_ptr<const Png8> png;
        std::shared_ptr<const TextureImage> image;
    };
    static std::mutex mutex;
    static std::unordered_map<const Png8*, Entry> cache;
    std::lock_guard lock(mutex);
    std::erase_if(cache, [](const auto& entry) { return entry.second.png.expired(); });
    if (auto it = cache.find(png.get()); it != cache.end()) return it->second.image;
    auto image = std::make_shared<const TextureImage>(TextureImage::from_png(*png));
    cache[png.get()] = {png, image};
    return image;
}

}  // namespace caustica
