// OpenEXR reading and writing behind image_io.h (only this file's .cpp includes OpenEXR).
#pragma once

#include "core/io/image_io.h"

#include <span>

namespace caustica {

/// Whether `bytes` start with the OpenEXR magic number (76 2f 31 01).
bool has_exr_magic(std::span<const unsigned char> bytes);

/// Reads an OpenEXR file's first part (scan lines or tiles) as float RGB: R, G, B, or Y copied to
/// all three when there is no colour; missing channels read 0. The data window is checked against
/// `limits` (and OpenEXR's own header checks) before any pixel is allocated. Throws
/// InputError("PATH: reason").
Image read_exr_image(const std::string& path, const ImageReadLimits& limits);

}  // namespace caustica
