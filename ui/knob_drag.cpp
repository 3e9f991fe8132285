#include "ui/knob_drag.h"

#include <algorithm>
#include <cmath>

namespace caustica::ui {
namespace {

/// `start` times the factor a pixel to the power `pixels`; a whole-number knob moves at least one
/// every whole_step_pixels.
double scaled(const LogKnobScale& scale, double start, double pixels, double factor) {
    const double value = start * std::pow(factor, pixels);
    if (!scale.whole) return value;
    const double steps = std::trunc(pixels / whole_step_pixels);
    return pixels > 0.0 ? std::max(value, start + steps) : std::min(value, start + steps);
}

}  // namespace

double dragged_value(const LogKnobScale& scale, double start, double pixels, bool coarse) {
    if (pixels == 0.0) return start;
    const double lo = start > 0.0 ? std::min(scale.lo, start) : scale.lo;
    const double hi = std::max({scale.hi, start, lo});
    const double factor = coarse ? coarse_factor_per_pixel : fine_factor_per_pixel;
    if (start <= 0.0) {
        if (!scale.zero) return dragged_value(scale, lo, pixels, coarse);
        if (pixels < 0.5 * zero_gap_pixels) return 0.0;
        return dragged_value(scale, lo, pixels - zero_gap_pixels, coarse);
    }
    const double value = scaled(scale, start, pixels, factor);
    if (value < lo) {
        if (!scale.zero) return lo;
        const double pixels_left_of_lo = std::log(lo / value) / std::log(factor);
        return pixels_left_of_lo > 0.5 * zero_gap_pixels ? 0.0 : lo;
    }
    const double clamped = std::min(value, hi);
    return scale.whole ? std::round(clamped) : clamped;
}

void LogKnobDrag::begin(double value, double mouse_x, bool coarse) {
    start_value_ = last_value_ = value;
    start_x_ = mouse_x;
    coarse_ = coarse;
}

double LogKnobDrag::update(const LogKnobScale& scale, double mouse_x, bool coarse) {
    if (coarse != coarse_) begin(last_value_, mouse_x, coarse);
    last_value_ = dragged_value(scale, start_value_, mouse_x - start_x_, coarse);
    return last_value_;
}

}  // namespace caustica::ui
