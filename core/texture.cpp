#include "core/texture.h"

namespace caustica {

struct TextureSet::Impl {};

TextureSet::TextureSet(const SceneDesc&) : impl_(std::make_unique<Impl>()) {}
TextureSet::~TextureSet() = default;

glm::vec3 TextureSet::diffuse(int, const SurfaceHit&, const glm::vec3& kd) const { return kd; }

glm::vec3 TextureSet::shading_normal(int, const SurfaceHit&, const glm::vec3& normal) const { return normal; }

}  // namespace caustica
