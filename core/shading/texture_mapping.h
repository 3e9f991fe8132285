// Where a surface hit looks up a texture or bump map: the primitive's uv (shape_uv; meshes have
// none) and the remaps (tex:remapt, bump:remap), which keep one uv window and stretch it to the
// whole image. docs/TEXTURES.md draws every layout ("Primitives: uv and bump tangents", "Remaps").
#pragma once

#include "core/geometry/ray.h"

#include <optional>
#include <string>

namespace caustica {

/// A texture's remap mode (TextureDesc::remap).
enum class TextureRemap {
    none,          ///< the primitive's uv as it is
    cube_top,      ///< u in [1/4, 1/2], v in [1/3, 2/3] -> (4u - 1, 3v - 1): a cube's +y face
    cube_front,    ///< u in [1/4, 1/2], v in [0, 1/3] -> (4u - 1, 3v): a cube's +z face
    cube_bottom,   ///< u in [3/4, 1], v in [1/3, 2/3] -> (4u - 3, 3v - 1): a cube's -y face
    cylinder_top,  ///< u in [1/2, 1], v in [1/2, 1] -> (2u - 1, 2v - 1): a cylinder's top cap
    cone_top,      ///< v in [1/2, 1] -> (u, 2v - 1): a cone's flat base
};

/// The remap named by a TextureDesc ("" = none), or nothing for an unknown name.
std::optional<TextureRemap> parse_texture_remap(const std::string& name);

/// The lookup a hit makes in texture space.
struct TextureLookup {
    bool covered = false;  ///< false: outside the remap's window (texture black, no bump)
    glm::vec2 uv{0.0f};    ///< texture coordinates (v = 1 at the image's top row)
};

/// A uv under a remap: the stretched window, or not covered when uv lies outside it (bounds
/// inclusive). The window is a window of uv, whatever the primitive.
TextureLookup remap_uv(glm::vec2 uv, TextureRemap remap);

/// The texture lookup for a hit: its uv (a mesh has none: (0, 0)) under the remap.
TextureLookup texture_lookup(const SurfaceHit& hit, TextureRemap remap);

}  // namespace caustica
