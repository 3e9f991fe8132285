// math.random and math.randomseed as Lua 5.1 had them on glibc: the C library's rand() (glibc's
// default TYPE_3 additive feedback generator), implemented here so that a scene's random layout
// is the same on every platform and does not depend on the host's C library.
#pragma once

#include <cstdint>

struct lua_State;

namespace caustica::scene_lua {

/// glibc's random()/rand() with its default state of 31 words (TYPE_3): the state is filled from
/// the seed by the 16807 multiplicative generator modulo 2^31 - 1 (Schrage's method, as glibc
/// computes it), then r[i] = r[i-3] + r[i-31] (mod 2^32) and each output is r >> 1; the first 310
/// outputs after seeding are discarded. Seed 0 acts as seed 1, as in glibc.
class GlibcRandom {
public:
    static constexpr std::int32_t rand_max = 2147483647;  ///< RAND_MAX on glibc

    explicit GlibcRandom(std::uint32_t seed = 1) { seed_with(seed); }

    /// srand(seed).
    void seed_with(std::uint32_t seed);
    /// rand(): the next value in [0, rand_max].
    std::int32_t next();
    /// Lua 5.1's r = (rand() % RAND_MAX) / RAND_MAX, in [0, 1).
    double next_fraction() { return static_cast<double>(next() % rand_max) / rand_max; }

private:
    static constexpr int degree = 31;     ///< words of state
    static constexpr int separation = 3;  ///< distance between the two taps
    std::uint32_t state_[degree] = {};
    int front_ = separation;              ///< the word replaced next (glibc's fptr)
    int rear_ = 0;                        ///< the word added to it (glibc's rptr)
};

/// Replaces math.random and math.randomseed (the math table must be a global) with the Lua 5.1
/// functions over one GlibcRandom per Lua state, seeded with 1: random() = r,
/// random(m) = floor(r*m) + 1, random(l, u) = floor(r*(u-l+1)) + l, randomseed(x) = srand(x).
/// Integer arguments are read as 5.1 read them (truncated towards zero to a C int); an empty
/// interval is "bad argument ... (interval is empty)" at the caller's line.
void open_random51(lua_State* L);

}  // namespace caustica::scene_lua
