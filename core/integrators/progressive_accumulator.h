// Progressive photon mapping's image side: the per-pixel sums of every pass's sample, from which
// the image is the mean, and the renderer's own estimate of its remaining error (docs/ACCURACY.md,
// "The renderer's estimate"). Memory is fixed by the image size, whatever the number of passes.
#pragma once

#include "core/render/image.h"
#include "core/render/render_region.h"

#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace caustica {

/// Passes are dealt into this many groups, independent replicates of the accumulation (pass p
/// into group p mod 4), each with its own photon and pixel sequences. The spread between the
/// groups measures the noise, whatever the correlations between the passes of one group.
inline constexpr int replicate_groups = 4;

/// One pass's contribution to a pixel.
struct PassSample {
    glm::vec3 colour{0.0f};
    /// The photon radiance kd E gathered along the sample's path (mean of the channels), at the
    /// pass radius r and at r / sqrt 2 (the blur probe of the estimate).
    double photon = 0.0, photon_inner = 0.0;
    int group = 0;  ///< the replicate group of the pass (0 to replicate_groups - 1)
};

/// The renderer's estimate of the relative RMSE of the accumulated image over its caustic region,
/// on the values the PNG shows (clamped to [0, 1]), against the converged image.
struct ErrorEstimate {
    bool known = false;            ///< needs at least 2 passes and a caustic region
    bool from_groups = false;      ///< from the replicate groups (every group has passes), not the probe
    double relative = 0.0;         ///< sqrt(noise^2 + bias^2) / mean over the region
    double noise = 0.0, bias = 0.0;  ///< the two parts, relative as well
    std::size_t region_pixels = 0;
};

/// The radius sequence of Knaus & Zwicker (2011): r^2 after pass i (1-based) from r^2 at pass i,
/// r^2_{i+1} = r^2_i (i + alpha) / (i + 1).
inline double next_radius2(double radius2, int pass, double alpha) {
    return radius2 * (static_cast<double>(pass) + alpha) / (static_cast<double>(pass) + 1.0);
}

/// The most passes one accumulation adds (its integer sums cannot overflow below it).
inline constexpr int max_accumulated_passes = 1 << 23;

/// The per-pixel sums of a progressive accumulation, in integers: each pass's sample is rounded
/// to fixed point once and added exactly, so the sums do not depend on the order the passes are
/// added in. Ranks that ran different passes add their sums (Cluster::reduce_sum) and get the
/// bits one process gets. Colour is held to 2^-40 (two int64 per channel, |sample| up to 2^31: signed, for
/// --show-layer normal);
/// the error statistics to 2^-16 with exact squares (two int64 each), so a pixel that does not
/// change between passes has a variance of exactly 0; each replicate group's value sum and count.
/// Up to max_accumulated_passes passes. 200 bytes per pixel.
class ProgressiveAccumulator {
public:
    /// int64 sums per pixel (see sums()).
    static constexpr std::size_t sums_per_pixel = 25;

    /// Where a pixel's sample count sits among its sums (what a saved state is checked by).
    static constexpr std::size_t sample_count_slot = 13;

    /// Empties the sums for an image of this size.
    void reset(int width, int height);
    /// Takes up saved sums (sums_per_pixel per pixel of a width x height image) without another copy.
    void adopt(int width, int height, std::vector<std::int64_t>&& sums);
    int width() const { return width_; }
    int height() const { return height_; }
    bool empty() const { return counts_empty(); }

    /// Adds a pass's sample to a pixel; returns the pixel's new mean colour. Pixels are
    /// independent: tiles may add concurrently to different pixels.
    glm::vec3 add(std::size_t pixel, const PassSample& sample);

    /// The mean colour of a pixel (black before its first sample).
    glm::vec3 mean(std::size_t pixel) const;
    /// Samples a pixel has (passes that reached it).
    std::uint32_t samples(std::size_t pixel) const {
        return static_cast<std::uint32_t>(sums_[pixel * sums_per_pixel + count_slot]);
    }

    /// The accumulated image (means).
    Image image() const;

    /// The estimate of the remaining error (see ErrorEstimate) over the pixels of `region` (empty:
    /// the whole image), whose caustic part is then found among those pixels alone. O(pixels).
    ErrorEstimate estimate_error(const RenderRegion& region = {}) const;

    /// Updates each pixel's radius factor (the multiplier of r^2 its passes to come gather with;
    /// `factors` holds one per pixel, 1 to start) so that noise and blur come into the balance of
    /// least squared error, from the passes since the last update: `previous` holds the sums then
    /// (snapshot_slots per pixel; empty at the first) and is brought up to now. docs/CAUSTICS.md,
    /// "A radius per pixel". Deterministic: the same sums give the same factors. O(pixels).
    void adapt_radius_factors(std::vector<float>& factors, std::vector<std::int64_t>& previous) const;
    /// int64 per pixel that adapt_radius_factors keeps between updates.
    static constexpr std::size_t snapshot_slots = 7;

    /// Bytes per pixel estimate_error holds while it runs, at most (freed when it returns): the
    /// region's shrunk values with their window sums (20), or with the values its percentile is
    /// taken of and which pixels give one (17), rounded up.
    static constexpr std::size_t estimate_bytes_per_pixel = 25;

    /// Bytes held: fixed by the image size.
    std::size_t memory_bytes() const {
        return sums_.capacity() * sizeof(std::int64_t);
    }

    /// The integer sums, sums_per_pixel per pixel in pixel order: what ranks add together.
    std::vector<std::int64_t>& sums() { return sums_; }
    const std::vector<std::int64_t>& sums() const { return sums_; }

private:
    // Per pixel: colour in two parts (units of 2^-8, and the remainder in units of 2^-40); in
    // units of 2^-16 (q = x 2^16, |x| < 2^16) the sample value v (mean of the channels) and its
    // square q^2 in two parts (q^2 >> 32, q^2 & (2^32 - 1)), the photon probe, the bias probe and
    // its square likewise; the sample count; per replicate group the sum of the values (units of
    // 2^-16), but for the last the count, and the sum of the bias probe.
    enum Slot : std::size_t {
        colour_high = 0, colour_low = 3, value = 6, value2_high, value2_low, photon, bias, bias2_high, bias2_low,
        count_slot, group_value = 14, group_count = 18, group_bias = 21
    };
    bool counts_empty() const { return sums_.empty(); }
    int width_ = 0, height_ = 0;
    std::vector<std::int64_t> sums_;
};

}  // namespace caustica
