// Whether this build runs under a sanitizer (AddressSanitizer, ThreadSanitizer, MemorySanitizer):
// such builds reserve far more address space than they use, so address-space limits and the
// timings of plain builds do not apply to them.
#pragma once

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define CAUSTICA_SANITIZED 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer) || __has_feature(memory_sanitizer)
#define CAUSTICA_SANITIZED 1
#endif
#endif

namespace caustica {

#ifdef CAUSTICA_SANITIZED
inline constexpr bool sanitized_build = true;
#else
inline constexpr bool sanitized_build = false;
#endif

}  // namespace caustica
