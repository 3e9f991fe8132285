#include "core/integrators/progressive_accumulator.h"

#include "core/render/image_error.h"
#include "core/util/huge_pages.h"
#include "core/util/parallel.h"
#include "core/util/rounding.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace caustica {
namespace {

double channel_mean(const glm::vec3& c) { return (static_cast<double>(c.x) + c.y + c.z) / 3.0; }


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
std::int64_t to_stat(double x) { return round_half_away(clamp_value(x, -stat_limit, stat_limit) * stat_unit); }

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

/// The variance of a pixel as shown (clamped to [0, 1]) when its raw mean m has variance v:
/// E[(clamp(m + e) - clamp(m))^2] for a normal e, by five-point Gauss-Hermite quadrature. A pixel
/// well inside [0, 1] keeps v; one far above 1 has almost none.
double shown_variance(double m, double v) {
    if (!(v > 0.0)) return 0.0;
    static constexpr double nodes[] = {-2.8569700138728056, -1.3556261799742659, 0.0, 1.3556261799742659,
                                       2.8569700138728056};
    static constexpr double weights[] = {0.011257411327720691, 0.22207592200561266, 0.5333333333333333,
                                         0.22207592200561266, 0.011257411327720691};
    const double sigma = std::sqrt(v), at = std::clamp(m, 0.0, 1.0);
    double sum = 0.0;
    for (int k = 0; k < 5; ++k) {
        const double d = std::clamp(m + sigma * nodes[k], 0.0, 1.0) - at;
        sum += weights[k] * d * d;
    }
    return sum;
}

/// The squared blur of a pixel as shown (clamped to [0, 1]), from its raw mean m, the raw blur
/// b the radius probe measures and the variance v of that measurement: the shown blur is
/// clamp(m) - clamp(m - b) (none where the pixel shows white either way), and the probe's
/// variance passes through in the same proportion and is subtracted. (The caller bounds the
/// result on both sides by the most a shown value can be wrong: a probe far noisier than its
/// mean would otherwise swing the region's sum.)
double shown_blur2(double m, double b, double v) {
    const double shown = std::clamp(m, 0.0, 1.0) - std::clamp(m - b, 0.0, 1.0);
    const double slope = b != 0.0 ? shown / b : (m > 0.0 && m < 1.0 ? 1.0 : 0.0);
    return shown * shown - slope * slope * v;
}

/// Half the side of the window the caustic region is chosen on (estimate_error).
constexpr int region_window = 3;

/// Replaces each value of a width x height image by the sum over the (2 half + 1)^2 window around
/// it (clipped at the borders): along the rows, then the columns, each sum in a fixed order (the
/// same bits for any thread count; exact where the window holds only zeros).
template <typename T>
void box_sums(std::vector<T>& v, int width, int height, int half) {
    const std::size_t w = static_cast<std::size_t>(width);
    std::vector<T> rows(v.size());
    caustica::parallel_for(tbb::blocked_range<int>(0, height, 16), [&](const tbb::blocked_range<int>& r) {
        for (int y = r.begin(); y != r.end(); ++y) {
            const T* in = &v[static_cast<std::size_t>(y) * w];
            T* out = &rows[static_cast<std::size_t>(y) * w];
            for (int x = 0; x < width; ++x) {
                T sum = 0;
                for (int d = std::max(0, x - half); d <= std::min(width - 1, x + half); ++d) sum += in[d];
                out[x] = sum;
            }
        }
    });
    caustica::parallel_for(tbb::blocked_range<int>(0, height, 16), [&](const tbb::blocked_range<int>& r) {
        for (int y = r.begin(); y != r.end(); ++y) {
            T* out = &v[static_cast<std::size_t>(y) * w];
            std::fill(out, out + w, T(0));
            for (int d = std::max(0, y - half); d <= std::min(height - 1, y + half); ++d) {
                const T* in = &rows[static_cast<std::size_t>(d) * w];
                for (std::size_t x = 0; x < w; ++x) out[x] += in[x];
            }
        }
    });
}

}  // namespace

void ProgressiveAccumulator::reset(int width, int height) {
    width_ = width;
    height_ = height;
    const std::size_t pixels = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
    if (sums_.capacity() < pixels * sums_per_pixel) {
        sums_ = {};
        reserve_huge(sums_, pixels * sums_per_pixel);
    }
    sums_.assign(pixels * sums_per_pixel, 0);
}

