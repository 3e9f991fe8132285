// The caustic error: how far an image is from a reference, as the PNG shows both, over the
// reference's caustic region (docs/ACCURACY.md, "The caustic error"). `caustica compare`, the
// renderer's own estimate and bench/trade all mean this.
#pragma once

#include "core/render/image.h"

#include <glm/vec3.hpp>

#include <cstddef>
#include <vector>

namespace caustica {

/// A pixel's value as the PNG shows it: each channel clamped to [0, 1], then their mean.
double shown_value(const glm::vec3& pixel);

/// The fraction of the 99th percentile of the reference's non-zero shown values that a pixel's
/// shown reference value must reach to belong to the caustic region.
inline constexpr double caustic_region_fraction = 0.1;

/// The pixel indices of the reference's caustic region (empty when the reference is all black).
std::vector<std::size_t> caustic_region(const Image& reference);

/// Error of one image against a reference of the same size, on shown (clamped) values.
struct ImageError {
    double rmse = 0.0;      ///< over every pixel and channel
    double rel_rmse = 0.0;  ///< over the caustic region, relative to the reference's mean there
    double rel_bias = 0.0;  ///< the image's sum over the region / the reference's - 1
    std::size_t region_pixels = 0;
};

/// The error of `image` against `reference` (same size), relative over `region`.
ImageError compare_images(const Image& image, const Image& reference, const std::vector<std::size_t>& region);

}  // namespace caustica
