// What a scene script says: print, io.write and write on io.stdout and io.stderr (to the
// terminal) and warn (to SceneScript::warnings) go through the run's output budget
// (LoaderContext::output), so that each call reaches the user bounded and with its control
// characters made visible, and all of them together stay within script_output_limit
// (docs/RELIABILITY.md, "Script text reaches the user bounded and visible"). Each C function first
// turns its arguments into strings (which may raise, as the library's own functions do); the C++
// that bounds and writes runs after, in a noexcept helper.
#include "core/lua/lua_context.h"

#include <algorithm>
#include <cstdio>

namespace caustica::scene_lua {
namespace {

/// Writes the strings at stack indices `first` to the top as one piece: joined by `separator`,
/// at most script_text_limit bytes kept, then printable and within the budget, followed by
/// `ending`. Nothing at all is written once the budget is spent. Never throws.
void write_piece(lua_State* L, LoaderContext& ctx, int first, const char* separator, const char* ending,
                 std::FILE* stream) noexcept {
    try {
        std::string text;
        std::size_t left_out = 0;
        const auto add = [&](std::string_view part) {
            const std::size_t kept = std::min(part.size(), script_text_limit - text.size());
            text.append(part.substr(0, kept));
            left_out += part.size() - kept;
        };
        const int top = lua_gettop(L);
        for (int i = first; i <= top; ++i) {
            if (i > first) add(separator);
            std::size_t size = 0;
            if (const char* value = lua_tolstring(L, i, &size)) add({value, size});  // strings: no conversion
        }
        if (text.empty() && left_out == 0 && *ending == '\0') return;
        const std::optional<std::string> shown = ctx.output.admit(text, left_out);
        if (!shown) return;
        std::fwrite(shown->data(), 1, shown->size(), stream);
        std::fputs(ending, stream);
    } catch (...) {
    }
}

/// Turns the arguments from `first` on into the strings io.write writes: numbers as the library
/// formats them (LUA_INTEGER_FMT, LUA_NUMBER_FMT), strings as they are; anything else raises
/// "bad argument #n to 'write' (string expected, got ...)" as the library does.
void to_written_strings(lua_State* L, int first) {
    for (int i = first, top = lua_gettop(L); i <= top; ++i) {
        if (lua_type(L, i) != LUA_TNUMBER) {
            luaL_checklstring(L, i, nullptr);
            continue;
        }
        char text[64];
        const int length =
            lua_isinteger(L, i)
                ? std::snprintf(text, sizeof text, LUA_INTEGER_FMT, static_cast<LUAI_UACINT>(lua_tointeger(L, i)))
                : std::snprintf(text, sizeof text, LUA_NUMBER_FMT, static_cast<LUAI_UACNUMBER>(lua_tonumber(L, i)));
        lua_pushlstring(L, text, static_cast<std::size_t>(std::clamp(length, 0, static_cast<int>(sizeof text) - 1)));
        lua_replace(L, i);
    }
}

/// print(...): each argument through tostring, separated by tabs, one line.
int bounded_print(lua_State* L) {
    for (int i = 1, count = lua_gettop(L); i <= count; ++i) {
        luaL_tolstring(L, i, nullptr);
        lua_replace(L, i);
    }
    write_piece(L, context(L), 1, "\t", "\n", stdout);
    return 0;
}

/// io.write(...): to standard output (scripts cannot change io.output); returns io.stdout
/// (upvalue 1).
int bounded_io_write(lua_State* L) {
    to_written_strings(L, 1);
    write_piece(L, context(L), 1, "", "", stdout);
    lua_pushvalue(L, lua_upvalueindex(1));
    return 1;
}

/// file:write(...): on io.stdout and io.stderr (upvalues 2 and 3) as io.write; on any other file
/// the library's method (upvalue 1), which refuses: scripts open files for reading only.
int bounded_file_write(lua_State* L) {
    std::FILE* stream = lua_rawequal(L, 1, lua_upvalueindex(2))   ? stdout
                        : lua_rawequal(L, 1, lua_upvalueindex(3)) ? stderr
                                                                  : nullptr;
    if (!stream) {
        lua_pushvalue(L, lua_upvalueindex(1));
        lua_insert(L, 1);
        lua_call(L, lua_gettop(L) - 1, LUA_MULTRET);
        return lua_gettop(L);
    }
    to_written_strings(L, 2);
    write_piece(L, context(L), 2, "", "", stream);
    lua_settop(L, 1);
    return 1;
}

/// Hands the strings at stack indices 1 to `count` to collect_warning_piece as one warning.
void add_warning(lua_State* L, LoaderContext& ctx, int count) noexcept {
    for (int i = 1; i <= count; ++i) {
        std::size_t size = 0;
        const char* piece = lua_tolstring(L, i, &size);  // strings by now: no conversion
        collect_warning_piece(ctx, std::string_view(piece ? piece : "", piece ? size : 0), i < count);
    }
}

/// warn(msg1, ...): as Lua's warn (strings or numbers, at least one), but each piece is read with
/// its length, so that a huge piece costs no more than the part of it that is kept.
int bounded_warn(lua_State* L) {
    const int count = lua_gettop(L);
    luaL_checkstring(L, 1);
    for (int i = 2; i <= count; ++i) luaL_checkstring(L, i);
    add_warning(L, context(L), count);
    return 0;
}

}  // namespace

void bound_script_output(lua_State* L) {
    lua_pushcfunction(L, bounded_print);
    lua_setglobal(L, "print");
    lua_pushcfunction(L, bounded_warn);
    lua_setglobal(L, "warn");
    lua_getglobal(L, LUA_IOLIBNAME);           // io
    lua_getfield(L, -1, "stdout");             // io, stdout
    lua_pushcclosure(L, bounded_io_write, 1);  // io, write
    lua_setfield(L, -2, "write");              // io
    luaL_getmetatable(L, LUA_FILEHANDLE);      // io, metatable
    lua_getfield(L, -1, "__index");            // io, metatable, methods
    lua_getfield(L, -1, "write");              // io, metatable, methods, the library's write
    lua_getfield(L, -4, "stdout");
    lua_getfield(L, -5, "stderr");
    lua_pushcclosure(L, bounded_file_write, 3);  // io, metatable, methods, write
    lua_setfield(L, -2, "write");
    lua_pop(L, 3);
}

}  // namespace caustica::scene_lua
