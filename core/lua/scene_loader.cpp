// load_scene_script: runs a scene script in a fresh, sandboxed Lua 5.4 state under a wall-clock
// limit, a heap limit and a cancel flag, and returns the renders it asked for.
#include "core/lua/scene_loader.h"

#include "core/lua/lua_context.h"

#include "core/lua/scene_files.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace caustica {

namespace scene_lua {
volatile std::sig_atomic_t stop_requested = 0;
}

namespace {

using namespace scene_lua;

/// Instructions between two runs of the limit-checking hook.
constexpr int hook_interval = 1000;

/// Copies a Lua location into ctx.last_hook_location and the shared progress page.
void record_location(LoaderContext& ctx, const lua_Debug& ar) {
    SourceLocation& last = ctx.last_hook_location;
    last.line = ar.currentline;
    if (const char* source = ar.source; source && (*source == '@' || *source == '=')) {
        if (last.file.compare(source + 1) != 0) last.file.assign(source + 1);
    } else {
        last.file = ar.short_src;
    }
    if (SharedProgress* shared = ctx.shared_progress) {
        shared->line = last.line;
        const std::size_t n = std::min(last.file.size(), sizeof shared->file - 1);
        if (std::memcmp(shared->file, last.file.data(), n) != 0 || shared->file[n] != 0) {
            std::memcpy(shared->file, last.file.data(), n);
            shared->file[n] = 0;
        }
    }
}

/// The location of the allocation being refused, for the memory message (a short script may fail
/// before the count hook has run once).
void note_refusal_location(LoaderContext& ctx) noexcept {
    if (ctx.L && !ctx.finished && !ctx.noting_location) {
        ctx.noting_location = true;
        note_location(ctx.L, ctx);
        ctx.noting_location = false;
    }
}

/// lua_Alloc that counts the heap and refuses to grow it past the limit (Lua raises LUA_ERRMEM),
/// or at all once the watchdog asked the script to stop.
void* counting_alloc(void* ud, void* block, size_t old_size, size_t new_size) noexcept {
    auto& ctx = *static_cast<LoaderContext*>(ud);
    const size_t old_bytes = block ? old_size : 0;  // without a block, old_size is a type tag
    if (new_size == 0) {
        std::free(block);
        ctx.memory_used -= old_bytes;
        return nullptr;
    }
    if (new_size > old_bytes && stop_requested) return nullptr;
    if (new_size > old_bytes && ctx.memory_limit != 0 &&
        ctx.memory_used - old_bytes + new_size > ctx.memory_limit) {
        note_memory_exceeded(ctx);
        return nullptr;
    }
    void* resized = std::realloc(block, new_size);
    if (!resized) {
        if (new_size <= old_bytes) return block;  // Lua assumes shrinking never fails
        note_refusal_location(ctx);
        return nullptr;
    }
    ctx.memory_used = ctx.memory_used - old_bytes + new_size;
    return resized;
}

std::string stop_location(const LoaderContext& ctx) {
    return ctx.last_hook_location.file.empty() ? ctx.script_path : ctx.last_hook_location.str();
}

/// Records where the script is (from the hook's activation record) and decides whether it must
/// stop. Never throws.
bool may_continue(lua_State* L, lua_Debug* ar, LoaderContext& ctx) noexcept {
    try {
        if (lua_getinfo(L, "Sl", ar) && ar->currentline > 0) record_location(ctx, *ar);
    } catch (...) {
    }
    if (!limits_reached(ctx)) return true;
    lua_sethook(L, lua_gethook(L), LUA_MASKCOUNT, 1);  // raise again at every instruction
    return false;
}

void count_hook(lua_State* L, lua_Debug* ar) {
    LoaderContext& ctx = context(L);
    if (may_continue(L, ar, ctx)) return;
    lua_pushlstring(L, ctx.stop_message.data(), ctx.stop_message.size());
    lua_error(L);
}

}  // namespace

void scene_lua::collect_warning_piece(LoaderContext& ctx, std::string_view piece, bool to_continue) noexcept {
    try {
        if (ctx.finished || !ctx.stop_message.empty()) return;
        const bool first_piece = ctx.warning_in_progress.empty() && ctx.warning_left_out == 0;
        if (first_piece && !to_continue && !piece.empty() && piece[0] == '@') return;  // "@on", "@off"
        const std::size_t kept = std::min(piece.size(), script_text_limit - ctx.warning_in_progress.size());
        ctx.warning_in_progress.append(piece.substr(0, kept));
        ctx.warning_left_out += piece.size() - kept;
        if (to_continue) return;
        const SourceLocation where = caller_location(ctx.L, 1);
        const std::string text = (where.file.empty() ? std::string() : where.str() + ": ") + ctx.warning_in_progress;
        const std::size_t left_out = ctx.warning_left_out;
        ctx.warning_in_progress.clear();
        ctx.warning_left_out = 0;
        std::optional<std::string> shown = ctx.output.admit(text, left_out);
        if (!shown) return;
        try {
            charge_memory(ctx, shown->size(), "warnings");
        } catch (const InputError& e) {
            // No Lua error can be raised from here: the hook raises it at the next instruction.
            ctx.stop_message = where.str() + ": warn: " + e.what();
            lua_sethook(ctx.L, count_hook, LUA_MASKCOUNT, 1);
            return;
        }
        ctx.warnings.push_back(std::move(*shown));
    } catch (...) {
    }
}

