#include "core/shading/texture.h"

#include "core/scene/source_location.h"
#include "core/shading/texture_bump.h"
#include "core/shading/texture_image.h"
#include "core/shading/texture_mapping.h"
#include "core/shading/texture_procedural.h"

#include <string>

namespace caustica {
namespace {

/// How far a PNG bump map tilts the normal: n' = normalise(n + 5 g_x U + 5 g_y V), g in intensity
/// per pixel (docs/TEXTURES.md, "Bump maps").
constexpr float bump_image_strength = 5.0f;

/// One texture or bump map of the scene, ready to be looked up.
struct Source {
    enum class Kind { image, checker, ripple };
    Kind kind = Kind::image;
    std::shared_ptr<const TextureImage> image;
    glm::vec3 checker_colour{0.0f};
    TextureRemap remap = TextureRemap::none;
};

/// The reason in a read_png message, without the path it repeats ("cannot open '/a.png': No such
/// file" -> "No such file"; "'/a.png' is not a PNG file" -> "not a PNG file").
std::string read_failure_reason(const std::string& message, const std::string& path) {
    const std::string quoted = "'" + path + "'";
    const std::size_t at = message.find(quoted);
    if (at == std::string::npos) return message;
    const std::string rest = message.substr(at + quoted.size());
    if (rest.starts_with(": ")) return rest.substr(2);
    if (rest.starts_with(" is ")) return rest.substr(4);
    return message;
}

/// Builds the source for a TextureDesc used as a texture (`bumpmap` false) or a bump map.
Source make_source(const TextureDesc& desc, bool bumpmap) {
    const std::string call = bumpmap ? "gr.bumpmap" : "gr.texture";
    Source source;
    const std::optional<TextureRemap> remap = parse_texture_remap(desc.remap);
    if (!remap)
        throw InputError(desc.where, call + ": unknown remap mode '" + desc.remap +
                                         "' (expected cubetop, cubefront, cubebot, cyltop or conetop)");
    source.remap = *remap;
    if (!desc.procedural) {
        try {
            source.image = desc.image ? texture_image_from(desc.image) : load_texture_image(desc.source);
        } catch (const std::exception& e) {
            throw InputError(desc.where, call + ": cannot read '" + desc.source + "': " +
                                             read_failure_reason(e.what(), desc.source));
        }
        return source;
    }
    if (bumpmap) {
        if (desc.source != "sinewaves" && desc.source != "ripple")
            throw InputError(desc.where, call + ": unknown procedural bump map '" + desc.source +
                                             "' (expected sinewaves or ripple)");
        source.kind = Source::Kind::ripple;
        return source;
    }
    const std::optional<glm::vec3> colour = checker_colour(desc.source);
    if (!colour)
        throw InputError(desc.where, call + ": unknown procedural texture '" + desc.source +
                                         "' (expected redcheck, greencheck, bluecheck or whitecheck)");
    source.kind = Source::Kind::checker;
    source.checker_colour = *colour;
    return source;
}

}  // namespace

struct TextureSet::Impl {
    /// Sources per SceneDesc::textures index, built on first use in each role.
    std::vector<std::unique_ptr<Source>> textures, bumpmaps;
    /// What each material (by index) uses; null = nothing.
    struct Binding {
        const Source* texture = nullptr;
        const Source* bumpmap = nullptr;
    };
    std::vector<Binding> materials;

    const Source* use(const SceneDesc& scene, const MaterialDesc& material, int index, bool bumpmap) {
        if (index < 0) return nullptr;
        if (index >= static_cast<int>(scene.textures.size()))
            throw InputError(material.where, std::string("material refers to ") +
                                                 (bumpmap ? "bump map" : "texture") + " #" +
                                                 std::to_string(index) + ", which does not exist");
        auto& slot = (bumpmap ? bumpmaps : textures)[index];
        if (!slot) slot = std::make_unique<Source>(make_source(scene.textures[index], bumpmap));
        return slot.get();
    }

    const Binding* binding(int material) const {
        if (material < 0 || material >= static_cast<int>(materials.size())) return nullptr;
        return &materials[material];
    }
};

TextureSet::TextureSet(const SceneDesc& scene) : impl_(std::make_unique<Impl>()) {
    impl_->textures.resize(scene.textures.size());
    impl_->bumpmaps.resize(scene.textures.size());
    for (const MaterialDesc& material : scene.materials) {
        Impl::Binding binding;
        binding.texture = impl_->use(scene, material, material.texture, false);
        binding.bumpmap = impl_->use(scene, material, material.bumpmap, true);
        if (binding.texture || binding.bumpmap) empty_ = false;
        impl_->materials.push_back(binding);
    }
}

TextureSet::~TextureSet() = default;

glm::vec3 TextureSet::diffuse(int material, const SurfaceHit& hit, const glm::vec3& kd) const {
    const Impl::Binding* binding = impl_->binding(material);
    if (!binding || !binding->texture) return kd;
    const Source& source = *binding->texture;
    const TextureLookup lookup = texture_lookup(hit, source.remap);
    if (!lookup.covered) return glm::vec3(0.0f);  // outside a remap's window: black, not kd
    if (source.kind == Source::Kind::checker) return checker(source.checker_colour, lookup.uv);
    return source.image->colour(lookup.uv);
}

glm::vec3 TextureSet::shading_normal(int material, const SurfaceHit& hit, const glm::vec3& normal) const {
    const Impl::Binding* binding = impl_->binding(material);
    if (!binding || !binding->bumpmap) return normal;
    if (hit.shape_kind < 0) return normal;  // meshes have no tangents (docs/TEXTURES.md)
    const Source& source = *binding->bumpmap;
    const TextureLookup lookup = texture_lookup(hit, source.remap);
    if (!lookup.covered) return normal;
    const glm::vec2 perturbation = source.kind == Source::Kind::ripple
                                       ? ripple_perturbation(lookup.uv)
                                       : bump_image_strength * source.image->bump_gradient(lookup.uv);
    return bump_normal(hit, normal, perturbation);
}

}  // namespace caustica
