// Fuzz target: PNG bytes -> Png8 or std::runtime_error (textures, core/io/png_io.h), with the
// default PngReadLimits: the header is checked before libpng allocates for the pixels.
#include "fuzz/fuzz_targets.h"

#include "core/io/png_io.h"

#include <stdexcept>
#include <string>

namespace caustica::fuzz::png_reader {

int fuzz_one(const std::uint8_t* data, std::size_t size) {
    const PngReadLimits limits;
    const std::span<const unsigned char> bytes(data, size);
    PngHeader header;
    try {
        header = read_png_header(bytes, "fuzz.png", limits);
    } catch (const std::runtime_error&) {
        return 0;
    }
    fuzz_require(header.width > 0 && header.height > 0, "a header that passed has a size");
    fuzz_require(static_cast<std::uint64_t>(header.width) <= limits.max_width &&
                     static_cast<std::uint64_t>(header.height) <= limits.max_height &&
                     static_cast<std::uint64_t>(header.width) * header.height <= limits.max_pixels,
                 "a header that passed is within the limits");
    Png8 png;
    try {
        png = read_png_memory(bytes, "fuzz.png", limits);
    } catch (const std::runtime_error&) {
        return 0;
    }
    fuzz_require(png.width == header.width && png.height == header.height && png.channels == header.channels,
                 "the image is what the header declared");
    fuzz_require(png.channels >= 1 && png.channels <= 4, "1 to 4 channels");
    fuzz_require(png.data.size() == header.decoded_bytes(), "width x height x channels bytes");
    fuzz_require(png.text.size() <= limits.max_ancillary_chunks, "text chunks within the limit");
    return 0;
}

}  // namespace caustica::fuzz::png_reader
