// How a drag moves a logarithmic knob (ui/knob_drag.h): by a bounded factor a pixel, fine by
// default and coarse with Shift, from 0 to the first value and back, never snapping a typed value.
#include "ui/knob_drag.h"

#include <gtest/gtest.h>

#include <cmath>

namespace caustica::ui {
namespace {

const LogKnobScale neighbours{1.0, 1e6, false, true};
const LogKnobScale photons{1000.0, 1e9, true, true};
const LogKnobScale distance{1e-3, 1e4};

TEST(KnobDrag, AShortFineDragStaysNearTheStartAndACoarseOneGoesFurther) {
    // 29 pixels from N = 25 (a slider spanning six decades across its width takes them to 2565).
    const double fine = dragged_value(neighbours, 25.0, 29.0, false);
    EXPECT_GT(fine, 25.0);
    EXPECT_LE(fine, 1.5 * 25.0);
    EXPECT_EQ(fine, std::round(25.0 * std::pow(fine_factor_per_pixel, 29.0)));
    const double coarse = dragged_value(neighbours, 25.0, 29.0, true);
    EXPECT_GT(coarse, 4.0 * fine);
    EXPECT_EQ(coarse, std::round(25.0 * std::pow(coarse_factor_per_pixel, 29.0)));
    // To the left as much: the same factors, divided.
    EXPECT_EQ(dragged_value(neighbours, 25.0, -29.0, false), std::round(25.0 / std::pow(fine_factor_per_pixel, 29.0)));
}

TEST(KnobDrag, EveryPixelChangesTheValueByAtMostItsFactor) {
    for (bool coarse : {false, true}) {
        const double factor = coarse ? coarse_factor_per_pixel : fine_factor_per_pixel;
        // 60 pixels either way stay within the scale at either factor.
        double last = dragged_value(distance, 0.5, -60.0, coarse);
        for (int pixels = -59; pixels <= 60; ++pixels) {
            const double value = dragged_value(distance, 0.5, pixels, coarse);
            EXPECT_GT(value, last) << pixels;
            EXPECT_LE(value / last, factor * (1.0 + 1e-12)) << pixels;
            last = value;
        }
    }
    // A fine drag across a whole sidebar (300 pixels) spans less than two decades.
    EXPECT_LT(dragged_value(distance, 0.5, 300.0, false) / 0.5, 100.0);
}

TEST(KnobDrag, NoMovementChangesNothingAndTypedValuesOutsideTheScaleStay) {
    EXPECT_EQ(dragged_value(neighbours, 25.0, 0.0, true), 25.0);
    EXPECT_EQ(dragged_value(distance, 0.0, 0.0, false), 0.0);  // a click alone keeps even an odd value
    // Typed values beyond the scale's ends: the scale widens, the drag goes on from them.
    EXPECT_EQ(dragged_value(photons, 2e9, -1.0, false), std::round(2e9 / fine_factor_per_pixel));
    EXPECT_EQ(dragged_value(photons, 5.0, 1.0, false), 5.0);  // 5.05 photons: still 5
    EXPECT_EQ(dragged_value(photons, 5.0, 8.0, false), 6.0);  // one whole step in 8 pixels
    // The scale's own ends hold.
    EXPECT_EQ(dragged_value(distance, 1e-3, -50.0, true), 1e-3);
    EXPECT_EQ(dragged_value(neighbours, 900'000.0, 100.0, true), 1e6);
}

TEST(KnobDrag, WholeKnobsMoveAtLeastOneEveryFewPixels) {
    EXPECT_EQ(dragged_value(neighbours, 1.0, whole_step_pixels - 1.0, false), 1.0);
    EXPECT_EQ(dragged_value(neighbours, 1.0, whole_step_pixels, false), 2.0);
    EXPECT_EQ(dragged_value(neighbours, 1.0, 2.0 * whole_step_pixels, false), 3.0);
    EXPECT_EQ(dragged_value(neighbours, 5.0, -whole_step_pixels, false), 4.0);
    EXPECT_EQ(dragged_value(neighbours, 2.0, -10.0 * whole_step_pixels, false), 1.0);  // not below the scale
}

TEST(KnobDrag, ZeroLiesLeftOfTheFirstValue) {
    EXPECT_EQ(dragged_value(photons, 0.0, 0.4 * zero_gap_pixels, false), 0.0);
    EXPECT_EQ(dragged_value(photons, 0.0, 0.6 * zero_gap_pixels, false), 1000.0);
    EXPECT_EQ(dragged_value(photons, 0.0, zero_gap_pixels, false), 1000.0);
    EXPECT_EQ(dragged_value(photons, 0.0, zero_gap_pixels + 50.0, false),
              std::round(1000.0 * std::pow(fine_factor_per_pixel, 50.0)));
    EXPECT_EQ(dragged_value(photons, 0.0, -20.0, true), 0.0);
    EXPECT_EQ(dragged_value(photons, 1000.0, -0.4 * zero_gap_pixels, false), 1000.0);
    EXPECT_EQ(dragged_value(photons, 1000.0, -0.6 * zero_gap_pixels, false), 0.0);
    EXPECT_EQ(dragged_value(photons, 1000.0, -0.6 * zero_gap_pixels, true), 0.0);
    // A knob without 0 stays at its first value.
    EXPECT_EQ(dragged_value(neighbours, 1.0, -100.0, true), 1.0);
}

TEST(KnobDrag, ShiftInMidDragGoesOnFromTheValueReached) {
    LogKnobDrag drag;
    drag.begin(25.0, 100.0, false);
    const double fine = drag.update(neighbours, 129.0, false);
    EXPECT_EQ(fine, dragged_value(neighbours, 25.0, 29.0, false));
    EXPECT_EQ(drag.update(neighbours, 129.0, true), fine);  // Shift pressed: no jump
    const double coarse = drag.update(neighbours, 139.0, true);
    EXPECT_EQ(coarse, dragged_value(neighbours, fine, 10.0, true));
    EXPECT_EQ(drag.update(neighbours, 139.0, false), coarse);  // Shift released: no jump
    EXPECT_EQ(drag.update(neighbours, 129.0, false), dragged_value(neighbours, coarse, -10.0, false));
}

}  // namespace
}  // namespace caustica::ui
