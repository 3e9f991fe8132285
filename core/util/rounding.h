// Rounding to integers without a library call, for loops that round several values per sample.
#pragma once

#include <cmath>
#include <cstdint>

namespace caustica {

/// std::llround(x) for |x| < 2^52, halves away from zero, the same integer for every such x.
/// The truncation of |x| is its floor, and |x| minus it is exact below 2^52, so the comparison
/// with 1/2 decides the way a library call would.
inline std::int64_t round_half_away(double x) {
    const double a = std::fabs(x);
    const auto whole = static_cast<std::int64_t>(a);
    const std::int64_t r = whole + (a - static_cast<double>(whole) >= 0.5 ? 1 : 0);
    return x < 0.0 ? -r : r;
}

}  // namespace caustica
