// PNG files: writing with metadata (atomic and cancellable: core/io/atomic_file.h), and reading
// with limits checked before libpng allocates (for textures, tests and tools).
#pragma once

#include "core/io/atomic_file.h"
#include "core/render/image.h"

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace caustica {

/// How linear radiance becomes 8-bit values.
enum class PixelEncoding {
    clamped_linear,  ///< clamp to [0,1], x255, truncate; no gamma (the original's output, the default)
    srgb,            ///< clamp, then the sRGB transfer curve, rounded (--srgb, ours)
};

/// 8-bit value of one linear channel under an encoding: clamp to [0,1] (NaN -> 0), then
/// clamped_linear: x255, truncated (0.5 -> 127, 0.999 -> 254, 1 -> 255); srgb: the sRGB curve,
/// x255, rounded.
unsigned char encode_channel(float value, PixelEncoding encoding);

/// Writes an RGB PNG atomically: to a hidden temporary in the same folder
/// (".NAME.png.caustica-tmp-HOST-PID-N"), then rename, so a failed or interrupted write never leaves
/// a truncated image. `text` becomes tEXt chunks. `cancel`, when given, is checked before every
/// row: once it reads true the write stops, the temporary is removed and ImageWriteCancelled is
/// thrown. Temporaries left in the folder by killed runs (their process gone) are removed first.
/// Throws std::runtime_error naming the path on failure (nothing is left behind), and
/// OutputOutsideFolder when `place` confines it to the current folder and it would land elsewhere.
void write_png_atomic(const std::string& path, const Image& image, PixelEncoding encoding,
                      const std::vector<std::pair<std::string, std::string>>& text = {},
                      const std::atomic<bool>* cancel = nullptr, OutputPlace place = OutputPlace::anywhere);

/// 8-bit RGB(A) image as read from a PNG.
struct Png8 {
    int width = 0, height = 0, channels = 0;
    std::vector<unsigned char> data;  ///< row-major, `channels` bytes per pixel
    std::vector<std::pair<std::string, std::string>> text;
};

/// What a PNG may cost to read. The header is checked against the sizes before libpng allocates
/// anything for the pixels; the chunk limits are given to libpng (png_set_chunk_malloc_max,
/// png_set_chunk_cache_max) and `max_width`/`max_height` to png_set_user_limits.
struct PngReadLimits {
    std::uint32_t max_width = 1u << 16;         ///< pixels per row
    std::uint32_t max_height = 1u << 16;        ///< rows
    std::uint64_t max_pixels = 1ull << 26;      ///< width x height (67108864: 256 MiB as 8-bit RGBA)
    std::size_t max_chunk_bytes = 8u << 20;     ///< one ancillary chunk, decompressed text included
    std::uint32_t max_ancillary_chunks = 1000;  ///< text and other ancillary chunks kept
    std::uint64_t max_file_bytes = 512ull << 20;  ///< read_png(path): the file's size on disk
    const char* budget_name = "image";          ///< in messages: "the 67108864-pixel image budget"
};

/// What the IHDR chunk of a PNG declares, and what read_png_memory would make of it.
struct PngHeader {
    int width = 0, height = 0;
    int bit_depth = 0, colour_type = 0;
    bool interlaced = false;
    int channels = 0;  ///< channels of the decoded Png8: 1 gray, 2 gray+alpha, 3 RGB, 4 RGBA

    /// Bytes of Png8::data once decoded.
    std::uint64_t decoded_bytes() const { return std::uint64_t(width) * std::uint64_t(height) * std::uint64_t(channels); }
};

/// Reads the header of a PNG held in memory and checks the chunk structure (every chunk fits in
/// the bytes given; IHDR first and valid) and the size against `limits`, without decoding
/// anything: for charging a memory budget before read_png_memory. Throws std::runtime_error
/// "DISPLAY_NAME: reason" (e.g. "tex.png: 16384 x 16384 pixels is more than the 67108864-pixel
/// texture budget").
PngHeader read_png_header(std::span<const unsigned char> bytes, const std::string& display_name,
                          const PngReadLimits& limits = {});

/// Decodes a PNG held in memory, of any bit depth and colour type, as 8-bit gray, gray+alpha,
/// RGB or RGBA, after read_png_header's checks: palettes become RGB(A), gray of 1, 2 or 4 bits
/// is scaled to 8 bits, 16-bit samples are scaled to the nearest 8-bit value. Peak memory is the decoded image plus libpng's
/// row buffers and at most `limits.max_chunk_bytes` per ancillary chunk. Throws
/// std::runtime_error "DISPLAY_NAME: reason".
Png8 read_png_memory(std::span<const unsigned char> bytes, const std::string& display_name,
                     const PngReadLimits& limits = {});

/// Reads a PNG file (a regular file of at most `limits.max_file_bytes`) with read_png_memory.
/// Throws std::runtime_error naming the path: "cannot open 'PATH': reason", "'PATH' is not a
/// PNG file" or "cannot read 'PATH': reason".
Png8 read_png(const std::string& path, const PngReadLimits& limits = {});

}  // namespace caustica
