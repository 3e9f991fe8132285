#include "core/render/image_error.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace caustica {
namespace {

glm::vec3 shown(const glm::vec3& p) { return glm::clamp(p, glm::vec3(0.0f), glm::vec3(1.0f)); }

}  // namespace

double shown_value(const glm::vec3& p) {
    const glm::vec3 s = shown(p);
    return (static_cast<double>(s.x) + s.y + s.z) / 3.0;
}

std::vector<std::size_t> caustic_region(const Image& reference) {
    std::vector<double> lit;
    for (const glm::vec3& p : reference.pixels)
        if (shown_value(p) > 0.0) lit.push_back(shown_value(p));
    std::vector<std::size_t> region;
    if (lit.empty()) return region;
    auto percentile = lit.begin() + static_cast<std::ptrdiff_t>(0.99 * static_cast<double>(lit.size() - 1));
    std::nth_element(lit.begin(), percentile, lit.end());
    const double threshold = caustic_region_fraction * *percentile;
    for (std::size_t i = 0; i < reference.pixels.size(); ++i)
        if (shown_value(reference.pixels[i]) >= threshold) region.push_back(i);
    return region;
}

ImageError compare_images(const Image& image, const Image& reference, const std::vector<std::size_t>& region) {
    ImageError e;
    e.region_pixels = region.size();
    double squared = 0.0;
    for (std::size_t i = 0; i < image.pixels.size(); ++i) {
        const glm::vec3 d = shown(image.pixels[i]) - shown(reference.pixels[i]);
        squared += glm::dot(d, d);
    }
    if (!image.pixels.empty()) e.rmse = std::sqrt(squared / (3.0 * static_cast<double>(image.pixels.size())));
    double region_squared = 0.0, sum = 0.0, sum_reference = 0.0;
    for (std::size_t i : region) {
        const glm::vec3 d = shown(image.pixels[i]) - shown(reference.pixels[i]);
        region_squared += glm::dot(d, d);
        sum += 3.0 * shown_value(image.pixels[i]);
        sum_reference += 3.0 * shown_value(reference.pixels[i]);
    }
    if (sum_reference > 0.0) {
        const double count = 3.0 * static_cast<double>(region.size());
        e.rel_rmse = std::sqrt(region_squared / count) / (sum_reference / count);
        e.rel_bias = sum / sum_reference - 1.0;
    }
    return e;
}

}  // namespace caustica
