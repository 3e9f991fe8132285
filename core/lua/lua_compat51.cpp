// The Lua 5.1 names the original scenes were written against (docs/SCENE_LANGUAGE.md, "Lua 5.1
// compatibility"), on top of the sandboxed 5.4 libraries: string.gfind, table.getn, unpack,
// math.mod, math.pow, loadstring and 5.1's math.random (lua_random51.h). module, package.seeall and
// require are in lua_sandbox.cpp.
// Nothing here reaches past the sandbox: loadstring compiles text only, into the same global
// table, and runs under the same instruction hook and allocator as the rest of the script.
#include "core/lua/lua_context.h"
#include "core/lua/lua_random51.h"

#include <cmath>

namespace caustica::scene_lua {
namespace {

/// math.pow(x, y) = x ^ y.
int math_pow(lua_State* L) {
    const lua_Number result = std::pow(luaL_checknumber(L, 1), luaL_checknumber(L, 2));
    // 5.1 printed a whole double without ".0": names built from pow ("tex" .. math.pow(2, 3)) stay
    // the same when integer arguments give a whole result that fits an integer.
    if (lua_isinteger(L, 1) && lua_isinteger(L, 2) && result == std::floor(result) && std::fabs(result) < 9.0e15)
        lua_pushinteger(L, static_cast<lua_Integer>(result));
    else
        lua_pushnumber(L, result);
    return 1;
}

/// math.mod(x, y): C's fmod, so the result has the sign of x (math.mod(-7, 3) == -1, where
/// -7 % 3 == 2). Two integers give an integer (printed "1" as 5.1 printed it); a zero divisor
/// gives nan, as in 5.1, instead of 5.4's error.
int math_mod(lua_State* L) {
    if (lua_isinteger(L, 1) && lua_isinteger(L, 2) && lua_tointeger(L, 2) != 0) {
        const lua_Integer x = lua_tointeger(L, 1), y = lua_tointeger(L, 2);
        lua_pushinteger(L, y == -1 ? 0 : x % y);  // C++ % truncates, as fmod does; -1 avoids overflow
        return 1;
    }
    lua_pushnumber(L, std::fmod(luaL_checknumber(L, 1), luaL_checknumber(L, 2)));
    return 1;
}

/// table.getn(t): the table's length without metamethods (5.1's lua_objlen).
int table_getn(lua_State* L) {
    luaL_checktype(L, 1, LUA_TTABLE);
    lua_pushinteger(L, static_cast<lua_Integer>(lua_rawlen(L, 1)));
    return 1;
}

/// string.gfind(s, pattern): 5.1's name for gmatch (upvalue 1, the library's own), which had no
/// third argument.
int string_gfind(lua_State* L) {
    luaL_checkstring(L, 1);
    luaL_checkstring(L, 2);
    lua_settop(L, 2);
    lua_pushvalue(L, lua_upvalueindex(1));
    lua_insert(L, 1);
    lua_call(L, 2, 1);
    return 1;
}

/// loadstring(s [, chunkname]): compiles text only (a binary chunk gets nil and the reason, as a
/// syntax error does) with the global table as its environment; the name defaults to the text.
int loadstring_51(lua_State* L) {
    std::size_t length = 0;
    const char* text = luaL_checklstring(L, 1, &length);
    const char* name = luaL_optstring(L, 2, text);
    if (luaL_loadbufferx(L, text, length, name, "t") == LUA_OK) return 1;
    luaL_pushfail(L);
    lua_insert(L, -2);
    return 2;
}

void set_function(lua_State* L, const char* table, const char* field, lua_CFunction function) {
    lua_getglobal(L, table);
    lua_pushcfunction(L, function);
    lua_setfield(L, -2, field);
    lua_pop(L, 1);
}

}  // namespace

void open_lua51_compat(lua_State* L) {
    lua_getglobal(L, LUA_TABLIBNAME);
    lua_getfield(L, -1, "unpack");
    lua_setglobal(L, "unpack");
    lua_pop(L, 1);
    set_function(L, LUA_TABLIBNAME, "getn", table_getn);
    set_function(L, LUA_MATHLIBNAME, "pow", math_pow);
    set_function(L, LUA_MATHLIBNAME, "mod", math_mod);
    lua_getglobal(L, LUA_STRLIBNAME);
    lua_getfield(L, -1, "gmatch");
    lua_pushcclosure(L, string_gfind, 1);
    lua_setfield(L, -2, "gfind");
    lua_pop(L, 1);
    lua_register(L, "loadstring", loadstring_51);
    open_random51(L);
}

}  // namespace caustica::scene_lua
