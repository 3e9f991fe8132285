#include "tests/time_bounds.h"

#include "core/util/sanitized.h"

#include <sched.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <thread>
#include <vector>

namespace caustica::testing {
namespace {

/// A fixed amount of integer work (a xorshift chain the compiler cannot shorten), built optimised
/// whatever the test sources' flags, with no memory access for a sanitizer to instrument.
__attribute__((noinline, optimize("O2"))) std::uint64_t calibration_work(std::uint64_t x, int steps) {
    for (int i = 0; i < steps; ++i) {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
    }
    return x;
}

}  // namespace

// The median of seven timings of calibration_work run on every CPU at once (as the renderer's
// threads run, so that other processes busy on the cores count) against the same work's time on
// the reference machine (about 15 ms), from 1 to 4 (beyond that the bounds would outlast ctest's
// own timeout).
double machine_factor() {
    static const double factor = [] {
        if (const char* given = std::getenv("CAUSTICA_TIME_FACTOR"); given && *given) {
            const double f = std::atof(given);
            if (f > 0.0) return f;
        }
        constexpr int steps = 7'000'000;
        constexpr double reference_seconds = 0.0146;
        // The processors this process may run on (its affinity), not every one the machine has.
        unsigned threads = std::max(1u, std::thread::hardware_concurrency());
        if (cpu_set_t allowed; ::sched_getaffinity(0, sizeof allowed, &allowed) == 0)
            threads = std::max(1, CPU_COUNT(&allowed));
        std::vector<double> seconds;
        std::vector<std::uint64_t> sinks(threads, 1);
        for (int i = 0; i < 7; ++i) {
            const auto t0 = std::chrono::steady_clock::now();
            std::vector<std::thread> workers;
            for (unsigned t = 0; t < threads; ++t)
                workers.emplace_back([&sinks, t] { sinks[t] = calibration_work(sinks[t] + 1, steps); });
            for (std::thread& w : workers) w.join();
            seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
        }
        static volatile std::uint64_t kept;
        for (std::uint64_t x : sinks) kept = kept + x;
        std::nth_element(seconds.begin(), seconds.begin() + 3, seconds.end());
        return std::clamp(seconds[3] / reference_seconds, 1.0, 4.0);
    }();
    return factor;
}


// AddressSanitizer + UndefinedBehaviorSanitizer runs CSG- and allocation-heavy paths 9-14 times
// slower (measured on the R1 and R3 scenes), ThreadSanitizer the session's paths 5-15 times.
double time_factor() { return (caustica::sanitized_build ? 12.0 : 1.0) * machine_factor(); }

}  // namespace caustica::testing
