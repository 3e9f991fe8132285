// Counter-based random numbers: a stream per (seed, pixel, sample) so results never depend on
// which thread ran what, and any pixel can be replayed alone.
#pragma once

#include <cstdint>
#include <cstring>

namespace caustica {

/// 64-bit finaliser of SplitMix64: a strong bijective mix of one word.
inline std::uint64_t mix64(std::uint64_t x) {
    x ^= x >> 30;
    x *= 0xbf58476d1ce4e5b9ULL;
    x ^= x >> 27;
    x *= 0x94d049bb133111ebULL;
    x ^= x >> 31;
    return x;
}

/// Folds one word into a running hash (fingerprints of what cached stages depend on).
inline std::uint64_t hash_combine(std::uint64_t h, std::uint64_t v) { return mix64(h ^ (v + 0x9e3779b97f4a7c15ULL)); }

/// Folds the bits of a double into a running hash.
inline std::uint64_t hash_double(std::uint64_t h, double d) {
    std::uint64_t bits;
    std::memcpy(&bits, &d, sizeof bits);
    return hash_combine(h, bits);
}

/// A small generator seeded from a key: SplitMix64 stepping, floats from the top 24 bits.
class RandomStream {
public:
    RandomStream(std::uint64_t seed, std::uint64_t a, std::uint64_t b = 0)
        : state_(mix64(seed ^ mix64(a + 0x9e3779b97f4a7c15ULL * (b + 1)))) {}

    /// The next 64 random bits.
    std::uint64_t next() {
        state_ += 0x9e3779b97f4a7c15ULL;
        return mix64(state_);
    }

    /// Uniform in [0, 1).
    float uniform() { return static_cast<float>(next() >> 40) * (1.0f / 16777216.0f); }

private:
    std::uint64_t state_;
};

}  // namespace caustica
