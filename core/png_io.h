// PNG files: atomic writing with metadata, and reading (for tests and textures).
#pragma once

#include "core/image.h"

#include <string>
#include <utility>
#include <vector>

namespace caustica {

/// How linear radiance becomes 8-bit values.
enum class PixelEncoding {
    clamped_linear,  ///< clamp to [0,1], no gamma (the seed's behaviour, the default)
    srgb,            ///< clamp, then the sRGB transfer curve (--srgb)
};

/// 8-bit value of one linear channel under an encoding.
unsigned char encode_channel(float value, PixelEncoding encoding);

/// Writes an RGB PNG atomically: to a temporary file in the same folder, then rename, so a
/// failed or interrupted write never leaves a truncated image. `text` becomes tEXt chunks.
/// Throws std::runtime_error naming the path on failure (nothing is left behind).
void write_png_atomic(const std::string& path, const Image& image, PixelEncoding encoding,
                      const std::vector<std::pair<std::string, std::string>>& text = {});

/// 8-bit RGB(A) image as read from a PNG.
struct Png8 {
    int width = 0, height = 0, channels = 0;
    std::vector<unsigned char> data;  ///< row-major, `channels` bytes per pixel
    std::vector<std::pair<std::string, std::string>> text;
};

/// Reads a PNG of any bit depth/colour type as 8-bit gray, gray+alpha, RGB or RGBA.
/// Throws std::runtime_error naming the path on failure.
Png8 read_png(const std::string& path);

}  // namespace caustica
