#include "core/integrators/progressive_accumulator.h"

#include <algorithm>
#include <cmath>

namespace caustica {
namespace {

double channel_mean(const glm::vec3& c) { return (static_cast<double>(c.x) + c.y + c.z) / 3.0; }

/// A pixel is in the caustic region when its mean photon radiance reaches this fraction of the
/// 99th percentile of the non-zero ones: the rule bench/trade applies to its references.
constexpr double region_fraction = 0.1;

/// Fixed-point units: colour in 2^-8 and 2^-40, statistics in 2^-16.
constexpr double colour_high_unit = 256.0, colour_low_unit = 4294967296.0, stat_unit = 65536.0;
/// Largest colour a sample adds (2^31: 2^23 passes fit in an int64); largest statistic (its units
/// then fit 32 bits, their square 64).
constexpr double colour_limit = 2147483648.0, stat_limit = 65536.0 - 1.0 / 65536.0;

/// x clamped to [lo, hi] (NaN to 0: a bug the debug build's pixel check reports before this).
double clamp_value(double x, double lo, double hi) {
    if (!(x == x)) return 0.0;
    return x < lo ? lo : (x > hi ? hi : x);
}

/// x in units of 2^-16, |x| < 2^16.
std::int64_t to_stat(double x) { return std::llround(clamp_value(x, -stat_limit, stat_limit) * stat_unit); }

/// Adds q and q^2 (exactly, in two parts) to three sums.
void add_with_square(std::int64_t* sum, std::int64_t* square_high, std::int64_t* square_low, std::int64_t q) {
    const std::uint64_t magnitude = static_cast<std::uint64_t>(q < 0 ? -q : q);
    const std::uint64_t square = magnitude * magnitude;  // < 2^64
    *sum += q;
    *square_high += static_cast<std::int64_t>(square >> 32);
    *square_low += static_cast<std::int64_t>(square & 0xffffffffULL);
}

/// n^2 (n - 1) times the variance of the mean of n samples, from their sums, in units^2: exact.
double variance_of_mean(double n, std::int64_t sum, std::int64_t square_high, std::int64_t square_low) {
    const __int128 squares = (static_cast<__int128>(square_high) << 32) + square_low;
    const __int128 spread = static_cast<__int128>(static_cast<std::int64_t>(n)) * squares -
                            static_cast<__int128>(sum) * static_cast<__int128>(sum);
    return static_cast<double>(spread) / (n * n * (n - 1.0)) / (stat_unit * stat_unit);
}

}  // namespace

void ProgressiveAccumulator::reset(int width, int height) {
    width_ = width;
    height_ = height;
    const std::size_t pixels = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
    sums_.assign(pixels * sums_per_pixel, 0);
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
    add_with_square(&s[value], &s[value2_high], &s[value2_low], to_stat(channel_mean(sample.colour)));
    s[photon] += to_stat(std::max(0.0, sample.photon));
    // E[L_r] - E[L_{r/sqrt 2}] = (r^2/8 - r^2/16) Laplacian: twice it is the bias at r.
    add_with_square(&s[bias], &s[bias2_high], &s[bias2_low], to_stat(2.0 * (sample.photon - sample.photon_inner)));
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
    const std::size_t pixels = sums_.size() / sums_per_pixel;
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
        const std::int64_t* sum = &sums_[i * sums_per_pixel];
        const double value = at(i, Slot::value) / stat_unit / n;
        // Variances of the means of n passes, exact from the integer sums.
        const double noise_var = variance_of_mean(n, sum[Slot::value], sum[value2_high], sum[value2_low]);
        const double bias_mean = at(i, bias) / stat_unit / n;
        const double bias_noise_var = variance_of_mean(n, sum[bias], sum[bias2_high], sum[bias2_low]);
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
