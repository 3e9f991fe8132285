#include "ui/view_transform.h"

#include <cmath>

namespace caustica::ui {

int tone_curve_index(Tonemap op) {
    switch (op) {
        case Tonemap::clamp: return 0;
        case Tonemap::reinhard: return 1;
        case Tonemap::filmic: return 2;
    }
    return 0;
}

glm::vec3 tonemap_weights(Tonemap op) {
    switch (op) {
        case Tonemap::clamp: return {1.0f, 0.0f, 0.0f};
        case Tonemap::reinhard: return {0.0f, 1.0f, 0.0f};
        case Tonemap::filmic: return {0.0f, 0.0f, 1.0f};
    }
    return {1.0f, 0.0f, 0.0f};
}

namespace {

/// One channel of shaders/image.frag's tone(): keep the two in step.
float shader_tone(float x, glm::vec3 weights) {
    const float clamped = std::fmin(x, 1.0f);
    const float reinhard = x / (1.0f + x);
    const float f = std::fmin(x, 8.0f);
    const float filmic = std::fmin(f * (2.51f * f + 0.03f) / (f * (2.43f * f + 0.59f) + 0.14f), 1.0f);
    return weights.x * clamped + weights.y * reinhard + weights.z * filmic;
}

/// One channel of the shaders' encoding: the sRGB curve, or x255 truncated as the batch PNG.
float shader_encode(float c, bool srgb) {
    if (!srgb) return std::floor(c * 255.0f) / 255.0f;
    return c < 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}

}  // namespace

glm::vec3 display_value(glm::vec3 linear, const ViewTransform& transform) {
    const float exposure = std::exp2(transform.exposure_stops);  // ImageView's u_exposure
    const glm::vec3 weights = tonemap_weights(transform.tonemap);
    glm::vec3 out;
    for (int i = 0; i < 3; ++i) {
        const float x = std::fmax(linear[i] * exposure, 0.0f);
        out[i] = shader_encode(shader_tone(x, weights), transform.srgb);
    }
    return out;
}

}  // namespace caustica::ui
