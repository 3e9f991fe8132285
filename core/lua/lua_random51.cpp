// Lua 5.1's math.random over our own copy of glibc's rand() (lua_random51.h).
#include "core/lua/lua_random51.h"

#include <lua.hpp>

#include <cmath>
#include <new>
#include <type_traits>

namespace caustica::scene_lua {

void GlibcRandom::seed_with(std::uint32_t seed) {
    if (seed == 0) seed = 1;
    // glibc runs the recurrence on a 32-bit signed word: a seed above 2^31 - 1 starts it negative.
    std::int64_t word = static_cast<std::int32_t>(seed);
    state_[0] = seed;
    for (int i = 1; i < degree; ++i) {
        // 16807 * word mod (2^31 - 1) without overflow (Schrage): 2^31 - 1 = 16807 * 127773 + 2836.
        const std::int64_t high = word / 127773, low = word % 127773;
        word = 16807 * low - 2836 * high;
        if (word < 0) word += 2147483647;
        state_[i] = static_cast<std::uint32_t>(word);
    }
    front_ = separation;
    rear_ = 0;
    for (int i = 0; i < 10 * degree; ++i) next();
}

std::int32_t GlibcRandom::next() {
    state_[front_] += state_[rear_];
    const auto result = static_cast<std::int32_t>(state_[front_] >> 1);
    front_ = front_ + 1 == degree ? 0 : front_ + 1;
    rear_ = rear_ + 1 == degree ? 0 : rear_ + 1;
    return result;
}

namespace {

/// An integer argument as Lua 5.1's luaL_checkint read it: any number (or numeric string),
/// truncated towards zero, then taken as a 32-bit C int (wrapping, as the conversion did on the
/// 64-bit platforms the seed ran on).
std::int32_t int_arg_51(lua_State* L, int index) {
    const lua_Number value = luaL_checknumber(L, index);
    if (!(std::fabs(value) < 9.2e18)) luaL_argerror(L, index, "number out of range");
    return static_cast<std::int32_t>(static_cast<std::uint32_t>(static_cast<std::int64_t>(value)));
}

GlibcRandom& generator(lua_State* L) {
    return *static_cast<GlibcRandom*>(lua_touserdata(L, lua_upvalueindex(1)));
}

/// math.random([m [, n]]): the generator advances before the arguments are checked, as in 5.1.
int random_51(lua_State* L) {
    const double r = generator(L).next_fraction();
    switch (lua_gettop(L)) {
    case 0: lua_pushnumber(L, r); return 1;
    case 1: {
        const std::int64_t upper = int_arg_51(L, 1);
        luaL_argcheck(L, 1 <= upper, 1, "interval is empty");
        lua_pushinteger(L, static_cast<lua_Integer>(std::floor(r * static_cast<double>(upper))) + 1);
        return 1;
    }
    case 2: {
        const std::int64_t lower = int_arg_51(L, 1);
        const std::int64_t upper = int_arg_51(L, 2);
        luaL_argcheck(L, lower <= upper, 2, "interval is empty");
        lua_pushinteger(L, static_cast<lua_Integer>(std::floor(r * static_cast<double>(upper - lower + 1))) + lower);
        return 1;
    }
    default: return luaL_error(L, "wrong number of arguments");
    }
}

/// math.randomseed(x): srand(x), x read as a C int and given to srand as unsigned.
int randomseed_51(lua_State* L) {
    generator(L).seed_with(static_cast<std::uint32_t>(int_arg_51(L, 1)));
    return 0;
}

}  // namespace

void open_random51(lua_State* L) {
    static_assert(std::is_trivially_destructible_v<GlibcRandom>);  // a userdata without __gc
    lua_getglobal(L, LUA_MATHLIBNAME);
    void* memory = lua_newuserdatauv(L, sizeof(GlibcRandom), 0);
    new (memory) GlibcRandom(1);
    lua_pushvalue(L, -1);
    lua_pushcclosure(L, random_51, 1);
    lua_setfield(L, -3, "random");
    lua_pushcclosure(L, randomseed_51, 1);
    lua_setfield(L, -2, "randomseed");
    lua_pop(L, 1);
}

}  // namespace caustica::scene_lua
