// The appearance half of the gr API: materials, textures, bump maps and lights.
#include "core/lua/lua_context.h"
#include "core/lua/scene_files.h"
#include "core/io/png_io.h"

#include <algorithm>
#include <array>
#include <cstdint>

namespace caustica::scene_lua {
namespace {

constexpr std::array<const char*, 4> procedural_textures = {"redcheck", "greencheck", "bluecheck", "whitecheck"};
constexpr std::array<const char*, 5> remap_modes = {"cubetop", "cubefront", "cubebot", "cyltop", "conetop"};

bool listed(const auto& names, const std::string& name) {
    return std::any_of(names.begin(), names.end(), [&](const char* n) { return name == n; });
}

/// Throws when a colour-like vector has a negative component.
void require_non_negative(const glm::dvec3& value, const char* what) {
    for (int i = 0; i < 3; ++i)
        if (value[i] < 0.0)
            throw InputError(std::string(what) + " must not be negative, " + what + "[" + std::to_string(i + 1) +
                             "] is " + format_number(value[i]));
}

int add_material(LoaderContext& ctx, MaterialDesc material) {
    charge_append(ctx, ctx.scene.materials, material.where.file.capacity(), "materials");
    ctx.scene.materials.push_back(std::move(material));
    return static_cast<int>(ctx.scene.materials.size()) - 1;
}

CallResult gr_material(lua_State* L, LoaderContext& ctx) {
    expect_arguments(L, 1, 3, 3, "{kd}, {ks}, shininess");
    MaterialDesc material;
    material.kd = vec3_arg(L, 1, "kd");
    material.ks = vec3_arg(L, 2, "ks");
    material.shininess = number_arg(L, 3, "shininess");
    require_non_negative(material.kd, "kd");
    require_non_negative(material.ks, "ks");
    if (material.shininess < 0.0)
        throw InputError("shininess must not be negative, got " + format_number(material.shininess));
    material.where = caller_location(L);
    return CallResult::of(HandleKind::material, add_material(ctx, std::move(material)));
}

CallResult gr_air(lua_State* L, LoaderContext& ctx) {
    expect_arguments(L, 1, 0, 0, "");
    MaterialDesc material;
    material.air = true;
    material.where = caller_location(L);
    return CallResult::of(HandleKind::material, add_material(ctx, std::move(material)));
}

CallResult material_set_reflective(lua_State* L, LoaderContext& ctx) {
    const int material = self_arg(L, HandleKind::material);
    expect_arguments(L, 2, 0, 0, "");
    ctx.scene.materials[material].reflective = true;
    return CallResult::nothing();
}

CallResult material_set_ri(lua_State* L, LoaderContext& ctx) {
    const int material = self_arg(L, HandleKind::material);
    expect_arguments(L, 2, 1, 1, "refractive index");
    const double index = number_arg(L, 2, "refractive index");
    if (index <= 0.0) throw InputError("refractive index must be positive, got " + format_number(index));
    ctx.scene.materials[material].refractive_index = index;
    return CallResult::nothing();
}

/// The texture (bumpmap = false) or bump map (true) handle at stack index 2.
int texture_arg(lua_State* L, LoaderContext& ctx, bool bumpmap) {
    const char* what = bumpmap ? "bump map" : "texture";
    const int texture = handle_arg(L, 2, HandleKind::texture, what);
    if (ctx.texture_is_bumpmap[texture] != bumpmap)
        throw InputError(std::string(what) + " must be " + (bumpmap ? "a bump map (from gr.bumpmap)" :
                                                                    "a texture (from gr.texture)") +
                         ", got " + describe_value(L, 2));
    return texture;
}

CallResult material_set_texture(lua_State* L, LoaderContext& ctx) {
    const int material = self_arg(L, HandleKind::material);
    expect_arguments(L, 2, 1, 1, "texture");
    ctx.scene.materials[material].texture = texture_arg(L, ctx, false);
    return CallResult::nothing();
}

CallResult material_set_bumpmap(lua_State* L, LoaderContext& ctx) {
    const int material = self_arg(L, HandleKind::material);
    expect_arguments(L, 2, 1, 1, "bump map");
    ctx.scene.materials[material].bumpmap = texture_arg(L, ctx, true);
    return CallResult::nothing();
}

/// Bytes a texel takes in the renderer's TextureImage (linear RGB and luminance, floats).
constexpr std::uint64_t texel_bytes = 16;

/// Decodes an image beside the script (once per file, whatever name it is given under), with its
/// pixels charged to the memory budget before libpng allocates them.
std::shared_ptr<const Png8> decode_image(LoaderContext& ctx, const std::string& as_written, std::string& resolved) {
    const SceneFile file = open_scene_file(ctx, as_written);
    resolved = file.path;
    const std::pair<std::uint64_t, std::uint64_t> identity{file.device, file.inode};
    if (auto cached = ctx.image_cache.find(identity); cached != ctx.image_cache.end()) return cached->second;
    const std::string bytes = read_scene_file(ctx, file, "the image file");
    const std::span<const unsigned char> encoded(reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size());
    PngReadLimits limits;
    limits.budget_name = "texture";
    const PngHeader header = read_png_header(encoded, file.shown, limits);
    // The decoded pixels now, and the renderer's linear texels and luminance later.
    const std::uint64_t texels = std::uint64_t(header.width) * std::uint64_t(header.height);
    charge_memory(ctx, static_cast<std::size_t>(header.decoded_bytes() + texels * texel_bytes), "the decoded image");
    auto image = std::make_shared<const Png8>(read_png_memory(encoded, file.shown, limits));
    release_memory(ctx, bytes.size());  // the file's bytes go; the pixels stay
    ctx.image_cache.emplace(identity, image);
    return image;
}

CallResult add_texture(lua_State* L, LoaderContext& ctx, bool bumpmap) {
    expect_arguments(L, 1, 1, 1, bumpmap ? "'file.png' or 'sinewaves'" : "'file.png' or a procedural name");
    const std::string source = string_arg(L, 1, bumpmap ? "bump map" : "texture");
    TextureDesc texture;
    if (!bumpmap && listed(procedural_textures, source)) {
        texture.source = source;
        texture.procedural = true;
    } else if (bumpmap && (source == "sinewaves" || source == "ripple")) {
        texture.source = "sinewaves";  // "ripple" is the same procedural bump map
        texture.procedural = true;
    } else {
        texture.image = decode_image(ctx, source, texture.source);
    }
    texture.where = caller_location(L);
    charge_append(ctx, ctx.scene.textures, texture.source.capacity() + texture.where.file.capacity(), "textures");
    ctx.scene.textures.push_back(std::move(texture));
    ctx.texture_is_bumpmap.push_back(bumpmap);
    return CallResult::of(HandleKind::texture, static_cast<int>(ctx.scene.textures.size()) - 1);
}

CallResult gr_texture(lua_State* L, LoaderContext& ctx) { return add_texture(L, ctx, false); }
CallResult gr_bumpmap(lua_State* L, LoaderContext& ctx) { return add_texture(L, ctx, true); }

CallResult texture_remap(lua_State* L, LoaderContext& ctx) {
    const int texture = self_arg(L, HandleKind::texture);
    expect_arguments(L, 2, 1, 1, "mode");
    const std::string mode = string_arg(L, 2, "mode");
    if (!listed(remap_modes, mode))
        throw InputError("unknown remap mode '" + mode + "' (expected cubetop, cubefront, cubebot, cyltop or conetop)");
    ctx.scene.textures[texture].remap = mode;
    return CallResult::nothing();
}

CallResult gr_light(lua_State* L, LoaderContext& ctx) {
    expect_arguments(L, 1, 3, 3, "{position}, {colour}, {c0, c1, c2}");
    LightDesc light;
    light.position = vec3_arg(L, 1, "position");
    light.colour = vec3_arg(L, 2, "colour");
    light.falloff = vec3_arg(L, 3, "falloff");
    require_non_negative(light.colour, "colour");
    require_non_negative(light.falloff, "falloff");
    if (light.falloff == glm::dvec3(0.0))
        throw InputError("falloff must not be all zero (intensity is divided by c0 + c1 d + c2 d^2)");
    light.where = caller_location(L);
    charge_append(ctx, ctx.scene.lights, light.where.file.capacity(), "lights");
    ctx.scene.lights.push_back(std::move(light));
    return CallResult::of(HandleKind::light, static_cast<int>(ctx.scene.lights.size()) - 1);
}

CallResult light_set_radius(lua_State* L, LoaderContext& ctx) {
    const int light = self_arg(L, HandleKind::light);
    expect_arguments(L, 2, 1, 1, "radius");
    const double radius = number_arg(L, 2, "radius");
    if (radius < 0.0) throw InputError("radius must not be negative, got " + format_number(radius));
    ctx.scene.lights[light].radius = radius;
    return CallResult::nothing();
}

const GrFunction shading_function_table[] = {
    {"material", guarded<gr_material>}, {"air", guarded<gr_air>},     {"texture", guarded<gr_texture>},
    {"bumpmap", guarded<gr_bumpmap>},   {"light", guarded<gr_light>},
};

const GrFunction material_method_table[] = {
    {"set_reflective", guarded<material_set_reflective>},
    {"set_ri", guarded<material_set_ri>},
    {"set_texture", guarded<material_set_texture>},
    {"set_bumpmap", guarded<material_set_bumpmap>},
};

const GrFunction texture_method_table[] = {
    {"remapt", guarded<texture_remap>},
    {"remap", guarded<texture_remap>},
};

const GrFunction light_method_table[] = {
    {"set_radius", guarded<light_set_radius>},
};

}  // namespace

std::span<const GrFunction> gr_shading_functions() { return shading_function_table; }
std::span<const GrFunction> material_methods() { return material_method_table; }
std::span<const GrFunction> texture_methods() { return texture_method_table; }
std::span<const GrFunction> light_methods() { return light_method_table; }

}  // namespace caustica::scene_lua