namespace {

/// Lua's own warnings (the script's warn() is bound_script_output's) go the same way.
void collect_warning(void* ud, const char* message, int to_continue) noexcept {
    collect_warning_piece(*static_cast<LoaderContext*>(ud), message, to_continue != 0);
}

/// True when `text` starts like "file:12: " (no colon or newline in the file part).
bool starts_with_location(const std::string& text) {
    const size_t colon = text.find(':');
    if (colon == 0 || colon == std::string::npos || text.find('\n') < colon) return false;
    size_t end = colon + 1;
    while (end < text.size() && std::isdigit(static_cast<unsigned char>(text[end]))) ++end;
    return end > colon + 1 && end < text.size() && text[end] == ':';
}

/// The error value as the user will see it, in ctx.result_text: a string made printable and
/// bounded (docs/RELIABILITY.md, "Script text reaches the user bounded and visible"), and given the
/// line that raised it when it carries none ("error('x', 0)", "error({})"). Never throws.
bool shown_error(lua_State* L, LoaderContext& ctx) noexcept {
    try {
        std::string text;
        bool located = false;
        if (lua_type(L, 1) == LUA_TSTRING) {
            std::size_t size = 0;
            const char* value = lua_tolstring(L, 1, &size);
            text = printable_text({value, size}, script_text_limit);
            located = starts_with_location(text) || text.rfind(ctx.script_path + ":", 0) == 0;
        } else {
            text = "error object is " + describe_value(L, 1);
        }
        const SourceLocation where = located ? SourceLocation{} : caller_location(L, 1);
        ctx.result_text = where.file.empty() ? std::move(text) : where.str() + ": " + text;
        return true;
    } catch (...) {
        return false;
    }
}

/// The message handler of the main chunk's lua_pcall.
int message_handler(lua_State* L) {
    LoaderContext& ctx = context(L);
    if (shown_error(L, ctx)) lua_pushlstring(L, ctx.result_text.data(), ctx.result_text.size());
    else lua_settop(L, 1);
    return 1;
}

/// Compiles the main chunk (text only) from ctx.result_text, named "@" + the script's path.
int load_main_chunk(lua_State* L) {
    LoaderContext& ctx = context(L);
    lua_pushfstring(L, "@%s", ctx.script_path.c_str());
    if (luaL_loadbufferx(L, ctx.result_text.data(), ctx.result_text.size(), lua_tostring(L, -1), "t") != LUA_OK)
        return lua_error(L);
    return 1;
}

int set_up_state(lua_State* L) {
    open_sandboxed_libraries(L);
    return 0;
}

/// The error value on top of the stack as text, without calling anything that may raise.
std::string error_text(lua_State* L) {
    switch (lua_type(L, -1)) {
    case LUA_TSTRING: {
        std::size_t size = 0;
        const char* text = lua_tolstring(L, -1, &size);
        return printable_text({text, size});
    }
    case LUA_TNUMBER: return "error " + format_number(lua_tonumber(L, -1));
    default: return "error object is " + describe_value(L, -1);
    }
}

std::string memory_limit_message(const LoaderContext& ctx) {
    const std::string where = ctx.memory_exceeded_at.file.empty() ? stop_location(ctx) : ctx.memory_exceeded_at.str();
    return where + ": script exceeded the memory limit of " +
           format_number(static_cast<double>(ctx.memory_limit) / (1024.0 * 1024.0)) +
           " MiB (Lua heap and scene data; --script-memory sets it)";
}

std::string failure_message(lua_State* L, LoaderContext& ctx, int status) {
    if (stop_requested) limits_reached(ctx);
    if (!ctx.stop_message.empty()) return ctx.stop_message;
    if (status == LUA_ERRMEM) {
        if (!ctx.memory_exceeded) return stop_location(ctx) + ": out of memory";
        return memory_limit_message(ctx);
    }
    return error_text(L);
}

/// Owns the lua_State and closes it once (scripts cannot leave finalizers: see setmetatable).
class StateOwner {
public:
    StateOwner(lua_State* L, LoaderContext& ctx) : L_(L), ctx_(ctx) {}
    StateOwner(const StateOwner&) = delete;
    StateOwner& operator=(const StateOwner&) = delete;
    ~StateOwner() { close(); }

    void close() {
        if (!L_) return;
        ctx_.finished = true;
        lua_close(L_);
        L_ = nullptr;
        ctx_.L = nullptr;
    }

private:
    lua_State* L_;
    LoaderContext& ctx_;
};

}  // namespace

