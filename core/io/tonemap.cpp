#include "core/io/tonemap.h"

#include <cmath>

namespace caustica {

float exposure_scale(float exposure_stops) { return std::exp2(exposure_stops); }

float tonemap_channel(float linear, Tonemap op, float exposure_stops) {
    // exposure 0 multiplies by nothing at all (not even by 1.0f, which would be exact anyway), so
    // the default path is the original clamping untouched.
    float x = exposure_stops == 0.0f ? linear : linear * exposure_scale(exposure_stops);
    if (!(x > 0.0f)) return 0.0f;  // NaN, negatives and zero
    switch (op) {
        case Tonemap::clamp: return x < 1.0f ? x : 1.0f;
        case Tonemap::reinhard:
            // x / (1 + x) tends to 1 but rounds to it only for huge x; infinity -> 1.
            return std::isinf(x) ? 1.0f : x / (1.0f + x);
        case Tonemap::filmic: {
            // Narkowicz (2016), "ACES Filmic Tone Mapping Curve": a rational fit of the ACES RRT+ODT.
            // Its derivative's numerator, 1.408 x^2 + 0.7028 x + 0.0042, is positive: increasing.
            // It reaches 1 near x = 7.24 and goes on to 2.51/2.43; clamped there.
            if (x >= 8.0f) return 1.0f;  // also keeps infinity out of the ratio
            const float y = x * (2.51f * x + 0.03f) / (x * (2.43f * x + 0.59f) + 0.14f);
            return y < 1.0f ? y : 1.0f;
        }
    }
    return 0.0f;
}

glm::vec3 tonemap(glm::vec3 linear, Tonemap op, float exposure_stops) {
    return {tonemap_channel(linear.x, op, exposure_stops), tonemap_channel(linear.y, op, exposure_stops),
            tonemap_channel(linear.z, op, exposure_stops)};
}

const char* tonemap_name(Tonemap op) {
    switch (op) {
        case Tonemap::clamp: return "clamp";
        case Tonemap::reinhard: return "reinhard";
        case Tonemap::filmic: return "filmic";
    }
    return "clamp";
}

std::optional<Tonemap> parse_tonemap(const std::string& name) {
    for (Tonemap op : {Tonemap::clamp, Tonemap::reinhard, Tonemap::filmic})
        if (name == tonemap_name(op)) return op;
    return std::nullopt;
}

}  // namespace caustica
