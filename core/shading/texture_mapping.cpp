#include "core/shading/texture_mapping.h"

namespace caustica {
namespace {

/// Whether uv lies in the window [lo, hi], bounds included (false for NaN).
bool inside(glm::vec2 uv, glm::vec2 lo, glm::vec2 hi) {
    return uv.x >= lo.x && uv.x <= hi.x && uv.y >= lo.y && uv.y <= hi.y;
}

}  // namespace

std::optional<TextureRemap> parse_texture_remap(const std::string& name) {
    if (name.empty()) return TextureRemap::none;
    if (name == "cubetop") return TextureRemap::cube_top;
    if (name == "cubefront") return TextureRemap::cube_front;
    if (name == "cubebot") return TextureRemap::cube_bottom;
    if (name == "cyltop") return TextureRemap::cylinder_top;
    if (name == "conetop") return TextureRemap::cone_top;
    return std::nullopt;
}

TextureLookup remap_uv(glm::vec2 uv, TextureRemap remap) {
    // The factors are written as the original's (4u - 1, 3v - 1, ...), not as (uv - lo) / size,
    // so that a window's edges land exactly on 0 and 1.
    switch (remap) {
        case TextureRemap::none: return {true, uv};
        case TextureRemap::cube_top:
            if (!inside(uv, {0.25f, 1.0f / 3.0f}, {0.5f, 2.0f / 3.0f})) return {};
            return {true, {4.0f * uv.x - 1.0f, 3.0f * uv.y - 1.0f}};
        case TextureRemap::cube_front:
            if (!inside(uv, {0.25f, 0.0f}, {0.5f, 1.0f / 3.0f})) return {};
            return {true, {4.0f * uv.x - 1.0f, 3.0f * uv.y}};
        case TextureRemap::cube_bottom:
            if (!inside(uv, {0.75f, 1.0f / 3.0f}, {1.0f, 2.0f / 3.0f})) return {};
            return {true, {4.0f * uv.x - 3.0f, 3.0f * uv.y - 1.0f}};
        case TextureRemap::cylinder_top:
            if (!inside(uv, {0.5f, 0.5f}, {1.0f, 1.0f})) return {};
            return {true, {2.0f * uv.x - 1.0f, 2.0f * uv.y - 1.0f}};
        case TextureRemap::cone_top:
            if (!(uv.y >= 0.5f && uv.y <= 1.0f)) return {};
            return {true, {uv.x, 2.0f * uv.y - 1.0f}};
    }
    return {};
}

TextureLookup texture_lookup(const SurfaceHit& hit, TextureRemap remap) {
    const glm::vec2 uv = hit.shape_kind < 0 ? glm::vec2(0.0f) : hit.uv;  // meshes have no uv
    return remap_uv(uv, remap);
}

}  // namespace caustica