void ProgressiveAccumulator::adopt(int width, int height, std::vector<std::int64_t>&& sums) {
    static_assert(sample_count_slot == count_slot);
    width_ = width;
    height_ = height;
    sums_ = std::move(sums);
}

glm::vec3 ProgressiveAccumulator::add(std::size_t index, const PassSample& sample) {
    std::int64_t* s = &sums_[index * sums_per_pixel];
    for (int c = 0; c < 3; ++c) {
        // Exact split of the float (times a power of two, in double): the whole 2^-8 units, and
        // the remainder rounded to 2^-40.
        const double scaled = clamp_value(static_cast<double>(sample.colour[c]), -colour_limit, colour_limit) * colour_high_unit;
        const double high = std::floor(scaled);
        s[colour_high + c] += static_cast<std::int64_t>(high);
        s[colour_low + c] += round_half_away((scaled - high) * colour_low_unit);
    }
    const double v = channel_mean(sample.colour);
    add_with_square(&s[value], &s[value2_high], &s[value2_low], to_stat(v));
    s[photon] += to_stat(std::max(0.0, sample.photon));
    // E[L_r] - E[L_{r/sqrt 2}] = (r^2/8 - r^2/16) Laplacian: twice it is the blur at r, on the
    // raw values (estimate_error takes it to the shown ones, on the pixel's mean).
    const std::int64_t probe = to_stat(2.0 * (sample.photon - sample.photon_inner));
    add_with_square(&s[bias], &s[bias2_high], &s[bias2_low], probe);
    s[count_slot] += 1;
    const int group = std::clamp(sample.group, 0, replicate_groups - 1);
    s[group_value + group] += to_stat(v);
    if (group < replicate_groups - 1) s[group_count + group] += 1;  // the last group's: the rest
    s[group_bias + group] += probe;
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

ErrorEstimate ProgressiveAccumulator::estimate_error(const RenderRegion& region_rendered) const {
    ErrorEstimate e;
    const std::size_t pixels = sums_.size() / sums_per_pixel;
    auto at = [&](std::size_t i, std::size_t slot) { return static_cast<double>(sums_[i * sums_per_pixel + slot]); };
    const std::size_t width = static_cast<std::size_t>(std::max(width_, 1));
    auto rendered = [&](std::size_t i) {
        return region_rendered.renders(static_cast<int>(i % width), static_cast<int>(i / width));
    };
    // In fixed chunks of pixels, in parallel, each chunk's sums added in chunk order: the same
    // bits for any thread count (the sums are a frame's worth of memory, read once per pass).
    constexpr std::size_t chunk = 16384;
    const std::size_t chunks = (pixels + chunk - 1) / chunk;
    auto for_chunks = [&](auto&& body) {
        caustica::parallel_for(tbb::blocked_range<std::size_t>(0, chunks, 1), [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t c = r.begin(); c != r.end(); ++c) body(c, c * chunk, std::min(pixels, (c + 1) * chunk));
        });
    };
    // A pixel's passes per replicate group; whether every group has some.
    auto group_counts = [&](std::size_t i, double* counts) {
        double last_count = at(i, count_slot);
        bool grouped = true;
        for (int g = 0; g < replicate_groups; ++g) {
            counts[g] = g < replicate_groups - 1 ? at(i, group_count + static_cast<std::size_t>(g)) : last_count;
            if (g < replicate_groups - 1) last_count -= counts[g];
            if (counts[g] < 1.0) grouped = false;
        }
        return grouped;
    };
    // The groups' means m of one statistic of pixel i (its group slots from `first` on) and their
    // spread, the sum of (m_g - M)^2 with M their mean.
    auto group_spread = [&](std::size_t i, std::size_t first, const double* counts, double* m) {
        double sum = 0.0;
        for (int g = 0; g < replicate_groups; ++g)
            sum += m[g] = at(i, first + static_cast<std::size_t>(g)) / stat_unit / counts[g];
        const double mean = sum * (1.0 / replicate_groups);
        double spread = 0.0;
        for (int g = 0; g < replicate_groups; ++g) spread += (m[g] - mean) * (m[g] - mean);
        return spread;
    };
    // The variance of a pixel's mean value: from its groups' spread when every group has passes
    // (as below), else from all its passes as if independent (none with fewer than 2).
    auto variance_of_pixel_mean = [&](std::size_t i) {
        const double n = at(i, count_slot);
        double counts[replicate_groups], m[replicate_groups];
        if (group_counts(i, counts)) return group_spread(i, group_value, counts, m) / 12.0;
        if (n < 2.0) return 0.0;
        const std::int64_t* sum = &sums_[i * sums_per_pixel];
        return variance_of_mean(n, sum[Slot::value], sum[value2_high], sum[value2_low]);
    };
    // The caustic region is chosen as caustic_region() chooses it on the converged image, but on
    // each pixel's photon value shrunk towards its neighbourhood's mean (a window of rendered
    // pixels) as far as its noise makes it uncertain: x = v - (v - m) s^2 / (s^2 + (v - m)^2),
    // with m and s^2 the window's mean value and mean variance of a pixel's mean. Early on,
    // where a disc holds a photon or none, the own values alone are spiky: their 99th percentile
    // is far above the converged one, and they drop the pixels that got no photon though these
    // belong to the region and err like the others (the sum of the groups' spreads is unbiased
    // only over pixels chosen independently of their own samples). The percentile is over the
    // pixels with photons, as on the converged image, and those without whose neighbourhood is
    // as noisy as it is bright (s^2 >= m^2: they might as well have had some). As the noise
    // falls, x tends to the pixel's own value and the region to the converged image's.
    // The variance is the sample value's (the photon value's alone is not kept): in a render
    // that is not caustics only, noise of the eye side (anti-aliasing, soft shadows) adds to it
    // and shrinks a little more, falling as fast. The window's sums are in floats (whether a
    // pixel counts, and its shrunk value, depend on them: the same bits on any thread count).
    // At most 25 bytes a pixel at once (estimate_bytes_per_pixel): own, the two window sums and
    // the sums' row pass; then own, counted and the percentile's values.
    std::vector<double> own(pixels, 0.0);
    std::vector<float> local(pixels, 0.0f), local_var(pixels, 0.0f);
    for_chunks([&](std::size_t, std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i) {
            const double n = at(i, count_slot);
            if (!rendered(i) || n <= 0.0 || !(at(i, photon) > 0.0)) continue;  // no photon: no photon noise
            own[i] = at(i, photon) / stat_unit / n;
            local[i] = static_cast<float>(own[i]);
            local_var[i] = static_cast<float>(variance_of_pixel_mean(i));
        }
    });
    box_sums(local, width_, height_, region_window);
    box_sums(local_var, width_, height_, region_window);
    // The rendered pixels in a window: its overlap with the rendered rectangle.
    const RenderRegion all = region_rendered.empty()
                                 ? RenderRegion{0, 0, width_, height_}
                                 : RenderRegion{std::max(0, region_rendered.x0), std::max(0, region_rendered.y0),
                                                std::min(width_, region_rendered.x1), std::min(height_, region_rendered.y1)};
    auto overlap = [](int at, int lo, int hi) {
        return std::max(0, std::min(hi, at + region_window + 1) - std::max(lo, at - region_window));
    };
    std::vector<char> counted(pixels, 0);
    for_chunks([&](std::size_t, std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i) {
            if (!(local[i] > 0.0f) || !rendered(i)) continue;  // no photon in the window: nothing to weigh
            const int x = static_cast<int>(i % width), y = static_cast<int>(i / width);
            const double window = static_cast<double>(overlap(x, all.x0, all.x1) * overlap(y, all.y0, all.y1));
            const double m = local[i] / window, d = own[i] - m, v = local_var[i] / window;
            counted[i] = at(i, photon) > 0.0 || (m > 0.0 && v >= m * m);
            if (v > 0.0) own[i] -= d * v / (v + d * d);
        }
    });
    std::vector<float>().swap(local);
    std::vector<float>().swap(local_var);
    // The percentile's values, in pixel order: counted per chunk, then copied to their place.
    std::vector<std::size_t> offsets(chunks + 1, 0);
    for_chunks([&](std::size_t c, std::size_t begin, std::size_t end) {
        offsets[c + 1] = static_cast<std::size_t>(std::count(counted.begin() + static_cast<std::ptrdiff_t>(begin),
                                                             counted.begin() + static_cast<std::ptrdiff_t>(end), 1));
    });
    for (std::size_t c = 0; c < chunks; ++c) offsets[c + 1] += offsets[c];
    std::vector<double> lit(offsets[chunks]);
    for_chunks([&](std::size_t c, std::size_t begin, std::size_t end) {
        std::size_t k = offsets[c];
        for (std::size_t i = begin; i < end; ++i)
            if (counted[i]) lit[k++] = own[i];
    });
    // Without photons (nothing specular, no --gi) the whole image is the region: its noise is
    // the eye side's (anti-aliasing, soft shadows).
    double threshold = -1.0;
    if (!lit.empty()) {
        auto percentile = lit.begin() + static_cast<std::ptrdiff_t>(0.99 * static_cast<double>(lit.size() - 1));
        std::nth_element(lit.begin(), percentile, lit.end());
        threshold = caustic_region_fraction * *percentile;  // the rule of caustic_region()
    }
    // Once every pixel of the region has passes in each replicate group, the noise from the
    // groups: per pixel the groups' means m_g of the sample values are independent replicates of
    // variance s^2, whatever the correlations between the passes inside a group (low-discrepancy
    // patterns make them negative). With M = (m_0 + m_1 + m_2 + m_3) / 4, the image's mean,
    // E[sum (m_g - M)^2] = 3 s^2 and the variance of M is s^2 / 4: the sum over 12. Before that (passes 2 and
    // 3) the spread between all the passes, as if they were independent. The blur in both
    // cases from the radius probe: its mean squared, less its own variance (from its groups'
    // spread likewise). Summed over the region both are unbiased; a pixel's term may be negative.
    // The chunks sum the groups' terms; if some pixel of the region lacks a group, a second read
    // sums every pixel's terms from all its passes instead.
    struct Terms {
        double noise2 = 0.0, bias2 = 0.0;
    };
    struct Part {
        bool groups = true;
        double shown = 0.0;
        std::size_t region = 0;
        Terms from_groups, from_passes;
    };
    std::vector<Part> parts(chunks);
    // Pixel i, of n passes, is in the caustic region the error is measured over.
    auto in_region = [&](std::size_t i, double n) { return n >= 2.0 && rendered(i) && own[i] >= threshold; };
    // A pixel's terms, from its raw mean v, the variance of v, the probe's mean blur and its
    // variance. The shown value cannot be wrong by more than the way to 0 or to 1: a pixel that
    // holds a spot far above 1 has a huge spread and at most that error.
    auto add_pixel_terms = [](Terms& t, double v, double noise_var, double blur, double blur_var) {
        const double pixel = std::clamp(v, 0.0, 1.0), bound = std::max(pixel, 1.0 - pixel);
        t.noise2 += std::min(shown_variance(v, noise_var), bound * bound);
        t.bias2 += std::clamp(shown_blur2(v, blur, blur_var), -bound * bound, bound * bound);
    };
    for_chunks([&](std::size_t c, std::size_t begin, std::size_t end) {
        Part& part = parts[c];
        for (std::size_t i = begin; i < end; ++i) {
            const double n = at(i, count_slot);
            if (!in_region(i, n)) continue;
            ++part.region;
            const double v = at(i, value) / stat_unit / n;
            part.shown += std::clamp(v, 0.0, 1.0);
            double counts[replicate_groups];
            if (!group_counts(i, counts)) {
                part.groups = false;
            } else if (part.groups) {
                double m[replicate_groups], b[replicate_groups];
                const double spread = group_spread(i, group_value, counts, m);
                const double bias_spread = group_spread(i, group_bias, counts, b);
                // Every group surely above 1 shows white, as the converged value most likely does.
                if (*std::min_element(m, m + replicate_groups) < 1.0)
                    add_pixel_terms(part.from_groups, v, spread / 12.0, at(i, bias) / stat_unit / n, bias_spread / 12.0);
            }
        }
    });
    bool groups = true;
    double shown = 0.0;
    std::size_t region = 0;
    for (const Part& part : parts) {
        groups = groups && part.groups;
        shown += part.shown;
        region += part.region;
    }
    // Some pixel lacks a group (passes 2 and 3): every pixel's terms from all its passes, as if
    // they were independent, with the variances of the means of n passes exact from the sums.
    if (!groups) {
        for_chunks([&](std::size_t c, std::size_t begin, std::size_t end) {
            Part& part = parts[c];
            for (std::size_t i = begin; i < end; ++i) {
                const double n = at(i, count_slot);
                if (!in_region(i, n)) continue;
                const double v = at(i, value) / stat_unit / n;
                const std::int64_t* sum = &sums_[i * sums_per_pixel];
                const double noise_var = variance_of_mean(n, sum[Slot::value], sum[value2_high], sum[value2_low]);
                const double bias_mean = at(i, bias) / stat_unit / n;
                const double bias_noise_var = variance_of_mean(n, sum[bias], sum[bias2_high], sum[bias2_low]);
                // A pixel surely above 1 shows white, as its converged value most likely does.
                if (v - 2.0 * std::sqrt(noise_var) < 1.0)
                    add_pixel_terms(part.from_passes, v, noise_var, bias_mean, bias_noise_var);
            }
        });
    }
    double noise2 = 0.0, bias2_sum = 0.0;
    for (const Part& part : parts) {
        const Terms& t = groups ? part.from_groups : part.from_passes;
        noise2 += t.noise2;
        bias2_sum += t.bias2;
    }
    if (region == 0 || !(shown > 0.0)) return e;
    const double mean = shown / static_cast<double>(region);
    e.known = true;
    e.from_groups = groups;
    e.region_pixels = region;
    e.noise = std::sqrt(noise2 / static_cast<double>(region)) / mean;
    e.bias = std::sqrt(std::max(0.0, bias2_sum) / static_cast<double>(region)) / mean;
    e.relative = std::sqrt(e.noise * e.noise + e.bias * e.bias);
    return e;
}

