// gr.render (the scene snapshot), gr.set_miss_colour, gr.option, and the registration of the whole
// gr table with its handle metatables.
#include "core/lua/lua_context.h"
#include "core/lua/scene_files.h"

#include <glm/geometric.hpp>

#include <cmath>
#include <filesystem>

namespace caustica::scene_lua {
namespace {

constexpr int max_image_side = 32768;
constexpr double max_image_pixels = 268435456.0;  // 2^28

int image_size_arg(lua_State* L, int index, const char* what) {
    const double value = number_arg(L, index, what);
    if (value != std::floor(value))
        throw InputError(std::string(what) + " must be a whole number of pixels, got " + format_number(value));
    if (value < 1.0) throw InputError(std::string(what) + " must be positive, got " + format_number(value));
    if (value > max_image_side)
        throw InputError(std::string(what) + " " + format_number(value) + " is larger than the maximum of " +
                         std::to_string(max_image_side) + " pixels");
    return static_cast<int>(value);
}

/// Output names from a script are relative to the folder caustica runs in and stay below it:
/// a scene may not write anywhere else (the user's -o may). This checks the name as text; where it
/// leads through symlinks is checked before rendering and when writing (core/io/output_folder.h).
void check_output_name(const std::string& name) {
    if (name.find('\0') != std::string::npos) throw InputError("output file name contains a NUL byte");
    const std::filesystem::path path(name);
    const char* hint = " (scenes write below the current folder; use -o to choose another place)";
    if (path.has_root_path())
        throw InputError("output file name '" + name + "' must be relative, not absolute" + hint);
    for (const auto& part : path)
        if (part == "..") throw InputError("output file name '" + name + "' must not climb with '..'" + hint);
}

glm::dvec3 direction_arg(lua_State* L, int index, const char* what) {
    const glm::dvec3 direction = vec3_arg(L, index, what);
    if (glm::length(direction) == 0.0) throw InputError(std::string(what) + " must not be zero-length");
    return direction;
}

/// gr.render(root, 'out.png', w, h, {eye}, {view}, {up}, fovy, {ambient}, {lights}) or root:render(...).
CallResult render(lua_State* L, LoaderContext& ctx, bool method) {
    if (method) {
        self_arg(L, HandleKind::node);
        expect_arguments(L, 2, 9, 9, "'out.png', width, height, {eye}, {view}, {up}, fovy, {ambient}, {lights}");
    } else {
        expect_arguments(L, 1, 10, 10,
                         "root, 'out.png', width, height, {eye}, {view}, {up}, fovy, {ambient}, {lights}");
    }
    RenderJob job;
    job.root = handle_arg(L, 1, HandleKind::node, "root");
    job.output = string_arg(L, 2, "output file name");
    if (job.output.empty()) throw InputError("output file name must not be empty");
    if (!ctx.output_given) check_output_name(job.output);
    job.width = image_size_arg(L, 3, "width");
    job.height = image_size_arg(L, 4, "height");
    if (static_cast<double>(job.width) * job.height > max_image_pixels)
        throw InputError("an image of " + std::to_string(job.width) + " x " + std::to_string(job.height) +
                         " pixels is larger than the maximum of 2^28 pixels");
    job.camera.eye = vec3_arg(L, 5, "eye");
    job.camera.view = direction_arg(L, 6, "view");
    job.camera.up = direction_arg(L, 7, "up");
    if (glm::length(glm::cross(glm::normalize(job.camera.view), glm::normalize(job.camera.up))) < 1e-9)
        throw InputError("up must not be parallel to view");
    job.camera.fovy_degrees = number_arg(L, 8, "fovy");
    if (job.camera.fovy_degrees <= 0.0 || job.camera.fovy_degrees >= 180.0)
        throw InputError("fovy must be between 0 and 180 degrees (both excluded), got " +
                         format_number(job.camera.fovy_degrees));
    job.ambient = vec3_arg(L, 9, "ambient");
    for (int i = 0; i < 3; ++i)
        if (job.ambient[i] < 0.0)
            throw InputError("ambient must not be negative, ambient[" + std::to_string(i + 1) + "] is " +
                             format_number(job.ambient[i]));
    if (lua_type(L, 10) != LUA_TTABLE)
        throw InputError("lights must be a table of lights, got " + describe_value(L, 10));
    const auto count = static_cast<lua_Integer>(lua_rawlen(L, 10));
    for (lua_Integer i = 1; i <= count; ++i) {
        lua_rawgeti(L, 10, i);
        const Handle* light = to_handle(L, -1);
        const bool is_light = light && light->kind == HandleKind::light;
        const int index = is_light ? light->index : -1;
        std::string description = is_light ? std::string() : describe_value(L, -1);
        lua_pop(L, 1);
        if (!is_light)
            throw InputError("lights[" + std::to_string(i) + "] must be a light (from gr.light), got " + description);
        job.lights.push_back(index);
    }
    job.miss_colour = ctx.miss_colour;
    job.options = ctx.options;
    job.option_origins = ctx.option_origins;
    job.where = caller_location(L);
    charge_memory(ctx, ctx.scene_bytes + sizeof(RenderJob) + ctx.option_origins.size() * 64, "the scene snapshot of this gr.render");
    job.scene = std::make_shared<const SceneDesc>(ctx.scene);
    ctx.renders.push_back(std::move(job));
    return CallResult::nothing();
}

CallResult gr_render(lua_State* L, LoaderContext& ctx) { return render(L, ctx, false); }
CallResult node_render(lua_State* L, LoaderContext& ctx) { return render(L, ctx, true); }

CallResult gr_set_miss_colour(lua_State* L, LoaderContext& ctx) {
    expect_arguments(L, 1, 1, 1, "{r, g, b}");
    const glm::dvec3 colour = vec3_arg(L, 1, "colour");
    for (int i = 0; i < 3; ++i)
        if (colour[i] < 0.0)
            throw InputError("colour must not be negative, colour[" + std::to_string(i + 1) + "] is " +
                             format_number(colour[i]));
    ctx.miss_colour = colour;
    ctx.options.rays = false;  // a miss colour replaces --rays (docs/SCENE_LANGUAGE.md, "background")
    return CallResult::nothing();
}

CallResult gr_option(lua_State* L, LoaderContext& ctx) {
    expect_arguments(L, 1, 1, 1, "'--flag --name value ...'");
    const std::string text = string_arg(L, 1, "options");
    Options options = ctx.options;  // all or nothing
    const std::vector<std::string> tokens = split_option_string(text);
    for (const std::string& token : tokens) {
        if (token.rfind("--allow-read", 0) == 0)
            throw InputError("--allow-read is for the command line only: a scene cannot widen what it may read");
        if (token.rfind("--render-memory", 0) == 0)
            throw InputError("--render-memory is for the command line only: a scene cannot raise what the renderer "
                             "may build");
    }
    apply_option_tokens(options, tokens);
    ctx.options = options;
    const SourceLocation where = caller_location(L);
    for (const std::string& token : tokens) {
        if (token.rfind("--", 0) != 0) continue;
        std::string name = token.substr(2, token.find('=') == std::string::npos ? std::string::npos : token.find('=') - 2);
        charge_memory(ctx, name.capacity() + where.file.capacity() + sizeof(SourceLocation), "option records");
        ctx.option_origins.emplace_back(std::move(name), where);
    }
    return CallResult::nothing();
}

/// __tostring of every handle: "node 'arc'", "material #2", "light #0", "texture '/abs/wood.png'".
CallResult handle_tostring(lua_State* L, LoaderContext& ctx) {
    const Handle* handle = to_handle(L, 1);
    if (!handle) throw InputError("expected a handle");
    const std::string number = " #" + std::to_string(handle->index);
    switch (handle->kind) {
    case HandleKind::node: ctx.result_text = "node '" + ctx.scene.nodes[handle->index].name + "'"; break;
    case HandleKind::material: ctx.result_text = "material" + number; break;
    case HandleKind::light: ctx.result_text = "light" + number; break;
    case HandleKind::texture:
        ctx.result_text = std::string(ctx.texture_is_bumpmap[handle->index] ? "bump map '" : "texture '") +
                          ctx.scene.textures[handle->index].source + "'";
        break;
    }
    return CallResult::text();
}

const GrFunction render_function_table[] = {
    {"render", guarded<gr_render>},
    {"set_miss_colour", guarded<gr_set_miss_colour>},
    {"option", guarded<gr_option>},
};

/// Registry keys (their addresses) of the four handle metatables.
char metatable_keys[4];

/// Sets fields `functions` of the table on top, each a closure with "<prefix><name>" as upvalue 1.
void add_functions(lua_State* L, const char* prefix, std::span<const GrFunction> functions) {
    for (const GrFunction& function : functions) {
        lua_pushfstring(L, "%s%s", prefix, function.name);
        lua_pushcclosure(L, function.function, 1);
        lua_setfield(L, -2, function.name);
    }
}

void make_metatable(lua_State* L, HandleKind kind, const char* type_name, const char* prefix,
                    std::span<const GrFunction> methods) {
    lua_createtable(L, 0, 4);
    lua_createtable(L, 0, static_cast<int>(methods.size()) + 1);
    add_functions(L, prefix, methods);
    if (kind == HandleKind::node) {
        lua_pushliteral(L, "node:render");
        lua_pushcclosure(L, guarded<node_render>, 1);
        lua_setfield(L, -2, "render");
    }
    lua_setfield(L, -2, "__index");
    lua_pushliteral(L, "tostring");
    lua_pushcclosure(L, guarded<handle_tostring>, 1);
    lua_setfield(L, -2, "__tostring");
    lua_pushstring(L, type_name);
    lua_setfield(L, -2, "__name");
    lua_pushliteral(L, "locked");  // getmetatable answers this: no __gc or other field can be added
    lua_setfield(L, -2, "__metatable");
    lua_rawsetp(L, LUA_REGISTRYINDEX, &metatable_keys[static_cast<int>(kind)]);
}

}  // namespace

std::span<const GrFunction> gr_render_functions() { return render_function_table; }

void push_handle(lua_State* L, const Handle& handle) {
    auto* block = static_cast<Handle*>(lua_newuserdatauv(L, sizeof(Handle), 0));
    *block = handle;
    lua_rawgetp(L, LUA_REGISTRYINDEX, &metatable_keys[static_cast<int>(handle.kind)]);
    lua_setmetatable(L, -2);
}

void register_gr_api(lua_State* L) {
    make_metatable(L, HandleKind::node, "caustica.node", "node:", node_methods());
    make_metatable(L, HandleKind::material, "caustica.material", "material:", material_methods());
    make_metatable(L, HandleKind::light, "caustica.light", "light:", light_methods());
    make_metatable(L, HandleKind::texture, "caustica.texture", "texture:", texture_methods());

    lua_createtable(L, 0, 24);
    add_functions(L, "gr.", gr_node_functions());
    add_functions(L, "gr.", gr_shading_functions());
    add_functions(L, "gr.", gr_render_functions());
    luaL_getsubtable(L, LUA_REGISTRYINDEX, LUA_LOADED_TABLE);
    lua_pushvalue(L, -2);
    lua_setfield(L, -2, "gr");
    lua_pop(L, 1);
    lua_setglobal(L, "gr");
}

}  // namespace caustica::scene_lua
