// round_half_away (core/util/rounding.h) gives std::llround's integer wherever the accumulator
// uses it (|x| < 2^52): ties, the doubles next to them, negative values and the range's ends.
#include "core/util/rounding.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using caustica::round_half_away;

TEST(RoundHalfAway, AgreesWithLlroundAtTiesAndBesideThem) {
    for (double base : {0.0, 1.0, 2.0, 3.0, 1e6, 4294967295.0, 4503599627370494.0}) {
        for (double x : {base + 0.5, base - 0.5, base + 0.25, base + 0.75}) {
            for (double y : {x, std::nextafter(x, -1e300), std::nextafter(x, 1e300)}) {
                EXPECT_EQ(round_half_away(y), std::llround(y)) << y;
                EXPECT_EQ(round_half_away(-y), std::llround(-y)) << -y;
            }
        }
    }
    // The largest double below 1/2: x + 0.5 rounds up to 1 in double, a classic mistake.
    EXPECT_EQ(round_half_away(0.49999999999999994), 0);
    EXPECT_EQ(round_half_away(-0.49999999999999994), 0);
    EXPECT_EQ(round_half_away(2.5), 3);
    EXPECT_EQ(round_half_away(-2.5), -3);
}

TEST(RoundHalfAway, AgreesWithLlroundOnRandomValuesOfEveryScale) {
    std::mt19937_64 random(7);
    std::uniform_real_distribution<double> mantissa(-1.0, 1.0);
    std::uniform_int_distribution<int> exponent(-30, 51);
    for (int i = 0; i < 200000; ++i) {
        const double x = std::ldexp(mantissa(random), exponent(random));
        ASSERT_EQ(round_half_away(x), std::llround(x)) << x;
    }
}