void ProgressiveAccumulator::adapt_radius_factors(std::vector<float>& factors,
                                                  std::vector<std::int64_t>& previous) const {
    // A pass at r^2 f has a blur f times and a variance 1/f times those at r^2 (the blur of a disc
    // average grows as r^2, its photon count too). If the passes since the last update, all at f,
    // had a blur b and a variance s^2 each, the n passes so far err least (squared) when the passes
    // to come gather at f' = f (s^2 / 2 n b^2)^(1/3), where the squared blur is half the variance
    // of the mean; the global sequence of radii then keeps that balance. Only those passes count:
    // the blur of earlier ones, at other radii, is not what f' changes. b^2 and s^2 are noisy in
    // one pixel: both are summed over a window of neighbours first (b^2 less its own variance, so
    // that noise does not pass for blur).
    constexpr int half_window = 3;
    constexpr double min_factor = 1.0 / 16.0, max_factor = 1.0, max_step = 4.0;
    const std::size_t pixels = static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_);
    if (factors.size() != pixels) factors.assign(pixels, 1.0f);
    if (previous.size() != pixels * snapshot_slots) previous.assign(pixels * snapshot_slots, 0);
    constexpr std::size_t kept[snapshot_slots] = {count_slot, Slot::value, value2_high, value2_low,
                                                  bias, bias2_high, bias2_low};
    std::vector<double> noise(pixels, 0.0), blur2(pixels, 0.0);
    std::vector<char> lit(pixels, 0);
    for (std::size_t i = 0; i < pixels; ++i) {
        const std::int64_t* s = &sums_[i * sums_per_pixel];
        std::int64_t* before = &previous[i * snapshot_slots];
        std::int64_t d[snapshot_slots];
        for (std::size_t k = 0; k < snapshot_slots; ++k) {
            d[k] = s[kept[k]] - before[k];
            before[k] = s[kept[k]];
        }
        const double m = static_cast<double>(d[0]), n = static_cast<double>(s[count_slot]);
        if (m < 2.0 || s[photon] <= 0) continue;
        lit[i] = 1;
        // On the values shown, as the error is measured (a pixel far above 1 has neither): the
        // mean of every pass so far; variance_of_mean gives s^2 / m, and s^2 / n is that times m / n.
        const double v = static_cast<double>(s[Slot::value]) / stat_unit / n;
        noise[i] = shown_variance(v, variance_of_mean(m, d[1], d[2], d[3]) * m / n);
        blur2[i] = shown_blur2(v, static_cast<double>(d[4]) / stat_unit / m, variance_of_mean(m, d[4], d[5], d[6]));
    }
    box_sums(noise, width_, height_, half_window);
    box_sums(blur2, width_, height_, half_window);
    for (std::size_t i = 0; i < pixels; ++i) {
        if (!lit[i]) continue;
        // No measurable blur: as large as the step allows.
        double step = max_step;
        if (blur2[i] > 0.0)
            step = std::clamp(std::cbrt(std::max(0.0, noise[i]) / (2.0 * blur2[i])), 1.0 / max_step, max_step);
        factors[i] = static_cast<float>(std::clamp(static_cast<double>(factors[i]) * step, min_factor, max_factor));
    }
}

}  // namespace caustica
