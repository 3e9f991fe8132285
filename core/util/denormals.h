// Flush-to-zero and denormals-are-zero for the code that traces rays, as Embree asks.
#pragma once

#include <pmmintrin.h>
#include <xmmintrin.h>

namespace caustica {

/// Sets FTZ and DAZ on the current thread for its lifetime, then restores the previous modes.
/// Put one at the top of every parallel task body that traces rays: the task runs on whatever
/// worker TBB picks, and setting the mode per task needs no task_scheduler_observer (whose proxy
/// oneTBB 2021 leaks when a worker still holds it as the observer goes away).
class ScopedFlushDenormals {
public:
    ScopedFlushDenormals() : saved_(_mm_getcsr()) { _mm_setcsr(saved_ | flags); }
    ~ScopedFlushDenormals() { _mm_setcsr(saved_); }
    ScopedFlushDenormals(const ScopedFlushDenormals&) = delete;
    ScopedFlushDenormals& operator=(const ScopedFlushDenormals&) = delete;

private:
    static constexpr unsigned flags = _MM_FLUSH_ZERO_ON | _MM_DENORMALS_ZERO_ON;
    unsigned saved_;
};

}  // namespace caustica
