// The renderer's parallel loops: oneTBB's, except under ThreadSanitizer. Debian's libtbb is not
// instrumented, so ThreadSanitizer cannot see how its workers hand work to each other and would
// take every loop for a race; under it these run the same chunks on std::threads, whose start
// and join it sees, so that the renderer's own parallel code (photon tracing, the photon grid,
// projection maps, the k-d tree build, tiles) is checked for races like the rest
// (docs/RELIABILITY.md, "Sanitizers"). The results are the same: every caller's outcome is
// independent of how the range is split and in which order the chunks run.
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/parallel_reduce.h>

#if defined(__SANITIZE_THREAD__)
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>
#endif

namespace caustica {

#if defined(__SANITIZE_THREAD__)

/// body(sub-range) over chunks of range.grainsize(), on as many threads as the arena allows.
template <class Index, class Body>
void parallel_for(const tbb::blocked_range<Index>& range, const Body& body) {
    const Index begin = range.begin(), end = range.end();
    if (!(begin < end)) return;
    const auto grain = static_cast<long long>(std::max<std::size_t>(1, range.grainsize()));
    const long long chunks = (static_cast<long long>(end - begin) + grain - 1) / grain;
    const long long workers = std::min<long long>(chunks, std::max(1, tbb::this_task_arena::max_concurrency()));
    std::atomic<long long> next{0};
    std::exception_ptr failure;
    std::mutex failure_mutex;
    auto work = [&] {
        for (long long k; (k = next.fetch_add(1)) < chunks;) {
            const Index lo = static_cast<Index>(begin + static_cast<Index>(k * grain));
            const Index hi = static_cast<Index>(std::min<long long>(static_cast<long long>(end - begin), (k + 1) * grain) + begin);
            try {
                body(tbb::blocked_range<Index>(lo, hi, range.grainsize()));
            } catch (...) {
                const std::lock_guard<std::mutex> lock(failure_mutex);
                if (!failure) failure = std::current_exception();
                next = chunks;
            }
        }
    };
    std::vector<std::thread> threads;
    for (long long t = 1; t < workers; ++t) threads.emplace_back(work);
    work();
    for (std::thread& t : threads) t.join();
    if (failure) std::rethrow_exception(failure);
}

/// The whole range in one call, from `identity` (reductions are cheap here; what matters to the
/// sanitizer is the code that runs in parallel_for).
template <class Index, class Value, class Body, class Reduce>
Value parallel_reduce(const tbb::blocked_range<Index>& range, const Value& identity, const Body& body, const Reduce&) {
    return body(range, identity);
}

/// f on a new thread, g on this one.
template <class F, class G>
void parallel_invoke(const F& f, const G& g) {
    std::exception_ptr failure;
    std::thread other([&] {
        try {
            f();
        } catch (...) {
            failure = std::current_exception();
        }
    });
    try {
        g();
    } catch (...) {
        other.join();
        throw;
    }
    other.join();
    if (failure) std::rethrow_exception(failure);
}

#else

using tbb::parallel_for;
using tbb::parallel_invoke;
using tbb::parallel_reduce;

#endif

}  // namespace caustica
