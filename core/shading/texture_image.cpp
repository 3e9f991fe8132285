#include "core/shading/texture_image.h"

#include "core/io/png_io.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <mutex>
#include <unordered_map>

namespace caustica {
namespace {

/// Luminance of linear RGB with the Rec. 709 weights.
float luminance(const glm::vec3& c) { return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b; }

/// The two texels along one axis that a bilinear lookup blends, and the weight of the second.
struct AxisTexels {
    int first = 0, second = 0;
    float fraction = 0.0f;
};

/// Texel centres sit at (i + 0.5) / size. `coord` is u or v; wrapping repeats the image,
/// otherwise the lookup is clamped to the centres of the texels inside [lo, hi].
AxisTexels axis_texels(float coord, int size, float lo, float hi, bool wrap) {
    float x = std::isfinite(coord) ? coord * static_cast<float>(size) - 0.5f : 0.0f;
    AxisTexels t;
    if (wrap) {
        x -= static_cast<float>(size) * std::floor(x / static_cast<float>(size));  // into [0, size]
        const float base = std::floor(x);
        t.fraction = std::clamp(x - base, 0.0f, 1.0f);
        t.first = std::clamp(static_cast<int>(base), 0, size) % size;  // x == size rounds to texel 0
        t.second = (t.first + 1) % size;
        return t;
    }
    const float last_texel = static_cast<float>(size - 1);
    const float first = std::clamp(std::ceil(lo * static_cast<float>(size) - 0.5f), 0.0f, last_texel);
    const float last = std::clamp(std::floor(hi * static_cast<float>(size) - 0.5f), first, last_texel);
    x = std::clamp(x, first, last);
    const float base = std::floor(x);
    t.fraction = x - base;
    t.first = static_cast<int>(base);
    t.second = std::min(t.first + 1, static_cast<int>(last));
    return t;
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
    luminance_.reserve(texels_.size());
    for (const glm::vec3& c : texels_) luminance_.push_back(luminance(c));
}

TextureImage TextureImage::from_png(const Png8& png) {
    std::vector<glm::vec3> texels(static_cast<std::size_t>(png.width) * png.height);
    const bool gray = png.channels < 3;
    for (std::size_t i = 0; i < texels.size(); ++i) {
        const unsigned char* p = png.data.data() + i * static_cast<std::size_t>(png.channels);
        texels[i] = gray ? glm::vec3(p[0] / 255.0f) : glm::vec3(p[0], p[1], p[2]) / 255.0f;
    }
    return TextureImage(png.width, png.height, std::move(texels));
}

TextureImage::Footprint TextureImage::footprint(glm::vec2 uv, const TextureWindow& window) const {
    const bool wrap_u = window.lo.x <= 0.0f && window.hi.x >= 1.0f;
    const AxisTexels x = axis_texels(uv.x, width_, window.lo.x, window.hi.x, wrap_u);
    const AxisTexels y = axis_texels(uv.y, height_, window.lo.y, window.hi.y, false);
    return {{static_cast<int>(index(x.first, y.first)), static_cast<int>(index(x.second, y.first)),
             static_cast<int>(index(x.first, y.second)), static_cast<int>(index(x.second, y.second))},
            {(1.0f - x.fraction) * (1.0f - y.fraction), x.fraction * (1.0f - y.fraction),
             (1.0f - x.fraction) * y.fraction, x.fraction * y.fraction}};
}

glm::vec3 TextureImage::colour(glm::vec2 uv, const TextureWindow& window) const {
    const Footprint f = footprint(uv, window);
    glm::vec3 sum(0.0f);
    for (int i = 0; i < 4; ++i) sum += f.weight[i] * texels_[f.index[i]];
    return sum;
}

float TextureImage::height(glm::vec2 uv, const TextureWindow& window) const {
    const Footprint f = footprint(uv, window);
    float sum = 0.0f;
    for (int i = 0; i < 4; ++i) sum += f.weight[i] * luminance_[f.index[i]];
    return sum;
}

glm::vec2 TextureImage::height_gradient(glm::vec2 uv, const TextureWindow& window) const {
    const float du = 1.0f / static_cast<float>(width_), dv = 1.0f / static_cast<float>(height_);
    const float h_u = height({uv.x + du, uv.y}, window) - height({uv.x - du, uv.y}, window);
    const float h_v = height({uv.x, uv.y + dv}, window) - height({uv.x, uv.y - dv}, window);
    return {h_u / (2.0f * du), h_v / (2.0f * dv)};
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
