#include "core/render/progressive_accumulator.h"

#include <algorithm>
#include <cmath>

namespace caustica {
namespace {

double channel_mean(const glm::vec3& c) { return (static_cast<double>(c.x) + c.y + c.z) / 3.0; }

/// A pixel is in the caustic region when its mean photon radiance reaches this fraction of the
/// 99th percentile of the non-zero ones: the rule bench/trade applies to its references.
constexpr double region_fraction = 0.1;

/// Fixed-point units: colour in 2^-8 and 2^-40, statistics in 2^-24.
constexpr double colour_high_unit = 256.0, colour_low_unit = 4294967296.0, stat_unit = 16777216.0;
/// Largest colour a sample adds (2^31: 2^24 passes fit in an int64), largest statistic.
constexpr double colour_limit = 2147483648.0, stat_limit = 65536.0, square_root_limit = 256.0;

/// x clamped to [lo, hi] (NaN to 0: a bug the debug build's pixel check reports before this).
double clamp_value(double x, double lo, double hi) {
    if (!(x == x)) return 0.0;
    return x < lo ? lo : (x > hi ? hi : x);
}

std::int64_t to_stat(double x) { return std::llround(x * stat_unit); }

}  // namespace

void ProgressiveAccumulator::reset(int width, int height) {
    width_ = width;
    height_ = height;
    const std::size_t pixels = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
    sums_.assign(pixels * sums_per_pixel, 0);
    first_radius_.assign(pixels, 0.0f);
}

glm::vec3 ProgressiveAccumulator::add(std::size_t index, const PassSample& sample) {
    std::int64_t* s = &sums_[index * sums_per_pixel];
    for (int c = 0; c < 3; ++c) {
        // Exact split of the float (times a power of two, in double): the whole 2^-8 units, and
        // the remainder rounded to 2^-40.
        const double scaled = clamp_value(static_cast<double>(sample.colour[c]), 0.0, colour_limit) * colour_high_unit;
        const double high = std::floor(scaled);
        s[colour_high + c] += static_cast<std::int64_t>(high);
        s[colour_low + c] += std::llround((scaled - high) * colour_low_unit);
    }
    const double v = clamp_value(channel_mean(sample.colour), 0.0, square_root_limit);
    s[value] += to_stat(v);
    s[value2] += to_stat(v * v);
    s[photon] += to_stat(clamp_value(sample.photon, 0.0, stat_limit));
    // E[L_r] - E[L_{r/sqrt 2}] = (r^2/8 - r^2/16) Laplacian: twice it is the bias at r.
    const double probe = 2.0 * (sample.photon - sample.photon_inner);
    s[bias] += to_stat(clamp_value(probe, -stat_limit, stat_limit));
    const double b = clamp_value(probe, -square_root_limit, square_root_limit);
    s[bias2] += to_stat(b * b);
    s[count_slot] += 1;
    return mean(index);
}

glm::vec3 ProgressiveAccumulator::mean(std::size_t index) const {
    const std::int64_t* s = &sums_[index * sums_per_pixel];
    if (s[count_slot] == 0) return glm::vec3(0.0f);
    const double n = static_cast<double>(s[count_slot]);
    glm::vec3 m;
    for (int c = 0; c < 3; ++c)
        m[c] = static_cast<float>((static_cast<double>(s[colour_high + c]) / colour_high_unit +
                                   static_cast<double>(s[colour_low + c]) / (colour_high_unit * colour_low_unit)) /
                                  n);
    return m;
}

Image ProgressiveAccumulator::image() const {
    Image out(width_, height_);
    for (std::size_t i = 0; i < out.pixels.size(); ++i) out.pixels[i] = mean(i);
    return out;
}

ErrorEstimate ProgressiveAccumulator::estimate_error() const {
    ErrorEstimate e;
    const std::size_t pixels = first_radius_.size();
    auto at = [&](std::size_t i, Slot slot) { return static_cast<double>(sums_[i * sums_per_pixel + slot]); };
    std::vector<double> lit;
    for (std::size_t i = 0; i < pixels; ++i)
        if (at(i, photon) > 0.0) lit.push_back(at(i, photon) / at(i, count_slot));
    // Without photons (nothing specular, no --gi) the whole image is the region: its noise is
    // the eye side's (anti-aliasing, soft shadows).
    double threshold = -1.0;
    if (!lit.empty()) {
        auto percentile = lit.begin() + static_cast<std::ptrdiff_t>(0.99 * static_cast<double>(lit.size() - 1));
        std::nth_element(lit.begin(), percentile, lit.end());
        threshold = region_fraction * *percentile;
    }
    double noise2 = 0.0, bias2_sum = 0.0, shown = 0.0;
    std::size_t region = 0;
    for (std::size_t i = 0; i < pixels; ++i) {
        const double n = at(i, count_slot);
        if (n < 2.0) continue;
        const double photon_mean = at(i, photon) / n;
        if (!(photon_mean >= threshold)) continue;
        ++region;
        const double value_sum = at(i, value) / stat_unit, value = value_sum / n;
        // Variance of the mean of n passes, from the sums (never below 0: rounding).
        const double noise_var = std::max(0.0, at(i, value2) / stat_unit - value_sum * value) / (n - 1.0) / n;
        const double bias_sum = at(i, bias), bias_mean = bias_sum / stat_unit / n;
        const double bias_noise_var =
            std::max(0.0, at(i, bias2) / stat_unit - bias_sum / stat_unit * bias_mean) / (n - 1.0) / n;
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
        const double bound = bias_mean > 0.0 ? shown_value : 1.0 - shown_value;
        bias2_sum += std::min(bias_mean * bias_mean - bias_noise_var, bound * bound);
    }
    if (region == 0 || !(shown > 0.0)) return e;
    const double mean = shown / static_cast<double>(region);
    const double bias_only = std::max(0.0, bias2_sum);
    e.known = true;
    e.region_pixels = region;
    e.noise = std::sqrt(noise2 / static_cast<double>(region)) / mean;
    e.bias = std::sqrt(bias_only / static_cast<double>(region)) / mean;
    e.relative = std::sqrt(e.noise * e.noise + e.bias * e.bias);
    return e;
}

}  // namespace caustica
