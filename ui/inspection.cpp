#include "ui/inspection.h"

#include "core/io/image_io.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace caustica::ui {
namespace {

bool finite(glm::vec3 c) { return std::isfinite(c.r) && std::isfinite(c.g) && std::isfinite(c.b); }
float l1(glm::vec3 c) { return std::abs(c.r) + std::abs(c.g) + std::abs(c.b); }

}  // namespace

int sample_stride(int width, int height, std::size_t budget) {
    if (width <= 0 || height <= 0 || budget == 0) return 1;
    int stride = 1;
    auto samples = [&](int s) {
        return static_cast<std::size_t>((width + s - 1) / s) * static_cast<std::size_t>((height + s - 1) / s);
    };
    while (samples(stride) > budget) ++stride;
    return stride;
}

LuminanceHistogram luminance_histogram(const Image& image, float exposure, int stride) {
    LuminanceHistogram h;
    stride = std::max(stride, 1);
    std::array<std::size_t, LuminanceHistogram::bin_count> counts{};
    std::size_t below = 0, above = 0, clipped = 0, black = 0, invalid = 0, n = 0;
    static const std::array<float, LuminanceHistogram::bin_count + 1> edges = [] {
        std::array<float, LuminanceHistogram::bin_count + 1> e{};
        for (int i = 0; i <= LuminanceHistogram::bin_count; ++i) e[static_cast<std::size_t>(i)] = LuminanceHistogram::edge(i);
        return e;
    }();
    const float lo = edges.front(), hi = edges.back();
    for (int y = 0; y < image.height; y += stride)
        for (int x = 0; x < image.width; x += stride) {
            ++n;
            const glm::vec3 c = image.at(x, y) * exposure;
            if (!finite(c)) {
                ++invalid;
                continue;
            }
            if (c.r >= 1.0f || c.g >= 1.0f || c.b >= 1.0f) ++clipped;
            // The display truncates c x 255 (image.frag): below 1/255 is 0.
            if (c.r * 255.0f < 1.0f && c.g * 255.0f < 1.0f && c.b * 255.0f < 1.0f) ++black;
            const float y_lum = luminance(c);
            if (!(y_lum >= lo)) {
                ++below;
            } else if (y_lum >= hi) {
                ++above;
            } else {  // the bin whose lower edge is the last at or below: a search, cheaper than a log
                const auto upper = std::upper_bound(edges.begin() + 1, edges.end() - 1, y_lum);
                ++counts[static_cast<std::size_t>(upper - edges.begin() - 1)];
            }
        }
    h.samples = n;
    if (n == 0) return h;
    const float inv = 1.0f / static_cast<float>(n);
    for (int i = 0; i < LuminanceHistogram::bin_count; ++i) h.bins[i] = static_cast<float>(counts[i]) * inv;
    h.below = static_cast<float>(below) * inv;
    h.above = static_cast<float>(above) * inv;
    h.clipped = static_cast<float>(clipped) * inv;
    h.black = static_cast<float>(black) * inv;
    h.invalid = static_cast<float>(invalid) * inv;
    return h;
}

float relative_error(glm::vec3 current, glm::vec3 reference, float epsilon) {
    return l1(current - reference) / std::max(l1(reference), epsilon);
}

std::optional<ImageComparison> compare_images(const Image& current, const Image& reference, float epsilon, int stride) {
    if (current.width != reference.width || current.height != reference.height || current.width <= 0 ||
        current.height <= 0)
        return std::nullopt;
    stride = std::max(stride, 1);
    ImageComparison r;
    double squares = 0.0, relative = 0.0;
    for (int y = 0; y < current.height; y += stride)
        for (int x = 0; x < current.width; x += stride) {
            const glm::vec3 a = current.at(x, y), b = reference.at(x, y);
            if (!finite(a) || !finite(b)) {
                ++r.non_finite;  // counted, so that "RMSE 0" of an all-NaN image is not taken for a match
                continue;
            }
            const glm::dvec3 d = glm::dvec3(a) - glm::dvec3(b);
            squares += d.x * d.x + d.y * d.y + d.z * d.z;
            r.max_abs = std::max({r.max_abs, std::abs(d.x), std::abs(d.y), std::abs(d.z)});
            ++r.samples;
            const double ref = static_cast<double>(l1(b));
            if (ref > epsilon) {
                relative += (std::abs(d.x) + std::abs(d.y) + std::abs(d.z)) / ref;
                ++r.relative_samples;
            }
        }
    if (r.samples > 0) r.rmse = std::sqrt(squares / (3.0 * static_cast<double>(r.samples)));
    if (r.relative_samples > 0) r.mean_relative = relative / static_cast<double>(r.relative_samples);
    return r;
}

float heat_position(float relative) {
    if (!(relative > 1e-3f)) return 0.0f;  // NaN too
    return std::min(1.0f, (std::log10(relative) + 3.0f) / 3.0f);
}

