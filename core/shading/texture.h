// Textures (drive kd) and bump maps (perturb the normal) of a scene's materials.
#pragma once

#include "core/geometry/ray.h"
#include "core/scene/scene_desc.h"

#include <memory>
#include <vector>

namespace caustica {

/// The textures and bump maps of one scene description, loaded once (images cached by path).
class TextureSet {
public:
    /// Loads every texture the materials use. Throws InputError naming the gr.texture/gr.bumpmap
    /// line when an image cannot be read.
    explicit TextureSet(const SceneDesc& scene);
    ~TextureSet();

    /// The diffuse colour at a hit: `kd` itself, or the material's texture there (black outside
    /// the texture's remap window: the texture replaces kd everywhere).
    glm::vec3 diffuse(int material, const SurfaceHit& hit, const glm::vec3& kd) const;

    /// The shading normal at a hit: `normal` itself, or perturbed by the material's bump map.
    /// `normal` is unit length and may face either side; the result faces the same side.
    glm::vec3 shading_normal(int material, const SurfaceHit& hit, const glm::vec3& normal) const;

    /// Whether any material has a texture or a bump map (lets the integrator skip the lookups).
    bool empty() const { return empty_; }

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
    bool empty_ = true;
};

}  // namespace caustica
