// The sandboxed Lua environment a scene script runs in (SCENE_API.md, "Scripts run sandboxed"):
// base (without dofile, loadfile, and __gc in setmetatable), table, string, math and utf8; io restricted to reading files under the scene's folder;
// os.clock/time/date/getenv; debug.getinfo/traceback; text-only load; and the Lua 5.1 module
// system the original's scenes use (module, package.seeall, require of sibling and include/ files).
// The other Lua 5.1 names (loadstring, unpack, math.random as 5.1 had it, ...) are in
// lua_compat51.cpp.
//
// The C functions here are written in C style (no C++ object alive across a Lua call that may
// raise); the little C++ they need runs in noexcept helpers that leave their answer in the context.
#include "core/lua/lua_context.h"
#include "core/lua/scene_files.h"

#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <initializer_list>

namespace caustica::scene_lua {
namespace {

namespace fs = std::filesystem;

/// Value stored in package.loaded while a module is running (detects require loops).
char loading_sentinel;

/// Opens a file the script wants to read (scene_files.h rules); the descriptor goes to
/// ctx.opened_fd, the reason for a refusal to ctx.pending_error. Never throws.
bool open_for_reading(LoaderContext& ctx, const char* path) noexcept {
    try {
        SceneFile file = open_scene_file(ctx, path);
        ctx.opened_fd = file.fd.release();
        ctx.resolved_path = "/proc/self/fd/" + std::to_string(ctx.opened_fd);
        return true;
    } catch (const std::exception& e) {
        try {
            ctx.pending_error = e.what();
        } catch (...) {
            ctx.pending_error = "out of memory";
        }
    } catch (...) {
        ctx.pending_error = "out of memory";
    }
    return false;
}

/// Closes ctx.opened_fd once the real io function has opened its own handle on the file.
void close_opened(LoaderContext& ctx) noexcept {
    if (ctx.opened_fd >= 0) ::close(ctx.opened_fd);
    ctx.opened_fd = -1;
}

/// Calls the real io function (upvalue 1) on the opened file with the arguments from stack index
/// 2 on; the results replace the stack. Errors are raised after the descriptor is closed.
int call_real_io(lua_State* L) {
    LoaderContext& ctx = context(L);
    lua_pushstring(L, ctx.resolved_path.c_str());
    lua_replace(L, 1);
    lua_pushvalue(L, lua_upvalueindex(1));
    lua_insert(L, 1);
    const int status = lua_pcall(L, lua_gettop(L) - 1, LUA_MULTRET, 0);
    close_opened(ctx);
    if (status != LUA_OK) return lua_error(L);
    return lua_gettop(L);
}

/// Finds `name`.lua beside the main script or in include/ beside it (dots become folders).
bool find_module_file(LoaderContext& ctx, const char* name) noexcept {
    try {
        std::string relative;
        bool valid = *name && *name != '.';
        char previous = 0;
        for (const char* c = name; *c && valid; previous = *c++) {
            if (*c == '.') {
                valid = previous != '.';
                relative += '/';
            } else {
                valid = std::isalnum(static_cast<unsigned char>(*c)) || *c == '_' || *c == '-';
                relative += *c;
            }
        }
        if (!valid || previous == '.') {
            ctx.pending_error = "invalid module name '" + std::string(name) + "' (letters, digits, '_', '-' and '.')";
            return false;
        }
        relative += ".lua";
        const fs::path candidates[] = {relative, fs::path("include") / relative};
        for (const fs::path& candidate : candidates) {
            std::error_code error;
            if (!fs::exists(fs::symlink_status(ctx.scene_dir / candidate, error))) continue;
            const SceneFile file = open_scene_file(ctx, candidate.string());
            ctx.result_text = read_scene_file(ctx, file, "the module");
            ctx.resolved_path = (ctx.script_dir_as_given / candidate).string();
            return true;
        }
        ctx.pending_error = "module '" + std::string(name) + "' not found (looked for " +
                            (ctx.script_dir_as_given / candidates[0]).string() + " and " +
                            (ctx.script_dir_as_given / candidates[1]).string() + ")";
    } catch (const std::exception& e) {
        try {
            ctx.pending_error = e.what();
        } catch (...) {
            ctx.pending_error = "out of memory";
        }
    } catch (...) {
        ctx.pending_error = "out of memory";
    }
    return false;
}

/// The stem of the file the calling chunk came from ("scene" for "@dir/scene.lua").
bool caller_stem(lua_State* L, LoaderContext& ctx) noexcept {
    try {
        SourceLocation where = caller_location(L);
        if (where.file.empty()) return false;
        ctx.result_text = fs::path(where.file).stem().string();
        return !ctx.result_text.empty();
    } catch (...) {
        return false;
    }
}

// ---- io ----

int sandbox_io_open(lua_State* L) {
    const char* path = luaL_checkstring(L, 1);
    const char* mode = luaL_optstring(L, 2, "r");
    if (std::strpbrk(mode, "wa+")) return luaL_error(L, "io.open: scripts cannot write files (mode '%s')", mode);
    LoaderContext& ctx = context(L);
    if (!open_for_reading(ctx, path)) {
        luaL_pushfail(L);
        lua_pushstring(L, ctx.pending_error.c_str());
        lua_pushinteger(L, EACCES);
        return 3;
    }
    lua_settop(L, 2);
    return call_real_io(L);
}

int sandbox_io_lines(lua_State* L) {
    if (lua_isnoneornil(L, 1))
        return luaL_error(L, "io.lines: a file name is required (scripts cannot read standard input)");
    const char* path = luaL_checkstring(L, 1);
    LoaderContext& ctx = context(L);
    if (!open_for_reading(ctx, path)) return luaL_error(L, "io.lines: %s", ctx.pending_error.c_str());
    return call_real_io(L);
}

/// io keeps open/lines (wrapped), close, type, write (to standard output, bounded by
/// bound_script_output), stdout and stderr.
void restrict_io(lua_State* L) {
    luaL_requiref(L, LUA_IOLIBNAME, luaopen_io, 1);
    lua_getfield(L, -1, "open");
    lua_pushcclosure(L, sandbox_io_open, 1);
    lua_setfield(L, -2, "open");
    lua_getfield(L, -1, "lines");
    lua_pushcclosure(L, sandbox_io_lines, 1);
    lua_setfield(L, -2, "lines");
    for (const char* removed : {"popen", "input", "output", "read", "tmpfile", "stdin"}) {
        lua_pushnil(L);
        lua_setfield(L, -2, removed);
    }
    lua_pop(L, 1);
}

/// Replaces a library by a table holding only the listed functions of the full one.
void keep_only(lua_State* L, const char* name, lua_CFunction open, std::initializer_list<const char*> kept) {
    luaL_requiref(L, name, open, 0);
    lua_createtable(L, 0, static_cast<int>(kept.size()));
    for (const char* field : kept) {
        lua_getfield(L, -2, field);
        lua_setfield(L, -2, field);
    }
    luaL_getsubtable(L, LUA_REGISTRYINDEX, LUA_LOADED_TABLE);
    lua_pushvalue(L, -2);
    lua_setfield(L, -2, name);
    lua_pop(L, 1);
    lua_setglobal(L, name);
    lua_pop(L, 1);
}

// ---- load ----

/// load(chunk [, name [, mode [, env]]]) with the mode forced to text: binary chunks are refused.
int load_text_only(lua_State* L) {
    if (lua_gettop(L) < 3) lua_settop(L, 3);
    lua_pushliteral(L, "t");
    lua_replace(L, 3);
    lua_pushvalue(L, lua_upvalueindex(1));  // the real load
    lua_insert(L, 1);
    lua_call(L, lua_gettop(L) - 1, LUA_MULTRET);
    return lua_gettop(L);
}

/// setmetatable without finalizers: Lua runs __gc with hooks off, where the time limit and the
/// cancel flag could not stop it, so a metatable with __gc is refused.
int setmetatable_without_gc(lua_State* L) {
    if (lua_type(L, 2) == LUA_TTABLE) {
        lua_pushliteral(L, "__gc");
        if (lua_rawget(L, 2) != LUA_TNIL)
            return luaL_error(L, "setmetatable: __gc finalizers are not allowed in scene scripts");
        lua_pop(L, 1);
    }
    lua_pushvalue(L, lua_upvalueindex(1));  // the real setmetatable
    lua_insert(L, 1);
    lua_call(L, lua_gettop(L) - 1, LUA_MULTRET);
    return lua_gettop(L);
}

// ---- what the count hook cannot see ----

/// debug.getinfo without the 'f' option: a script must never get hold of a function object from
/// the call stack (the real `load` is on it while a reader function runs, and it accepts binary
/// chunks). Without an option string it answers "lnSrtu", the default less 'f'.
int getinfo_without_functions(lua_State* L) {
    if (lua_type(L, 1) == LUA_TTHREAD) return luaL_error(L, "debug.getinfo: threads are not available in scene scripts");
    lua_settop(L, 2);
    if (lua_isnil(L, 2)) {
        lua_pushliteral(L, "lnSrtu");
    } else {
        const char* requested = luaL_checkstring(L, 2);
        luaL_Buffer options;
        luaL_buffinit(L, &options);
        for (const char* c = requested; *c; ++c)
            if (*c != 'f' && *c != '>') luaL_addchar(&options, *c);
        luaL_pushresult(&options);
    }
    lua_replace(L, 2);
    if (lua_isinteger(L, 1)) {  // levels as the script counts them: this wrapper is not one
        const lua_Integer level = lua_tointeger(L, 1);
        if (level >= 0 && level < LUA_MAXINTEGER) lua_pushinteger(L, level + 1);
        else lua_pushvalue(L, 1);
        lua_replace(L, 1);
    }
    lua_pushvalue(L, lua_upvalueindex(1));  // the real debug.getinfo
    lua_insert(L, 1);
    lua_call(L, 2, 1);
    return 1;
}

/// Raises the stop message when the time limit, the cancel flag or the watchdog says so.
void stop_if_limits_reached(lua_State* L) {
    LoaderContext& ctx = context(L);
    if (ctx.stop_message.empty()) note_location(L, ctx);
    if (!limits_reached(ctx)) return;
    lua_pushstring(L, ctx.stop_message.c_str());
    lua_error(L);
}

/// Comparator for table.sort: the script's (upvalue 1) or `<`, with the limits checked every few
/// thousand comparisons (a sort of numbers never runs an instruction the hook could count).
int bounded_less(lua_State* L) {
    LoaderContext& ctx = context(L);
    if ((++ctx.library_steps & 0xfff) == 0) stop_if_limits_reached(L);
    if (lua_isnil(L, lua_upvalueindex(1))) {
        lua_pushboolean(L, lua_compare(L, 1, 2, LUA_OPLT));
        return 1;
    }
    lua_pushvalue(L, lua_upvalueindex(1));
    lua_insert(L, 1);
    lua_call(L, 2, 1);
    return 1;
}

/// table.sort(t [, comp]) through bounded_less.
int bounded_sort(lua_State* L) {
    note_location(L, context(L));
    luaL_checktype(L, 1, LUA_TTABLE);
    if (!lua_isnoneornil(L, 2)) luaL_checktype(L, 2, LUA_TFUNCTION);
    lua_settop(L, 2);
    lua_pushcclosure(L, bounded_less, 1);
    lua_pushvalue(L, lua_upvalueindex(1));  // the real table.sort
    lua_insert(L, 1);
    lua_call(L, 2, 0);
    return 0;
}

/// table.move(a1, f, e, t [, a2]) with the limits checked as it goes (the library's loop runs in
/// C: table.move({}, 1, 1e15, 2) would never end).
int bounded_move(lua_State* L) {
    luaL_checktype(L, 1, LUA_TTABLE);
    const lua_Integer first = luaL_checkinteger(L, 2);
    const lua_Integer last = luaL_checkinteger(L, 3);
    const lua_Integer target = luaL_checkinteger(L, 4);
    const int destination = lua_isnoneornil(L, 5) ? 1 : 5;
    luaL_checktype(L, destination, LUA_TTABLE);
    if (last >= first) {
        luaL_argcheck(L, first > 0 || last < LUA_MAXINTEGER + first, 3, "too many elements to move");
        const lua_Integer count = last - first;
        luaL_argcheck(L, target <= LUA_MAXINTEGER - count, 4, "destination wrap around");
        LoaderContext& ctx = context(L);
        const bool backwards = target > first && target <= last && lua_compare(L, 1, destination, LUA_OPEQ);
        for (lua_Integer i = 0; i <= count; ++i) {
            if ((++ctx.library_steps & 0xfff) == 0) stop_if_limits_reached(L);
            const lua_Integer k = backwards ? count - i : i;
            lua_geti(L, 1, first + k);
            lua_seti(L, destination, target + k);
        }
    }
    lua_pushvalue(L, destination);
    return 1;
}

/// Library functions that may run long inside one C call (string patterns, string.rep,
/// table.concat) go through this: it records the caller's line first, so that should the loader
/// process have to be stopped from outside, the message names the line that was running.
int noting_location(lua_State* L) {
    note_location(L, context(L));
    lua_pushvalue(L, lua_upvalueindex(1));
    lua_insert(L, 1);
    if (lua_pcall(L, lua_gettop(L) - 1, LUA_MULTRET, 0) != LUA_OK) {
        // Called from here, the library function cannot find its own name: "bad argument #1 to
        // '?'" gets it back from upvalue 2.
        if (const char* message = lua_tostring(L, -1); message && lua_type(L, -1) == LUA_TSTRING) {
            if (const char* unnamed = std::strstr(message, "to '?'")) {
                lua_pushlstring(L, message, static_cast<std::size_t>(unnamed - message));
                lua_pushfstring(L, "to '%s'%s", lua_tostring(L, lua_upvalueindex(2)), unnamed + 6);
                lua_concat(L, 2);
            }
        }
        return lua_error(L);
    }
    return lua_gettop(L);
}

void wrap_field(lua_State* L, const char* table, const char* field, lua_CFunction wrapper) {
    lua_getglobal(L, table);
    lua_getfield(L, -1, field);
    lua_pushstring(L, field);
    lua_pushcclosure(L, wrapper, 2);
    lua_setfield(L, -2, field);
    lua_pop(L, 1);
}

/// Gives a shared metatable a __metatable field: getmetatable then answers a string, so a script
/// cannot add __gc (finalizers run with hooks off) or change how other values behave.
void lock_metatable(lua_State* L) {
    lua_pushliteral(L, "locked");
    lua_setfield(L, -2, "__metatable");
}

void lock_shared_metatables(lua_State* L) {
    luaL_getmetatable(L, LUA_FILEHANDLE);
    lock_metatable(L);
    lua_pop(L, 1);
    lua_pushliteral(L, "");
    lua_getmetatable(L, -1);
    lock_metatable(L);
    lua_pop(L, 2);
}

void bound_library_calls(lua_State* L) {
    wrap_field(L, LUA_TABLIBNAME, "sort", bounded_sort);
    lua_getglobal(L, LUA_TABLIBNAME);
    lua_pushcfunction(L, bounded_move);
    lua_setfield(L, -2, "move");
    lua_pop(L, 1);
    for (const char* field : {"find", "match", "gmatch", "gfind", "gsub", "rep"}) wrap_field(L, LUA_STRLIBNAME, field, noting_location);
    wrap_field(L, LUA_TABLIBNAME, "concat", noting_location);
    lua_getglobal(L, LUA_DBLIBNAME);
    lua_getfield(L, -1, "getinfo");
    lua_pushcclosure(L, getinfo_without_functions, 1);
    lua_setfield(L, -2, "getinfo");
    lua_pop(L, 1);
    lock_shared_metatables(L);
}

// ---- the Lua 5.1 module system ----

/// package.seeall(module): globals stay visible inside the module.
int package_seeall(lua_State* L) {
    luaL_checktype(L, 1, LUA_TTABLE);
    if (!lua_getmetatable(L, 1)) {
        lua_createtable(L, 0, 1);
        lua_pushvalue(L, -1);
        lua_setmetatable(L, 1);
    }
    lua_pushglobaltable(L);
    lua_setfield(L, -2, "__index");
    return 0;
}

/// Pushes the global table at dotted `name` ("a.b" is _G.a.b), creating missing levels.
void push_global_path(lua_State* L, const char* name) {
    lua_pushglobaltable(L);
    const char* end = nullptr;
    for (const char* part = name;; part = end + 1) {
        end = std::strchr(part, '.');
        if (!end) end = part + std::strlen(part);
        lua_pushlstring(L, part, end - part);
        if (lua_rawget(L, -2) == LUA_TNIL) {
            lua_pop(L, 1);
            lua_newtable(L);
            lua_pushlstring(L, part, end - part);
            lua_pushvalue(L, -2);
            lua_rawset(L, -4);
        } else if (!lua_istable(L, -1)) {
            luaL_error(L, "module: name conflict for module '%s'", name);
        }
        lua_remove(L, -2);
        if (*end != '.') break;
    }
}

/// module(name [, option...]): the Lua 5.1 function. Makes (or reuses) the module table, records
/// it in package.loaded, applies the options (package.seeall) and makes it the environment of the
/// calling chunk by setting the chunk's _ENV upvalue. A nil name (the main script's
/// `module(..., package.seeall)`) names the module after the calling file.
int module_function(lua_State* L) {
    if (lua_gettop(L) == 0) lua_settop(L, 1);
    if (lua_isnil(L, 1)) {
        if (!caller_stem(L, context(L))) return luaL_error(L, "module: a module name is required");
        lua_pushstring(L, context(L).result_text.c_str());
        lua_replace(L, 1);
    }
    const char* name = luaL_checkstring(L, 1);
    const int last_option = lua_gettop(L);
    luaL_getsubtable(L, LUA_REGISTRYINDEX, LUA_LOADED_TABLE);
    const int loaded = lua_gettop(L);
    if (lua_getfield(L, loaded, name) != LUA_TTABLE) {
        lua_pop(L, 1);
        push_global_path(L, name);
        lua_pushvalue(L, -1);
        lua_setfield(L, loaded, name);
    }
    const int module = lua_gettop(L);
    lua_pushliteral(L, "_NAME");
    if (lua_rawget(L, module) == LUA_TNIL) {
        lua_pushvalue(L, module);
        lua_setfield(L, module, "_M");
        lua_pushvalue(L, 1);
        lua_setfield(L, module, "_NAME");
        const char* dot = std::strrchr(name, '.');
        lua_pushlstring(L, name, dot ? dot - name + 1 : 0);
        lua_setfield(L, module, "_PACKAGE");
    }
    lua_pop(L, 1);
    lua_Debug ar;
    if (!lua_getstack(L, 1, &ar) || !lua_getinfo(L, "f", &ar) || lua_iscfunction(L, -1))
        return luaL_error(L, "module: must be called from a Lua chunk");
    const int caller = lua_gettop(L);
    for (int i = 1;; ++i) {
        const char* upvalue = lua_getupvalue(L, caller, i);
        if (!upvalue) break;
        lua_pop(L, 1);
        if (std::strcmp(upvalue, "_ENV") == 0) {
            lua_pushvalue(L, module);
            lua_setupvalue(L, caller, i);
            break;
        }
    }
    lua_pop(L, 1);
    for (int option = 2; option <= last_option; ++option) {
        lua_pushvalue(L, option);
        lua_pushvalue(L, module);
        lua_call(L, 1, 0);
    }
    return 0;
}

/// require(name): package.loaded[name], else name.lua beside the main script or in include/,
/// run with (name, path) as its arguments. No C modules, no search paths from the environment.
int require_function(lua_State* L) {
    const char* name = luaL_checkstring(L, 1);
    lua_settop(L, 1);
    luaL_getsubtable(L, LUA_REGISTRYINDEX, LUA_LOADED_TABLE);  // 2
    lua_getfield(L, 2, name);                                  // 3
    if (lua_touserdata(L, 3) == &loading_sentinel)
        return luaL_error(L, "require: loop or previous error loading module '%s'", name);
    if (lua_toboolean(L, 3)) return 1;
    lua_pop(L, 1);
    LoaderContext& ctx = context(L);
    if (!find_module_file(ctx, name)) return luaL_error(L, "require: %s", ctx.pending_error.c_str());
    lua_pushstring(L, ctx.resolved_path.c_str());  // 3
    lua_pushfstring(L, "@%s", ctx.resolved_path.c_str());
    const int loaded = luaL_loadbufferx(L, ctx.result_text.data(), ctx.result_text.size(), lua_tostring(L, -1), "t");
    release_memory(ctx, ctx.result_text.size());  // charged by read_scene_file; the text goes now
    ctx.result_text.clear();
    ctx.result_text.shrink_to_fit();
    if (loaded != LUA_OK) return lua_error(L);
    lua_remove(L, -2);  // 4
    lua_pushlightuserdata(L, &loading_sentinel);
    lua_setfield(L, 2, name);
    lua_pushvalue(L, 1);
    lua_pushvalue(L, 3);
    lua_call(L, 2, 1);
    if (!lua_isnil(L, -1)) lua_setfield(L, 2, name);
    lua_settop(L, 3);
    lua_getfield(L, 2, name);
    if (lua_touserdata(L, -1) == &loading_sentinel) {
        lua_pop(L, 1);
        lua_pushboolean(L, 1);
        lua_pushvalue(L, -1);
        lua_setfield(L, 2, name);
    }
    return 1;
}

void open_package(lua_State* L) {
    lua_createtable(L, 0, 6);
    luaL_getsubtable(L, LUA_REGISTRYINDEX, LUA_LOADED_TABLE);
    lua_pushvalue(L, -2);
    lua_setfield(L, -2, "package");
    lua_setfield(L, -2, "loaded");
    lua_pushcfunction(L, package_seeall);
    lua_setfield(L, -2, "seeall");
    lua_pushliteral(L, "");
    lua_setfield(L, -2, "path");
    lua_pushliteral(L, "");
    lua_setfield(L, -2, "cpath");
    lua_setglobal(L, "package");
    lua_register(L, "require", require_function);
    lua_register(L, "module", module_function);
}

void open_global(lua_State* L, const char* name, lua_CFunction open) {
    luaL_requiref(L, name, open, 1);
    lua_pop(L, 1);
}

void set_field(lua_State* L, const char* table, const char* field, lua_CFunction function) {
    lua_getglobal(L, table);
    if (function) lua_pushcfunction(L, function);
    else lua_pushnil(L);
    lua_setfield(L, -2, field);
    lua_pop(L, 1);
}

}  // namespace

int open_sandboxed_libraries(lua_State* L) {
    open_global(L, LUA_GNAME, luaopen_base);
    open_global(L, LUA_TABLIBNAME, luaopen_table);
    open_global(L, LUA_STRLIBNAME, luaopen_string);
    open_global(L, LUA_MATHLIBNAME, luaopen_math);
    open_global(L, LUA_UTF8LIBNAME, luaopen_utf8);

    lua_pushnil(L);
    lua_setglobal(L, "dofile");
    lua_pushnil(L);
    lua_setglobal(L, "loadfile");
    lua_getglobal(L, "load");
    lua_pushcclosure(L, load_text_only, 1);
    lua_setglobal(L, "load");
    lua_getglobal(L, "setmetatable");
    lua_pushcclosure(L, setmetatable_without_gc, 1);
    lua_setglobal(L, "setmetatable");
    set_field(L, LUA_STRLIBNAME, "dump", nullptr);

    restrict_io(L);
    bound_script_output(L);
    keep_only(L, LUA_OSLIBNAME, luaopen_os, {"clock", "time", "date", "getenv"});
    keep_only(L, LUA_DBLIBNAME, luaopen_debug, {"getinfo", "traceback"});
    open_package(L);
    register_gr_api(L);
    open_lua51_compat(L);  // before the wrapping below: string.gfind is wrapped too
    bound_library_calls(L);
    return 0;
}

}  // namespace caustica::scene_lua
