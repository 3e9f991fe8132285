// Image files by format: PNG (8-bit, display), OpenEXR and PFM (linear float, high dynamic range).
// Reading for tools, tests and the preview's comparisons; writing atomically like write_png_atomic
// (hidden temporary + rename, cancellable, temporaries removed by signal handlers and later runs).
#pragma once

#include "core/io/png_io.h"
#include "core/io/tonemap.h"
#include "core/render/image.h"

#include <atomic>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace caustica {

enum class ImageFormat { png, exr, pfm };

/// The format a file name asks for, by its extension (".png", ".exr", ".pfm", any case), or nullopt.
std::optional<ImageFormat> image_format_of(const std::string& path);

/// "png", "exr", "pfm".
const char* image_format_name(ImageFormat format);

/// What an image file may cost to read: checked against the header before the pixels are allocated.
struct ImageReadLimits {
    std::uint64_t max_pixels = 1ull << 26;   ///< width x height (67108864: 768 MiB as float RGB)
    std::uint32_t max_side = 1u << 16;       ///< width and height each
};

/// Reads a PNG (8/16-bit: values/255 as linear, or sRGB-decoded if `srgb_png`), EXR or PFM into a
/// float RGB Image (gray is copied to R, G, B; alpha is dropped); the format comes from the file's
/// contents, not its name. Throws InputError("FILE: reason") for missing, unreadable, corrupt,
/// truncated or too large files; memory stays bounded by `limits` whatever the file declares.
Image read_image_file(const std::string& path, bool srgb_png = false, const ImageReadLimits& limits = {});

/// OpenEXR channel type of a written file.
enum class ExrPixel {
    half,     ///< 16-bit float: 11 significant bits (relative error <= 2^-11), max 65504
    float32,  ///< 32-bit float: the renderer's values exactly
};

/// How a linear image becomes a file. `exposure_stops` scales every format (by 2^stops); the
/// tone curve and `encoding` apply to PNG only, EXR and PFM stay linear and unclamped.
struct ImageWriteSettings {
    PixelEncoding encoding = PixelEncoding::clamped_linear;  ///< PNG
    Tonemap tonemap = Tonemap::clamp;                        ///< PNG
    float exposure_stops = 0.0f;                             ///< all formats
    ExrPixel exr_pixel = ExrPixel::half;                     ///< EXR
};

/// Metadata: (key, value) pairs; PNG tEXt chunks, EXR string attributes. PFM has no room for it.
using ImageMetadata = std::vector<std::pair<std::string, std::string>>;

/// Writes `image` to `path` in the format of its extension (png, exr or pfm) atomically, as
/// write_png_atomic does. Throws std::runtime_error naming the path for an unknown extension or a
/// failed write, ImageWriteCancelled when `cancel` was raised (nothing is left behind),
/// OutputOutsideFolder when `place` confines it to the current folder and it would land elsewhere.
void write_image_atomic(const std::string& path, const Image& image, const ImageWriteSettings& settings,
                        const ImageMetadata& metadata = {}, const std::atomic<bool>* cancel = nullptr,
                        OutputPlace place = OutputPlace::anywhere);

/// PFM ("PF", 3 channels, little-endian, rows bottom to top as the format says), atomically.
void write_pfm_atomic(const std::string& path, const Image& image, const std::atomic<bool>* cancel = nullptr,
                      OutputPlace place = OutputPlace::anywhere);

/// OpenEXR (scan lines, ZIP compression, channels R G B of `pixel` type, `metadata` as string
/// attributes), atomically.
void write_exr_atomic(const std::string& path, const Image& image, ExrPixel pixel, const ImageMetadata& metadata = {},
                      const std::atomic<bool>* cancel = nullptr, OutputPlace place = OutputPlace::anywhere);

/// One channel of an OpenEXR file: component `component` (0, 1, 2) of `image`, or `constant`
/// everywhere when `image` is null (an alpha of 1).
struct ExrChannel {
    std::string name;  ///< "R", "caustic.G", "normal.X", ...
    const Image* image = nullptr;
    int component = 0;
    float constant = 0.0f;
};

/// OpenEXR with the given channels, all `width` x `height` and of `pixel` type (scan lines, ZIP
/// compression, `metadata` as string attributes), atomically as write_exr_atomic. Names with a
/// dot make a multilayer file ("caustic.R": layer caustic, channel R), as Cycles and LuxCore
/// write their passes. Values are written as they are (no exposure).
void write_exr_channels_atomic(const std::string& path, int width, int height, const std::vector<ExrChannel>& channels,
                               ExrPixel pixel, const ImageMetadata& metadata = {},
                               const std::atomic<bool>* cancel = nullptr, OutputPlace place = OutputPlace::anywhere);

/// The image a write would store: `image` x 2^exposure, then for PNG the tone curve (whose output
/// write_png_atomic then encodes). With the defaults the result is `image` itself.
Image prepare_for_format(const Image& image, ImageFormat format, const ImageWriteSettings& settings);

/// The string attributes of an OpenEXR file (for tests and tools). Throws InputError("FILE: ...").
ImageMetadata read_exr_metadata(const std::string& path);

}  // namespace caustica
