// Internal to the Lua scene loader: the state a running script builds, the handles Lua holds,
// and the guard that keeps C++ exceptions from crossing Lua frames.
//
// Lua is compiled as C here, so lua_error unwinds with longjmp. The rule every C function follows:
// C++ work (which may throw) runs inside `call_guarded`, reads its arguments only through the
// non-raising readers below, and hands back a `CallResult`; anything that can raise a Lua error
// (pushing results, lua_error) happens after every C++ object of the call is gone.
#pragma once

#include "core/lua/loader_child.h"
#include "core/lua/scene_loader.h"
#include "core/util/printable_text.h"

#include <lua.hpp>

#include <chrono>
#include <csignal>
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace caustica {
struct Png8;
}

namespace caustica::scene_lua {

/// What a Lua handle refers to; the index is into the matching SceneDesc vector.
enum class HandleKind : std::uint32_t { node, material, light, texture };

/// The payload of every userdata the gr API gives to Lua.
struct Handle {
    std::uint32_t magic = 0;  ///< handle_magic for ours (a script cannot forge userdata bytes)
    HandleKind kind = HandleKind::node;
    int index = -1;
};

/// Marks a userdata as a caustica handle.
inline constexpr std::uint32_t handle_magic = 0xCA05771Cu;

/// Everything a running script builds and the limits it runs under; lives as long as the lua_State.
struct LoaderContext {
    // inputs
    std::string script_path;                ///< as passed to load_scene_script
    std::filesystem::path script_dir_as_given;  ///< parent of script_path as written ("" for the cwd)
    std::filesystem::path scene_dir;        ///< absolute, canonical folder of the main script
    std::vector<std::filesystem::path> read_roots;  ///< real paths scripts may read under (scene_dir first)
    bool output_given = false;              ///< -o was given: gr.render's file names are not used
    lua_State* L = nullptr;

    // the scene so far
    SceneDesc scene;
    std::vector<bool> texture_is_bumpmap;   ///< parallel to scene.textures
    std::vector<bool> node_is_held;         ///< parallel to scene.nodes: some node's child or CSG operand
    std::vector<std::uint32_t> node_walk_mark;  ///< parallel to scene.nodes: add_child's cycle walk that saw it
    std::uint32_t node_walk = 0;            ///< the last cycle walk's number (marks above are older walks)
    std::map<std::pair<std::uint64_t, std::uint64_t>, int> mesh_cache;  ///< (device, inode) -> scene.meshes index
    int isodecahedron_mesh = -1;            ///< scene.meshes index of gr.isodecahedron's mesh, made once
    std::map<std::pair<std::uint64_t, std::uint64_t>, std::shared_ptr<const Png8>> image_cache;  ///< decoded once per file
    std::size_t scene_bytes = 0;            ///< estimate of ctx.scene's size: what one gr.render snapshot costs
    Options options;                        ///< base options + every gr.option so far
    std::vector<std::pair<std::string, SourceLocation>> option_origins;  ///< see RenderJob::option_origins
    glm::dvec3 miss_colour{1.0};            ///< white until gr.set_miss_colour (docs/SCENE_LANGUAGE.md)
    std::vector<RenderJob> renders;
    std::vector<std::string> warnings;
    std::string warning_in_progress;        ///< pieces of a multi-part warn() message, at most script_text_limit bytes
    std::size_t warning_left_out = 0;       ///< bytes of those pieces past script_text_limit
    ScriptOutputBudget output;              ///< what print, io.write and warn may still show

    // limits
    std::size_t memory_used = 0;
    std::size_t memory_limit = 0;           ///< 0 = no limit
    bool memory_exceeded = false;           ///< an allocation was refused for the limit
    SourceLocation memory_exceeded_at;      ///< where it first was (the stop message names it)
    double timeout_seconds = 0.0;
    std::chrono::steady_clock::time_point deadline;
    const std::atomic<bool>* cancel = nullptr;
    bool timed_out = false;
    bool cancelled = false;
    bool finished = false;                  ///< the state is closing: warnings are no longer collected
    SourceLocation last_hook_location;      ///< refreshed by the instruction-count hook (memory errors use it)
    SharedProgress* shared_progress = nullptr;  ///< a copy of last_hook_location for the parent process
    bool noting_location = false;           ///< note_location is running (the allocator must not re-enter it)
    std::uint64_t library_steps = 0;        ///< iterations of bounded library loops (limits checked every 4096)

    // messages handed from C++ to Lua
    std::string pending_error;              ///< raised by the guard after the C++ frames are gone
    std::string stop_message;               ///< timeout/cancel message, raised again on every later hook
    std::string result_text;                ///< CallResult::Kind::text payload
    std::string resolved_path;              ///< output of resolve_* helpers for the sandbox functions
    int opened_fd = -1;                     ///< a scene file opened for io.open/io.lines, closed after the call
};

/// Limits the watchdog may set from another thread or a signal handler (the parent process asks
/// the loader process to stop): allocations fail and the hook raises at the next instruction.
extern volatile std::sig_atomic_t stop_requested;

/// Records the line the script is on (the first Lua function on the stack) in
/// ctx.last_hook_location and the shared progress page. Never throws.
void note_location(lua_State* L, LoaderContext& ctx) noexcept;
/// True when the script must stop (time limit, cancel flag, watchdog, memory budget):
/// ctx.stop_message says why.
bool limits_reached(LoaderContext& ctx) noexcept;
/// Records that the memory budget is used up, where the script is, and makes the limit-checking
/// hook run at every instruction: the script then stops at once, whatever pcall it wraps around
/// the allocation. Never throws.
void note_memory_exceeded(LoaderContext& ctx) noexcept;

/// The loader context stored in the state's extra space.
LoaderContext& context(lua_State* L);

/// What a guarded body gives back to Lua.
struct CallResult {
    enum class Kind { none, handle, text } kind = Kind::none;
    Handle handle;

