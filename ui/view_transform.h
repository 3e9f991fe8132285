// The viewport's view transform: the exposure and tone curve of `caustica render --exposure E
// --tonemap X` (core/io/tonemap.h), then the 8-bit encoding of the batch PNG or the sRGB display
// curve. shaders/image.frag and shaders/image_compare.frag apply it on the GPU; display_value()
// is the same formula on the CPU, so that a test can hold the shader to core/io/tonemap
// (docs/PREVIEW.md, "View transform").
#pragma once

#include "core/io/tonemap.h"

#include <glm/glm.hpp>

namespace caustica::ui {

/// What the viewport does to the linear image: exposure, curve, encoding.
struct ViewTransform {
    Tonemap tonemap = Tonemap::clamp;
    float exposure_stops = 0.0f;  ///< the job's --exposure plus the display's exposure
    bool srgb = false;            ///< sRGB display curve (else x255 truncated, as the batch PNG)

    bool operator==(const ViewTransform&) const = default;
};

/// image_compare.frag's u_tonemap: one weight per curve (clamp, Reinhard, filmic), 1 for `op`, 0
/// for the others. It computes the three curves and weights them: no branch for llvmpipe to run.
glm::vec3 tonemap_weights(Tonemap op);
/// The TONE_CURVE of shaders/image.frag that draws `op`: 0 clamp, 1 Reinhard, 2 filmic.
int tone_curve_index(Tonemap op);

/// The value the shaders display for a linear colour (each channel in [0, 1]), as the shaders
/// compute it: x = max(linear 2^stops, 0); clamp min(x, 1), Reinhard x / (1 + x), filmic
/// min(1, f (2.51 f + 0.03) / (f (2.43 f + 0.59) + 0.14)) with f = min(x, 8); then floor(255 c) / 255,
/// or the sRGB curve.
glm::vec3 display_value(glm::vec3 linear, const ViewTransform& transform);

}  // namespace caustica::ui
