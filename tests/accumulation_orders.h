// The same progressive samples accumulated in three orders, for the tests of the integer sums'
// exactness (what lets ranks add their sums and get one process's bits).
#pragma once

#include "core/integrators/progressive_accumulator.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace caustica::testing {

struct AccumulationOrders {
    ProgressiveAccumulator forward;   ///< passes 0, 1, ... in turn
    ProgressiveAccumulator backward;  ///< the last pass first
    std::vector<std::int64_t> merged;  ///< even and odd passes in two accumulators, their sums added
};

/// sample(pixel, pass) for `passes` passes over a row of `width` pixels, added in the three orders.
template <class Sample>
AccumulationOrders accumulate_in_three_orders(int width, int passes, const Sample& sample) {
    AccumulationOrders o;
    ProgressiveAccumulator even, odd;
    for (ProgressiveAccumulator* a : {&o.forward, &o.backward, &even, &odd}) a->reset(width, 1);
    for (int p = 0; p < passes; ++p)
        for (int i = 0; i < width; ++i) {
            o.forward.add(static_cast<std::size_t>(i), sample(i, p));
            o.backward.add(static_cast<std::size_t>(i), sample(i, passes - 1 - p));
            (p % 2 ? odd : even).add(static_cast<std::size_t>(i), sample(i, p));
        }
    o.merged = even.sums();
    for (std::size_t k = 0; k < o.merged.size(); ++k) o.merged[k] += odd.sums()[k];
    return o;
}

}  // namespace caustica::testing