    static CallResult nothing() { return {}; }
    static CallResult of(HandleKind kind, int index) { return {Kind::handle, Handle{handle_magic, kind, index}}; }
    /// A string result; the text is in LoaderContext::result_text.
    static CallResult text() { return {Kind::text, {}}; }
};

/// The C++ body of a gr function: reads its arguments, changes the context, throws on bad input.
using GuardedBody = CallResult (*)(lua_State* L, LoaderContext& ctx);

/// Runs `body` and pushes its result; a C++ exception becomes a Lua error "file:line: name: what",
/// where name is the closure's first upvalue (e.g. "gr.material").
int call_guarded(lua_State* L, GuardedBody body);

/// The lua_CFunction for a body (register it with its name as upvalue 1).
template <GuardedBody Body>
int guarded(lua_State* L) {
    return call_guarded(L, Body);
}

/// One gr function or method: its name as shown in errors and its entry point.
struct GrFunction {
    const char* name;  ///< e.g. "material" (registered as gr.material) or "translate" (node:translate)
    lua_CFunction function;
};

// ---- argument readers: they never raise Lua errors; they throw InputError without location ----

/// The first Lua function on the stack from `level` up: the line a gr call was written on.
SourceLocation caller_location(lua_State* L, int level = 1);
/// The location of an activation record filled by lua_getstack/lua_getinfo("Sl").
SourceLocation location_of(const lua_Debug& ar);
/// Checks the number of arguments from stack index `first` (2 for methods: self is 1).
void expect_arguments(lua_State* L, int first, int min, int max, const char* signature);
/// A string argument ("name must be a string, got a number").
std::string string_arg(lua_State* L, int index, const char* what);
/// A finite number argument.
double number_arg(lua_State* L, int index, const char* what);
/// A table of exactly 3 finite numbers ("kd must be 3 numbers, ...").
glm::dvec3 vec3_arg(lua_State* L, int index, const char* what);
/// Our handle at `index`, or nullptr when the value is anything else.
const Handle* to_handle(lua_State* L, int index);
/// The index of a handle of `kind` at `index`; `what` names the argument in the error.
int handle_arg(lua_State* L, int index, HandleKind kind, const char* what);
/// The receiver of a method (stack index 1) as a handle of `kind`.
int self_arg(lua_State* L, HandleKind kind);
/// Bytes held by a mesh's arrays.
std::size_t mesh_bytes(const MeshData& mesh);

/// "nil", "a number", "a node", "a bump map", ... for error messages.
std::string describe_value(lua_State* L, int index);
/// Short text for a number in messages ("nan", "-inf", "0.5").
std::string format_number(double value);

// ---- registration ----

/// gr.node, gr.sphere, ..., gr.union and friends.
std::span<const GrFunction> gr_node_functions();
/// node:add_child, node:translate, ... (without node:render).
std::span<const GrFunction> node_methods();
/// gr.material, gr.air, gr.texture, gr.bumpmap, gr.light.
std::span<const GrFunction> gr_shading_functions();
/// m:set_reflective, m:set_ri, m:set_texture, m:set_bumpmap.
std::span<const GrFunction> material_methods();
/// tex:remapt and bump:remap (one handle type for both).
std::span<const GrFunction> texture_methods();
/// light:set_radius.
std::span<const GrFunction> light_methods();
/// gr.render, gr.set_miss_colour, gr.option.
std::span<const GrFunction> gr_render_functions();

/// Creates the gr table (global and package.loaded.gr) and the handle metatables.
void register_gr_api(lua_State* L);
/// Pushes a new userdata for `handle` with the metatable of its kind.
void push_handle(lua_State* L, const Handle& handle);

/// Runs a script in this process (load_scene_script_in_process); `progress`, when given, is kept
/// up to date with the line the script is on.
SceneScript run_script(const std::string& path, const LoadSettings& settings, SharedProgress* progress);

/// Opens base, table, string, math, utf8 and the restricted io, os, debug, package, require,
/// module and load (lua_CFunction run under lua_pcall while the state is set up).
int open_sandboxed_libraries(lua_State* L);

/// Replaces print, io.write, the standard files' write and warn by versions that go through
/// LoaderContext::output (core/lua/lua_output.cpp).
void bound_script_output(lua_State* L);
/// Adds one piece of a warning (the last one when !to_continue) to ctx.warnings: each warning
/// printable and bounded, all of them within ctx.output, shared with print and io.write
/// (docs/RELIABILITY.md, "Script text reaches the user bounded and visible"). Never throws.
void collect_warning_piece(LoaderContext& ctx, std::string_view piece, bool to_continue) noexcept;

/// Adds the Lua 5.1 names to the opened libraries: string.gfind, table.getn, unpack, math.mod,
/// math.pow, loadstring (text only) and 5.1's math.random/math.randomseed (lua_random51.h).
void open_lua51_compat(lua_State* L);

}  // namespace caustica::scene_lua