glm::vec3 heat_colour(float t) {
    // Keep in step with heat() in shaders/image.frag.
    static constexpr glm::vec3 stops[5] = {{0.0f, 0.0f, 0.25f}, {0.0f, 0.35f, 1.0f}, {0.0f, 0.8f, 0.3f},
                                           {1.0f, 0.9f, 0.0f}, {1.0f, 0.0f, 0.0f}};
    const float s = std::clamp(t, 0.0f, 1.0f) * 4.0f;
    const int i = std::min(static_cast<int>(s), 3);
    return glm::mix(stops[i], stops[i + 1], s - static_cast<float>(i));
}

PixelReadout read_pixel(const Image& image, glm::vec2 p, const Image* reference) {
    PixelReadout r;
    if (!(p.x >= 0.0f && p.y >= 0.0f && p.x < image.width && p.y < image.height)) return r;
    r.valid = true;
    r.x = std::min(static_cast<int>(p.x), image.width - 1);
    r.y = std::min(static_cast<int>(p.y), image.height - 1);
    r.rgb = image.at(r.x, r.y);
    if (reference && reference->width == image.width && reference->height == image.height)
        r.reference = reference->at(r.x, r.y);
    return r;
}

std::string format_rgb(glm::vec3 c) {
    char text[96];
    std::snprintf(text, sizeof text, "%.3g %.3g %.3g", static_cast<double>(c.r), static_cast<double>(c.g),
                  static_cast<double>(c.b));
    return text;
}

ImageLayout ImageZoom::layout(glm::vec2 area_origin, glm::vec2 area_size, int width, int height) const {
    if (fit) return fit_image(area_origin, area_size, width, height);
    ImageLayout l;
    l.image_width = width;
    l.image_height = height;
    l.scale = scale;
    l.origin = glm::floor(area_origin + 0.5f * area_size - centre * scale + 0.5f);
    return l;
}

void ImageZoom::set_scale(const ImageLayout& current, glm::vec2 area_origin, glm::vec2 area_size, glm::vec2 cursor,
                          float new_scale) {
    new_scale = std::clamp(new_scale, min_scale, max_scale);
    const glm::vec2 p = current.to_image(cursor);  // stays under the cursor
    const glm::vec2 origin = cursor - p * new_scale;
    centre = (area_origin + 0.5f * area_size - origin) / new_scale;
    scale = new_scale;
    fit = false;
    clamp(current.image_width, current.image_height);
}

void ImageZoom::zoom_at(const ImageLayout& current, glm::vec2 area_origin, glm::vec2 area_size, glm::vec2 cursor,
                        int count) {
    float s = current.scale;
    for (; count > 0; --count) {
        const auto next = std::find_if(steps.begin(), steps.end(), [&](float v) { return v > s * 1.001f; });
        s = next == steps.end() ? max_scale : *next;
    }
    for (; count < 0; ++count) {
        const auto next = std::find_if(steps.rbegin(), steps.rend(), [&](float v) { return v < s / 1.001f; });
        s = next == steps.rend() ? min_scale : *next;
    }
    set_scale(current, area_origin, area_size, cursor, s);
}

void ImageZoom::pan(const ImageLayout& current, glm::vec2 area_origin, glm::vec2 area_size, glm::vec2 delta) {
    if (fit) {  // start from what is shown
        scale = current.scale;
        centre = current.to_image(area_origin + 0.5f * area_size);
        fit = false;
    }
    centre -= delta / scale;
    clamp(current.image_width, current.image_height);
}

std::array<std::string, 4> histogram_axis_labels() {
    std::array<std::string, 4> labels;
    for (int i = 0; i < 4; ++i) {
        const float exponent = LuminanceHistogram::log_lo + (LuminanceHistogram::log_hi - LuminanceHistogram::log_lo) * i / 3.0f;
        char text[16];
        if (exponent < -2.5f) std::snprintf(text, sizeof text, "1e%.0f", static_cast<double>(exponent));
        else std::snprintf(text, sizeof text, "%g", std::pow(10.0, static_cast<double>(exponent)));
        labels[i] = text;
    }
    return labels;
}

std::string reference_range_note(const std::string& path) {
    if (image_format_of(path) != ImageFormat::png) return {};
    return "B is an 8-bit PNG: values clamped to 0..1 in steps of 1/255, while A is the HDR render, so they differ "
           "wherever A is above 1 or very dark. Load an EXR or PFM to compare radiance.";
}

void ImageZoom::clamp(int width, int height) {
    scale = std::clamp(scale, min_scale, max_scale);
    centre = glm::clamp(centre, glm::vec2(0.0f), glm::vec2(std::max(width, 0), std::max(height, 0)));
}

}  // namespace caustica::ui
