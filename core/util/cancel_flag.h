// The cancel flag a render's long loops and ray queries read (docs/RELIABILITY.md, "Bounded time").
#pragma once

#include <atomic>

namespace caustica {

/// Whether `cancel` (null: no flag) asks the work in progress to stop. A relaxed load is enough:
/// during a render the flag only goes from false to true, so once a load on a thread reads true,
/// every later load on that thread does too, and the caller that checks after the work sees what
/// the work saw (and throws its result away).
inline bool is_cancelled(const std::atomic<bool>* cancel) {
    return cancel && cancel->load(std::memory_order_relaxed);
}

/// Loops whose steps are cheap but whose count has no bound (the photons of one emission cell)
/// read the flag once every this many steps.
inline constexpr long long steps_between_cancel_checks = 1024;

}  // namespace caustica
