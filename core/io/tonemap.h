// Display mapping of linear radiance: exposure in stops, then a tone curve onto [0, 1].
// Used when an 8-bit PNG is written (the batch command and the preview's save); the HDR formats
// (EXR, PFM) take the exposure only and keep the linear values unclamped.
#pragma once

#include <glm/glm.hpp>

#include <optional>
#include <string>

namespace caustica {

/// How linear values above 1 reach the [0, 1] of an 8-bit image.
enum class Tonemap {
    clamp,     ///< min(max(x, 0), 1): the original's output, the default
    reinhard,  ///< x / (1 + x), per channel (Reinhard et al. 2002, the simple global operator)
    filmic,    ///< Narkowicz's rational fit of the ACES reference tone curve, per channel, clamped
};

/// 2^stops: the factor an exposure of `stops` applies to linear values.
float exposure_scale(float exposure_stops);

/// One channel: x' = x * 2^stops (NaN and negatives -> 0), then
///   clamp:    min(x', 1)
///   reinhard: x' / (1 + x')
///   filmic:   min(1, x' (2.51 x' + 0.03) / (x' (2.43 x' + 0.59) + 0.14))
/// Every curve maps 0 to 0, is non-decreasing, and stays in [0, 1]. With clamp and 0 stops the
/// result is exactly the clamped input, so the default output is bit for bit the original's.
float tonemap_channel(float linear, Tonemap op, float exposure_stops);

/// tonemap_channel on each of R, G, B (per channel: hue may shift for bright saturated colours,
/// as with any per-channel curve; luminance-based mapping would exceed 1 on saturated colours).
glm::vec3 tonemap(glm::vec3 linear, Tonemap op, float exposure_stops);

/// "clamp", "reinhard", "filmic".
const char* tonemap_name(Tonemap op);

/// The Tonemap named `name` (as tonemap_name writes it), or nullopt.
std::optional<Tonemap> parse_tonemap(const std::string& name);

}  // namespace caustica
