#include "tests/time_bounds.h"

#include "core/util/sanitized.h"

#include <sched.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <thread>
#include <vector>

namespace caustica::testing {
namespace {

/// A fixed amount of integer work (a xorshift chain the compiler cannot shorten), with no memory
/// access for a sanitizer to instrument. This file is built optimised whatever the test sources'
/// flags (tests/CMakeLists.txt), with GCC and clang alike.
__attribute__((noinline)) std::uint64_t calibration_work(std::uint64_t x, int steps) {
    for (int i = 0; i < steps; ++i) {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
    }
    return x;
}

/// Seconds to fault in `bytes` of fresh memory a page at a time (the kernel finds and zeroes each
/// page), 0 if it cannot be mapped.
double fault_seconds(std::size_t bytes) {
    void* mapped = ::mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (mapped == MAP_FAILED) return 0.0;
    ::madvise(mapped, bytes, MADV_NOHUGEPAGE);
    const long page = std::max(4096L, ::sysconf(_SC_PAGESIZE));
    volatile char* bytes_of = static_cast<volatile char*>(mapped);
    const auto t0 = std::chrono::steady_clock::now();
    for (std::size_t i = 0; i < bytes; i += static_cast<std::size_t>(page)) bytes_of[i] = 1;
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    ::munmap(mapped, bytes);
    return seconds;
}

}  // namespace

// The median of seven timings of calibration_work run on every CPU at once (as the renderer's
// threads run, so that other processes busy on the cores count) against the same work's time on
// the reference machine (about 15 ms), or, if that is larger, the median of three timings of
// faulting in 4 MiB of fresh memory against 2 µs a page (an assumed reference: the suite's
// memory-heavy reproducers spend much of their time in page faults, which cost 11 µs each on some
// virtual machines, where a gigabyte-sized reproducer under AddressSanitizer took 56 s against a
// bound of 36), from 1 to 4 (beyond that the bounds would outlast ctest's own timeout).
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
        constexpr std::size_t fault_bytes = std::size_t{4} << 20;
        constexpr double reference_fault_seconds = 2e-6 * static_cast<double>(fault_bytes / 4096);
        double faults[3];
        for (double& f : faults) f = fault_seconds(fault_bytes);
        std::sort(faults, faults + 3);
        const double factor = std::max(seconds[3] / reference_seconds, faults[1] / reference_fault_seconds);
        return std::clamp(factor, 1.0, 4.0);
    }();
    return factor;
}


// AddressSanitizer + UndefinedBehaviorSanitizer runs CSG- and allocation-heavy paths 9-14 times
// slower (measured on the R1 and R3 scenes), ThreadSanitizer the session's paths 5-15 times.
double time_factor() { return (caustica::sanitized_build ? 12.0 : 1.0) * machine_factor(); }

}  // namespace caustica::testing
