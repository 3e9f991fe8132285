#include "core/render/progressive_accumulator.h"

#include <algorithm>
#include <cmath>

namespace caustica {
namespace {

float channel_mean(const glm::vec3& c) { return (c.x + c.y + c.z) / 3.0f; }

/// A pixel is in the caustic region when its mean photon radiance reaches this fraction of the
/// 99th percentile of the non-zero ones: the rule bench/trade applies to its references.
constexpr double region_fraction = 0.1;

}  // namespace

void ProgressiveAccumulator::reset(int width, int height) {
    width_ = width;
    height_ = height;
    pixels_.assign(static_cast<std::size_t>(width) * static_cast<std::size_t>(height), Pixel{});
}

glm::vec3 ProgressiveAccumulator::add(std::size_t index, const PassSample& sample) {
    Pixel& p = pixels_[index];
    const float n = static_cast<float>(++p.count);
    const float value_before = channel_mean(p.mean);
    p.mean += (sample.colour - p.mean) / n;
    const float value = channel_mean(sample.colour);
    p.value_m2 += (value - value_before) * (value - channel_mean(p.mean));
    p.photon += (static_cast<float>(sample.photon) - p.photon) / n;
    // E[L_r] - E[L_{r/sqrt 2}] = (r^2/8 - r^2/16) Laplacian: twice it is the bias at r.
    const float probe = 2.0f * static_cast<float>(sample.photon - sample.photon_inner);
    const float bias_before = p.bias;
    p.bias += (probe - p.bias) / n;
    p.bias_m2 += (probe - bias_before) * (probe - p.bias);
    return p.mean;
}

glm::vec3 ProgressiveAccumulator::mean(std::size_t index) const { return pixels_[index].mean; }

Image ProgressiveAccumulator::image() const {
    Image out(width_, height_);
    for (std::size_t i = 0; i < pixels_.size(); ++i) out.pixels[i] = pixels_[i].mean;
    return out;
}

ErrorEstimate ProgressiveAccumulator::estimate_error() const {
    ErrorEstimate e;
    std::vector<float> lit;
    for (const Pixel& p : pixels_)
        if (p.photon > 0.0f) lit.push_back(p.photon);
    // Without photons (nothing specular, no --gi) the whole image is the region: its noise is
    // the eye side's (anti-aliasing, soft shadows).
    double threshold = -1.0;
    if (!lit.empty()) {
        auto percentile = lit.begin() + static_cast<std::ptrdiff_t>(0.99 * static_cast<double>(lit.size() - 1));
        std::nth_element(lit.begin(), percentile, lit.end());
        threshold = region_fraction * *percentile;
    }
    double noise2 = 0.0, bias2 = 0.0, shown = 0.0;
    std::size_t region = 0;
    for (const Pixel& p : pixels_) {
        if (!(p.photon >= threshold) || p.count < 2) continue;
        ++region;
        const double n = p.count;
        const double value = channel_mean(p.mean);
        const double noise_var = p.value_m2 / (n - 1.0) / n;  // variance of the mean of n passes
        const double bias_noise_var = p.bias_m2 / (n - 1.0) / n;
        shown += std::clamp(value, 0.0, 1.0);
        // A pixel surely above 1 shows white, as its converged value most likely does (a bright
        // caustic's blur lowers its peaks): it counts no error.
        if (value - 2.0 * std::sqrt(noise_var) >= 1.0) continue;
        noise2 += noise_var;
        // The squared mean probe is the squared bias plus the probe's own variance (a difference
        // of two noisy estimates: about twice the image's noise), which is subtracted: summed over
        // the region this is unbiased where the bias is small. The shown value cannot move by more
        // than to 0 (a positive bias) or to 1 (a negative one): near focal spots the probe is
        // huge and that bound is what counts. (Clamping to the noisy corrected value instead would
        // turn the probe's noise into bias everywhere.)
        const double shown_value = std::clamp(value, 0.0, 1.0);
        const double bound = p.bias > 0.0f ? shown_value : 1.0 - shown_value;
        bias2 += std::min(static_cast<double>(p.bias) * p.bias - bias_noise_var, bound * bound);
    }
    if (region == 0 || !(shown > 0.0)) return e;
    const double mean = shown / static_cast<double>(region);
    const double bias_only = std::max(0.0, bias2);
    e.known = true;
    e.region_pixels = region;
    e.noise = std::sqrt(noise2 / static_cast<double>(region)) / mean;
    e.bias = std::sqrt(bias_only / static_cast<double>(region)) / mean;
    e.relative = std::sqrt(e.noise * e.noise + e.bias * e.bias);
    return e;
}

}  // namespace caustica
