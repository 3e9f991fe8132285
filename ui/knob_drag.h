// How a drag on a logarithmic knob (photons, N, the distances) changes its value: by a bounded
// factor a pixel, so that a short drag is a small change wherever the value lies, and a coarser
// factor with Shift (docs/PREVIEW.md, "Panels"). GL-free, so that the mapping is unit-tested.
#pragma once

namespace caustica::ui {

/// Where a logarithmic knob's drag may take it.
struct LogKnobScale {
    double lo = 1.0;     ///< the smallest positive value a drag reaches
    double hi = 1e6;     ///< the largest value a drag reaches
    bool zero = false;   ///< left of `lo` lies 0, the knob's "off" (photons)
    bool whole = false;  ///< whole numbers only
};

/// A drag's factor a pixel: 1 % by default ...
inline constexpr double fine_factor_per_pixel = 1.01;
/// ... and 10 % with Shift.
inline constexpr double coarse_factor_per_pixel = 1.10;
/// A whole-number knob moves at least one a this many pixels (at 1 % a pixel, N would need 70
/// pixels to go from 1 to 2).
inline constexpr double whole_step_pixels = 8.0;
/// Pixels between 0 and `lo` on a knob that can be 0: the first half stays at 0, the second at `lo`.
inline constexpr double zero_gap_pixels = 8.0;

/// The value after a drag of `pixels` (positive: to the right) that started at `start`: `start`
/// times the factor a pixel (coarse: Shift held) to the power `pixels`, within the scale. The
/// scale widens to hold `start`, so that a drag never snaps a typed value to the scale's end, and
/// no drag (0 pixels) changes nothing. From 0, the drag reaches `lo` after zero_gap_pixels.
double dragged_value(const LogKnobScale& scale, double start, double pixels, bool coarse);

/// A drag in progress: its value follows the mouse from where the drag started, and a change of
/// the modifier starts again from the value reached, so that pressing or releasing Shift in
/// mid-drag never makes the value jump.
class LogKnobDrag {
public:
    /// The button went down on the knob at `mouse_x` with the knob at `value`.
    void begin(double value, double mouse_x, bool coarse);
    /// The knob's value with the mouse at `mouse_x`.
    double update(const LogKnobScale& scale, double mouse_x, bool coarse);

private:
    double start_value_ = 0.0, start_x_ = 0.0, last_value_ = 0.0;
    bool coarse_ = false;
};

}  // namespace caustica::ui
