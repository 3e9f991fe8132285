// Progressive photon mapping's image side (issue 11): the per-pixel sums of every pass's sample,
// from which the image is the mean, and the renderer's own estimate of its remaining error
// (noise from the spread between passes, bias from the radius probe). Memory is fixed by the
// image size, whatever the number of passes.
#pragma once

#include "core/render/image.h"

#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace caustica {

/// One pass's contribution to a pixel.
struct PassSample {
    glm::vec3 colour{0.0f};
    /// The photon radiance kd E gathered along the sample's path (mean of the channels), at the
    /// pass radius r and at r / sqrt 2.
    double photon = 0.0, photon_inner = 0.0;
};

/// The renderer's estimate of the relative RMSE of the accumulated image over its caustic region,
/// on the values the PNG shows (clamped to [0, 1]), against the converged image.
struct ErrorEstimate {
    bool known = false;            ///< needs at least 2 passes and a caustic region
    double relative = 0.0;         ///< sqrt(noise^2 + bias^2) / mean over the region
    double noise = 0.0, bias = 0.0;  ///< the two parts, relative as well
    std::size_t region_pixels = 0;
};

/// The radius sequence of Knaus & Zwicker (2011): r^2 after pass i (1-based) from r^2 at pass i,
/// r^2_{i+1} = r^2_i (i + alpha) / (i + 1).
inline double next_radius2(double radius2, int pass, double alpha) {
    return radius2 * (static_cast<double>(pass) + alpha) / (static_cast<double>(pass) + 1.0);
}

class ProgressiveAccumulator {
public:
    /// Empties the sums for an image of this size.
    void reset(int width, int height);
    int width() const { return width_; }
    int height() const { return height_; }
    bool empty() const { return pixels_.empty(); }

    /// Adds a pass's sample to a pixel; returns the pixel's new mean colour. Pixels are
    /// independent: tiles may add concurrently to different pixels.
    glm::vec3 add(std::size_t pixel, const PassSample& sample);

    /// The mean colour of a pixel (black before its first sample).
    glm::vec3 mean(std::size_t pixel) const;
    /// A pixel's first gather radius r_1 (0 until a pass gathered for it), and setting it once.
    float first_radius(std::size_t pixel) const { return pixels_[pixel].first_radius; }
    void set_first_radius(std::size_t pixel, float radius) { pixels_[pixel].first_radius = radius; }
    /// Samples a pixel has (passes that reached it).
    std::uint32_t samples(std::size_t pixel) const { return pixels_[pixel].count; }

    /// The accumulated image (means).
    Image image() const;

    /// The estimate of the remaining error (see ErrorEstimate). O(pixels).
    ErrorEstimate estimate_error() const;

    /// Bytes held: fixed by the image size.
    std::size_t memory_bytes() const { return pixels_.capacity() * sizeof(Pixel); }

private:
    // Running means and sums of squared deviations (Welford), stable in float for any count.
    struct Pixel {
        glm::vec3 mean{0.0f};
        float value_m2 = 0.0f;  ///< of the sample value (mean of the channels)
        float photon = 0.0f;    ///< mean photon radiance
        float bias = 0.0f;      ///< mean bias probe 2 (L_r - L_{r/sqrt 2})
        float bias_m2 = 0.0f;
        float first_radius = 0.0f;  ///< r_1 of the pixel's gathers (0 until its first gather)
        std::uint32_t count = 0;
    };
    int width_ = 0, height_ = 0;
    std::vector<Pixel> pixels_;
};

}  // namespace caustica
