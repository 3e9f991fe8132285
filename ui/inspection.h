// Inspection of the shown image, GL-free (docs/INSPECTION.md): the luminance histogram with the
// clipped and black fractions, comparison metrics against a reference image, the value of the
// pixel under the cursor, the relative-error colour ramp, and the zoom and pan of the image view.
// The shader (shaders/image.frag) applies the same formulas per pixel; these are what the panels
// print and what the tests pin down.
#pragma once

#include "core/render/image.h"
#include "ui/image_layout.h"

#include <glm/glm.hpp>

#include <array>
#include <cmath>
#include <cstddef>
#include <optional>
#include <string>

namespace caustica::ui {

/// Rec. 709 luminance of linear RGB.
inline float luminance(glm::vec3 c) { return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b; }

/// Sampling stride that keeps a width x height image to at most `budget` samples (1 for small
/// images): statistics are taken on every stride-th pixel of every stride-th row.
int sample_stride(int width, int height, std::size_t budget = 32768);

/// Luminance histogram of the displayed values (after the exposure multiplier): `bin_count` bins
/// spaced evenly in log10 over [10^log_lo, 10^log_hi), ten per decade by default.
struct LuminanceHistogram {
    static constexpr int bin_count = 60;
    static constexpr float log_lo = -4.0f, log_hi = 2.0f;
    std::array<float, bin_count> bins{};  ///< fraction of the samples in each bin
    float below = 0.0f;    ///< fraction under 10^log_lo (zero included)
    float above = 0.0f;    ///< fraction at or over 10^log_hi
    float clipped = 0.0f;  ///< fraction with any channel >= 1 after exposure (white in the display)
    float black = 0.0f;    ///< fraction with every channel < 1/255 after exposure (black in 8 bits)
    float invalid = 0.0f;  ///< fraction with a NaN or infinite channel (not in the bins)
    std::size_t samples = 0;

    /// Lower edge of bin i (luminance).
    static float edge(int i) { return std::pow(10.0f, log_lo + (log_hi - log_lo) * static_cast<float>(i) / bin_count); }
};

/// The histogram of `image` times `exposure` (a multiplier, 2^stops), on every `stride`-th pixel.
LuminanceHistogram luminance_histogram(const Image& image, float exposure, int stride = 1);

/// How a current image differs from a reference of the same size.
struct ImageComparison {
    double rmse = 0.0;           ///< sqrt(mean over samples and channels of (a - b)^2)
    double mean_relative = 0.0;  ///< mean of |a - b|_1 / |b|_1 over samples with |b|_1 > epsilon
    double max_abs = 0.0;        ///< largest |a_c - b_c|
    std::size_t samples = 0;           ///< pixels compared
    std::size_t non_finite = 0;        ///< sampled pixels left out: NaN or infinite in either image
    std::size_t relative_samples = 0;  ///< of which counted in mean_relative
};

/// Relative error of one pixel as the heat map shows it: |a - b|_1 / max(|b|_1, epsilon), with
/// |x|_1 the sum of the three channels.
float relative_error(glm::vec3 current, glm::vec3 reference, float epsilon);

/// Compares every `stride`-th pixel; nullopt when the sizes differ or an image is empty.
/// Non-finite pixels are skipped.
std::optional<ImageComparison> compare_images(const Image& current, const Image& reference, float epsilon = 1e-3f,
                                              int stride = 1);

/// The heat map's scale: relative error 10^-3 (0.1 %) and below is t = 0, 1 (100 %) and above is
/// t = 1, log-spaced between.
float heat_position(float relative);
/// The heat map's colour ramp at t in [0, 1] (dark blue, blue, green, yellow, red; the shader's).
glm::vec3 heat_colour(float t);

/// What lies under the cursor.
struct PixelReadout {
    bool valid = false;  ///< the point is on the image
    int x = 0, y = 0;    ///< image pixel (column, row from the top)
    glm::vec3 rgb{0.0f}; ///< linear radiance as rendered (before exposure)
    std::optional<glm::vec3> reference;  ///< the reference's pixel, when one of the same size is loaded
};

/// The labels of the histogram's x axis, evenly spaced from its left edge to its right: every
/// second decade of luminance from 10^log_lo to 10^log_hi ("1e-4", "0.01", "1", "100").
std::array<std::string, 4> histogram_axis_labels();

/// What the A/B comparison must say about a reference read from `path`: a PNG holds 8-bit values
/// clamped to [0, 1] while the shown image is HDR, so they differ wherever the shown image leaves
/// that range ("" for EXR and PFM, which hold the radiance).
std::string reference_range_note(const std::string& path);

/// The pixel of `image` containing image point `p` (pixels are unit squares from (0, 0)).
PixelReadout read_pixel(const Image& image, glm::vec2 p, const Image* reference = nullptr);

/// "0.123 0.456 7.89": a colour with three significant figures per channel.
std::string format_rgb(glm::vec3 c);

/// Zoom and pan of the image view. In `fit` the image is placed by fit_image; otherwise it is
/// magnified by `scale` with image point `centre` at the middle of the area.
struct ImageZoom {
    bool fit = true;
    float scale = 1.0f;
    glm::vec2 centre{0.0f};

    /// Magnifications the wheel steps through: whole factors above 1 (pixels stay sharp squares).
    static constexpr std::array<float, 19> steps = {1.0f / 16, 1.0f / 8, 1.0f / 6, 1.0f / 4, 1.0f / 3, 1.0f / 2, 2.0f / 3,
                                                    1.0f, 2.0f, 3.0f, 4.0f, 6.0f, 8.0f, 12.0f, 16.0f, 24.0f,
                                                    32.0f, 48.0f, 64.0f};
    static constexpr float min_scale = 1.0f / 16, max_scale = 64.0f;

    /// Where the image goes in the area (a whole-pixel origin).
    ImageLayout layout(glm::vec2 area_origin, glm::vec2 area_size, int width, int height) const;
    /// Back to fitting the area.
    void fit_area() { fit = true; }
    /// Steps the magnification up (`steps` > 0) or down, keeping the image point under `cursor`
    /// where it is; `current` is the layout shown now.
    void zoom_at(const ImageLayout& current, glm::vec2 area_origin, glm::vec2 area_size, glm::vec2 cursor, int steps);
    /// Sets the magnification to `new_scale` keeping the image point under `cursor` in place.
    void set_scale(const ImageLayout& current, glm::vec2 area_origin, glm::vec2 area_size, glm::vec2 cursor,
                   float new_scale);
    /// Moves the image by `delta` window pixels.
    void pan(const ImageLayout& current, glm::vec2 area_origin, glm::vec2 area_size, glm::vec2 delta);
    /// Keeps the centre on the image and the scale in range.
    void clamp(int width, int height);
};

}  // namespace caustica::ui
