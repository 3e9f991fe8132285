// The guard around every gr function and the argument readers it uses. Nothing here raises a Lua
// error while a C++ object is alive: readers use only non-raising Lua API calls and throw C++
// exceptions, which call_guarded turns into one lua_error after its C++ frames are gone.
#include "core/lua/lua_context.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <new>
#include <sstream>

namespace caustica::scene_lua {
namespace {

const char* handle_description(const LoaderContext& ctx, const Handle& handle) {
    switch (handle.kind) {
    case HandleKind::node: return "a node";
    case HandleKind::material: return "a material";
    case HandleKind::light: return "a light";
    case HandleKind::texture:
        if (handle.index >= 0 && handle.index < static_cast<int>(ctx.texture_is_bumpmap.size()) &&
            ctx.texture_is_bumpmap[handle.index])
            return "a bump map";
        return "a texture";
    }
    return "a handle";
}

const char* kind_description(HandleKind kind) {
    switch (kind) {
    case HandleKind::node: return "a node";
    case HandleKind::material: return "a material (from gr.material or gr.air)";
    case HandleKind::light: return "a light (from gr.light)";
    case HandleKind::texture: return "a texture";
    }
    return "a handle";
}

/// Fills ctx.pending_error with "file:line: name: what"; never throws.
void compose_error(lua_State* L, LoaderContext& ctx, const char* what) noexcept {
    try {
        const char* name = lua_tostring(L, lua_upvalueindex(1));  // a string upvalue: no conversion
        SourceLocation where = caller_location(L);
        std::string message = where.str();
        if (!message.empty()) message += ": ";
        if (name) message += std::string(name) + ": ";
        message += what;
        ctx.pending_error = std::move(message);
    } catch (...) {
        ctx.pending_error = "out of memory";  // fits the small-string buffer: cannot throw
    }
}

bool run_body(lua_State* L, LoaderContext& ctx, GuardedBody body, CallResult& result) noexcept {
    try {
        result = body(L, ctx);
        return true;
    } catch (const std::bad_alloc&) {
        compose_error(L, ctx, "out of memory");
    } catch (const std::exception& e) {
        compose_error(L, ctx, e.what());
    } catch (...) {
        compose_error(L, ctx, "unexpected error");
    }
    return false;
}

}  // namespace

LoaderContext& context(lua_State* L) {
    return **static_cast<LoaderContext**>(lua_getextraspace(L));
}

int call_guarded(lua_State* L, GuardedBody body) {
    LoaderContext& ctx = context(L);
    CallResult result;
    if (!run_body(L, ctx, body, result)) {
        lua_pushlstring(L, ctx.pending_error.data(), ctx.pending_error.size());
        return lua_error(L);
    }
    switch (result.kind) {
    case CallResult::Kind::none: return 0;
    case CallResult::Kind::handle: push_handle(L, result.handle); return 1;
    case CallResult::Kind::text: lua_pushlstring(L, ctx.result_text.data(), ctx.result_text.size()); return 1;
    }
    return 0;
}

SourceLocation location_of(const lua_Debug& ar) {
    SourceLocation where;
    if (ar.source && (ar.source[0] == '@' || ar.source[0] == '='))
        where.file.assign(ar.source + 1, ar.srclen > 0 ? ar.srclen - 1 : 0);
    else
        where.file = ar.short_src;
    where.line = ar.currentline;
    return where;
}

SourceLocation caller_location(lua_State* L, int level) {
    lua_Debug ar;
    for (; lua_getstack(L, level, &ar); ++level) {
        if (!lua_getinfo(L, "Sl", &ar)) break;
        if (ar.currentline > 0) return location_of(ar);  // skips C functions such as pcall
    }
    return {};
}

std::string format_number(double value) {
    if (std::isnan(value)) return "nan";
    if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
    std::ostringstream text;
    text << value;
    return text.str();
}

std::string describe_value(lua_State* L, int index) {
    switch (lua_type(L, index)) {
    case LUA_TNONE:
    case LUA_TNIL: return "nil";
    case LUA_TBOOLEAN: return "a boolean";
    case LUA_TNUMBER: return "a number (" + format_number(lua_tonumber(L, index)) + ")";
    case LUA_TSTRING: {
        std::size_t size = 0;
        const char* value = lua_tolstring(L, index, &size);
        std::string text(value, std::min<std::size_t>(size, 40));
        if (size > 40) text = text.substr(0, 37) + "...";
        return "a string ('" + printable_text(text) + "')";
    }
    case LUA_TTABLE: return "a table";
    case LUA_TFUNCTION: return "a function";
    case LUA_TUSERDATA:
        if (const Handle* handle = to_handle(L, index)) return handle_description(context(L), *handle);
        return "a userdata";
    default: return lua_typename(L, lua_type(L, index));
    }
}

void expect_arguments(lua_State* L, int first, int min, int max, const char* signature) {
    const int count = std::max(0, lua_gettop(L) - first + 1);
    if (count >= min && count <= max) return;
    std::string expected;
    if (min == max)
        expected = std::to_string(min) + (min == 1 ? " argument" : " arguments");
    else if (max == min + 1)
        expected = std::to_string(min) + " or " + std::to_string(max) + " arguments";
    else
        expected = std::to_string(min) + " to " + std::to_string(max) + " arguments";
    std::string message = "expected " + expected;
    if (signature && *signature) message += " (" + std::string(signature) + ")";
    throw InputError(message + ", got " + std::to_string(count));
}

std::string string_arg(lua_State* L, int index, const char* what) {
    if (lua_type(L, index) != LUA_TSTRING)
        throw InputError(std::string(what) + " must be a string, got " + describe_value(L, index));
    size_t length = 0;
    const char* text = lua_tolstring(L, index, &length);  // already a string: no conversion
    return std::string(text, length);
}

double number_arg(lua_State* L, int index, const char* what) {
    if (lua_type(L, index) != LUA_TNUMBER)
        throw InputError(std::string(what) + " must be a number, got " + describe_value(L, index));
    const double value = lua_tonumber(L, index);
    if (!std::isfinite(value))
        throw InputError(std::string(what) + " must be a finite number, got " + format_number(value));
    return value;
}

glm::dvec3 vec3_arg(lua_State* L, int index, const char* what) {
    const std::string name = what;
    if (lua_type(L, index) != LUA_TTABLE)
        throw InputError(name + " must be 3 numbers, got " + describe_value(L, index));
    const lua_Unsigned length = lua_rawlen(L, index);
    if (length != 3)
        throw InputError(name + " must be 3 numbers, got a table of " + std::to_string(length) + " values");
    glm::dvec3 result{0.0};
    for (int i = 0; i < 3; ++i) {
        const int type = lua_rawgeti(L, index, i + 1);
        const double value = lua_tonumber(L, -1);
        lua_pop(L, 1);
        const std::string element = name + "[" + std::to_string(i + 1) + "]";
        if (type != LUA_TNUMBER)
            throw InputError(name + " must be 3 numbers, " + element + " is " +
                             (type == LUA_TNIL ? std::string("nil") : std::string("a ") + lua_typename(L, type)));
        if (!std::isfinite(value))
            throw InputError(name + " must be 3 finite numbers, " + element + " is " + format_number(value));
        result[i] = value;
    }
    return result;
}

const Handle* to_handle(lua_State* L, int index) {
    if (lua_type(L, index) != LUA_TUSERDATA || lua_rawlen(L, index) != sizeof(Handle)) return nullptr;
    const auto* handle = static_cast<const Handle*>(lua_touserdata(L, index));
    return handle->magic == handle_magic ? handle : nullptr;
}

int handle_arg(lua_State* L, int index, HandleKind kind, const char* what) {
    const Handle* handle = to_handle(L, index);
    if (!handle || handle->kind != kind)
        throw InputError(std::string(what) + " must be " + kind_description(kind) + ", got " +
                         describe_value(L, index));
    return handle->index;
}

int self_arg(lua_State* L, HandleKind kind) {
    const Handle* handle = to_handle(L, 1);
    if (!handle || handle->kind != kind)
        throw InputError(std::string("expected ") + kind_description(kind) +
                         " before ':' (write object:method(...)), got " + describe_value(L, 1));
    return handle->index;
}

}  // namespace caustica::scene_lua