namespace scene_lua {

void note_location(lua_State* L, LoaderContext& ctx) noexcept {
    try {
        lua_Debug ar;
        for (int level = 0; lua_getstack(L, level, &ar); ++level) {
            if (!lua_getinfo(L, "Sl", &ar)) break;
            if (ar.currentline > 0) {
                record_location(ctx, ar);
                return;
            }
        }
    } catch (...) {
    }
}

void note_memory_exceeded(LoaderContext& ctx) noexcept {
    if (!ctx.memory_exceeded) {
        note_refusal_location(ctx);
        try {
            ctx.memory_exceeded_at = ctx.last_hook_location;
        } catch (...) {
        }
    }
    ctx.memory_exceeded = true;
    if (ctx.L && !ctx.finished) lua_sethook(ctx.L, count_hook, LUA_MASKCOUNT, 1);
}

bool limits_reached(LoaderContext& ctx) noexcept {
    try {
        if (!ctx.stop_message.empty()) return true;  // once stopped, a pcall cannot resume the script
        if ((ctx.cancel && ctx.cancel->load(std::memory_order_relaxed)) || stop_requested == 2) {
            ctx.cancelled = true;
            ctx.stop_message = stop_location(ctx) + ": interrupted";
        } else if (stop_requested ||
                   (ctx.timeout_seconds > 0.0 && std::chrono::steady_clock::now() >= ctx.deadline)) {
            ctx.timed_out = true;
            ctx.stop_message = stop_location(ctx) + ": script stopped after " + format_number(ctx.timeout_seconds) +
                               " s (--script-timeout)";
        } else if (ctx.memory_exceeded) {
            // The budget is not a Lua error the script may catch: once reached, the script stops.
            ctx.stop_message = memory_limit_message(ctx);
        } else {
            return false;
        }
    } catch (...) {
        ctx.stop_message = "out of memory";
    }
    return true;
}

}  // namespace scene_lua

SceneScript scene_lua::run_script(const std::string& path, const LoadSettings& settings, SharedProgress* progress) {
    namespace fs = std::filesystem;
    LoaderContext ctx;
    ctx.script_path = path;
    ctx.script_dir_as_given = fs::path(path).parent_path();
    ctx.result_text = read_main_script(path, settings.memory_limit_bytes);
    std::error_code error;
    const fs::path folder = fs::absolute(path, error).parent_path();
    ctx.scene_dir = real_folder(folder.string(), "the scene's folder");
    ctx.read_roots.push_back(ctx.scene_dir);
    for (const std::string& allowed : settings.allow_read) ctx.read_roots.push_back(real_folder(allowed, "--allow-read"));
    ctx.output_given = settings.output_given;
    ctx.options = settings.base_options;
    ctx.memory_limit = settings.memory_limit_bytes;
    ctx.shared_progress = progress;
    ctx.memory_used = ctx.result_text.size();
    ctx.timeout_seconds = settings.timeout_seconds;
    ctx.cancel = settings.cancel;
    if (ctx.cancel && ctx.cancel->load()) throw ScriptCancelled();

    lua_State* L = lua_newstate(counting_alloc, &ctx);
    if (!L) throw InputError(path + ": cannot start the Lua interpreter (out of memory)");
    StateOwner owner(L, ctx);
    ctx.L = L;
    *static_cast<LoaderContext**>(lua_getextraspace(L)) = &ctx;
    lua_setwarnf(L, collect_warning, &ctx);

    lua_pushcfunction(L, set_up_state);
    if (lua_pcall(L, 0, 0, 0) != LUA_OK) {
        const std::string message = failure_message(L, ctx, LUA_ERRRUN);
        throw InputError(path + ": cannot set up the scene interpreter: " + message);
    }

    ctx.deadline = std::chrono::steady_clock::now() +
                   std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                       std::chrono::duration<double>(std::min(settings.timeout_seconds, 1e9)));
    lua_sethook(L, count_hook, LUA_MASKCOUNT, hook_interval);

    // Compiled under protection, then called straight from C so that at the chunk's top level
    // debug.getinfo(2) is nil ("run as main").
    lua_pushcfunction(L, message_handler);
    lua_pushcfunction(L, load_main_chunk);
    int status = lua_pcall(L, 0, 1, 0);
    release_memory(ctx, ctx.result_text.size());  // the text goes; the chunk stays
    std::string().swap(ctx.result_text);
    if (status == LUA_OK) status = lua_pcall(L, 0, 0, 1);
    const std::string output_left_out = ctx.output.summary("script output (print, io.write, warn)");
    if (status != LUA_OK) {
        const std::string message = failure_message(L, ctx, status);
        const bool cancelled = ctx.cancelled;
        owner.close();
        if (cancelled) throw ScriptCancelled();
        if (!output_left_out.empty()) {  // the error replaces the warnings: say it where the output went
            std::fflush(stdout);
            std::fprintf(stderr, "warning: %s\n", printable_text(path + ": " + output_left_out).c_str());
        }
        throw InputError(message);
    }
    owner.close();

    SceneScript script;
    script.path = path;
    script.renders = std::move(ctx.renders);
    script.warnings = std::move(ctx.warnings);
    if (!output_left_out.empty()) script.warnings.push_back(path + ": " + output_left_out);
    return script;
}

SceneScript load_scene_script_in_process(const std::string& path, const LoadSettings& settings) {
    return scene_lua::run_script(path, settings, nullptr);
}

}  // namespace caustica
