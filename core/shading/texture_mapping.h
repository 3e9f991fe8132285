// Where a surface hit looks up a texture or bump map: the default parametrisation of each
// primitive (the cube's 3x4 unwrap) and the seed's remaps (tex:remapt, bump:remap).
// docs/TEXTURES.md draws every layout.
#pragma once

#include "core/geometry/ray.h"
#include "core/shading/texture_image.h"

#include <optional>
#include <string>

namespace caustica {

/// A texture's remap mode (TextureDesc::remap).
enum class TextureRemap {
    none,          ///< the primitive's default parametrisation
    cube_top,      ///< the whole image on a box's +y face only
    cube_front,    ///< the whole image on a box's +z face only
    cube_bottom,   ///< the whole image on a box's -y face only
    cylinder_top,  ///< the whole image on a cylinder's top cap only (a planar projection from above)
    cone_top,      ///< a planar projection from above onto a cone's side, image centre at the apex
};

/// The remap named by a TextureDesc ("" = none), or nothing for an unknown name.
std::optional<TextureRemap> parse_texture_remap(const std::string& name);

/// The lookup a hit makes in texture space.
struct TextureLookup {
    bool covered = false;   ///< false: the remap leaves this face untextured (kd, no bump)
    glm::vec2 uv{0.0f};     ///< texture coordinates (v = 0 at the image's top row)
    /// d(uv)/d(hit.uv): column 0 is the derivative along hit.uv.x, column 1 along hit.uv.y.
    /// Turns texture-space gradients into the hit's parametrisation, where dpdu/dpdv live.
    glm::mat2 jacobian{1.0f};
    TextureWindow window;   ///< region the lookup stays in (a cell of the cube unwrap)
};

/// The texture lookup for a hit under a remap. Remaps meant for another primitive kind (a cube
/// remap on a sphere, ...) are ignored: the default parametrisation applies.
TextureLookup texture_lookup(const SurfaceHit& hit, TextureRemap remap);

}  // namespace caustica
