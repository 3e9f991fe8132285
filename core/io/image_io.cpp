#include "core/io/image_io.h"

#include "core/io/exr_io.h"
#include "core/io/regular_file.h"
#include "core/scene/source_location.h"

#include <algorithm>
#include <bit>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <sys/stat.h>
#include <unistd.h>

namespace caustica {
namespace {

using io::Descriptor;
using io::open_regular;
using io::read_at;

// ---------------------------------------------------------------------------------------------
// PFM: "PF" (RGB) or "Pf" (gray), white space, width, white space, height, white space, scale
// (negative: little-endian floats, positive: big-endian; its magnitude is ignored here, as by most
// readers), one white-space byte, then the rows from the bottom of the image to the top. Writers on
// Windows may end the scale with "\r\n": that pair is taken as the separator only when the bytes
// after it are exactly the pixel data (otherwise the "\n" is the data's first byte, as the format
// says).

/// The most header text read (any white space between the fields is allowed up to this).
constexpr std::size_t max_pfm_header = 4096;

struct PfmHeader {
    int width = 0, height = 0, channels = 0;
    bool little_endian = true;
    std::size_t data_offset = 0;
    bool crlf = false;  ///< the scale ends with "\r\n" (see above)
};

bool is_pfm_space(unsigned char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

/// `size` bytes of the file's start; `whole` when they are the whole file.
PfmHeader parse_pfm_header(const std::string& path, const unsigned char* bytes, std::size_t size, bool whole,
                           const ImageReadLimits& limits) {
    auto fail = [&](const std::string& why) -> InputError { return InputError(path + ": " + why); };
    if (size < 2 || bytes[0] != 'P' || (bytes[1] != 'F' && bytes[1] != 'f')) throw fail("not a PFM file");
    PfmHeader h;
    h.channels = bytes[1] == 'F' ? 3 : 1;
    std::size_t at = 2;
    auto token = [&](const char* what) {
        std::size_t spaces = 0;
        while (at < size && is_pfm_space(bytes[at])) ++at, ++spaces;
        if (spaces == 0) throw fail(std::string("malformed PFM header: no white space before the ") + what);
        const std::size_t start = at;
        while (at < size && !is_pfm_space(bytes[at])) ++at;
        if ((at == start || at == size) && !whole)
            throw fail("the PFM header is longer than " + std::to_string(max_pfm_header) + " bytes");
        if (at == start || at == size) throw fail(std::string("truncated PFM header: no ") + what);
        return std::string(reinterpret_cast<const char*>(bytes + start), at - start);
    };
    auto dimension = [&](const char* what) {
        const std::string t = token(what);
        if (t.size() > 9 || !std::all_of(t.begin(), t.end(), [](char c) { return std::isdigit(static_cast<unsigned char>(c)); }))
            throw fail(std::string("PFM header: the ") + what + " '" + t.substr(0, 20) + "' is not a number of pixels");
        const long v = std::stol(t);
        if (v <= 0) throw fail(std::string("PFM header: the ") + what + " is 0");
        return static_cast<int>(v);
    };
    h.width = dimension("width");
    h.height = dimension("height");
    const std::string scale_text = token("scale");
    char* end = nullptr;
    errno = 0;
    const double scale = scale_text.size() < 40 ? std::strtod(scale_text.c_str(), &end) : 0.0;
    if (scale_text.size() >= 40 || end != scale_text.c_str() + scale_text.size() || !std::isfinite(scale) || scale == 0.0)
        throw fail("PFM header: the scale '" + scale_text.substr(0, 20) + "' is not a non-zero number");
    h.little_endian = scale < 0.0;
    h.data_offset = at + 1;  // exactly one white-space byte ends the header
    h.crlf = bytes[at] == '\r' && at + 1 < size && bytes[at + 1] == '\n';
    const std::string dims = std::to_string(h.width) + " x " + std::to_string(h.height) + " pixels";
    if (std::uint64_t(h.width) * std::uint64_t(h.height) > limits.max_pixels)
        throw fail(dims + " is more than the " + std::to_string(limits.max_pixels) + "-pixel image budget");
    if (std::uint64_t(h.width) > limits.max_side || std::uint64_t(h.height) > limits.max_side)
        throw fail(dims + ": a side is more than the " + std::to_string(limits.max_side) + " allowed");
    return h;
}

Image read_pfm(const std::string& path, const ImageReadLimits& limits) {
    Descriptor d;
    const std::uint64_t file_size = open_regular(path, d);
    std::vector<unsigned char> head(static_cast<std::size_t>(std::min<std::uint64_t>(file_size, max_pfm_header)));
    const std::size_t got = read_at(d.fd, head.data(), head.size(), 0);
    PfmHeader h = parse_pfm_header(path, head.data(), got, got == file_size, limits);
    const std::size_t row_floats = std::size_t(h.width) * std::size_t(h.channels);
    const std::uint64_t data_bytes = std::uint64_t(row_floats) * std::uint64_t(h.height) * 4;
    if (h.crlf && file_size == h.data_offset + 1 + data_bytes) ++h.data_offset;
    // Before allocating: the file must hold every row it declares.
    if (file_size < h.data_offset || file_size - h.data_offset < data_bytes)
        throw InputError(path + ": truncated PFM: " + std::to_string(h.width) + " x " + std::to_string(h.height) +
                         " pixels need " + std::to_string(data_bytes) + " bytes of data, the file has " +
                         std::to_string(file_size > h.data_offset ? file_size - h.data_offset : 0));
    Image image(h.width, h.height);
    std::vector<std::uint32_t> row(row_floats);
    const bool swap = h.little_endian != (std::endian::native == std::endian::little);
    for (int r = 0; r < h.height; ++r) {
        const std::uint64_t offset = h.data_offset + std::uint64_t(r) * row_floats * 4;
        if (read_at(d.fd, row.data(), row_floats * 4, offset) != row_floats * 4)
            throw InputError(path + ": truncated PFM (the file shrank while being read)");
        const int y = h.height - 1 - r;  // the file's first row is the image's bottom row
        for (int x = 0; x < h.width; ++x) {
            float v[3];
            for (int c = 0; c < h.channels; ++c) {
                std::uint32_t bits = row[std::size_t(x) * h.channels + c];
                if (swap) bits = __builtin_bswap32(bits);
                v[c] = std::bit_cast<float>(bits);
            }
            image.at(x, y) = h.channels == 3 ? glm::vec3(v[0], v[1], v[2]) : glm::vec3(v[0]);
        }
    }
    return image;
}

/// The PFM byte stream of `image` (already exposed): little-endian, bottom row first.
FileWriteOutcome write_pfm_stream(std::FILE* file, const Image& image, const std::atomic<bool>* cancel,
                                  std::string& error) {
    if (std::fprintf(file, "PF\n%d %d\n-1.0\n", image.width, image.height) < 0) {
        error = std::strerror(errno);
        return FileWriteOutcome::failed;
    }
    std::vector<std::uint32_t> row(std::size_t(image.width) * 3);
    for (int y = image.height - 1; y >= 0; --y) {
        if (cancel && cancel->load(std::memory_order_relaxed)) return FileWriteOutcome::cancelled;
        for (int x = 0; x < image.width; ++x)
            for (int c = 0; c < 3; ++c) {
                std::uint32_t bits = std::bit_cast<std::uint32_t>(image.at(x, y)[c]);
                if constexpr (std::endian::native != std::endian::little) bits = __builtin_bswap32(bits);
                row[std::size_t(x) * 3 + c] = bits;
            }
        if (std::fwrite(row.data(), 4, row.size(), file) != row.size()) {
            error = std::strerror(errno);
            return FileWriteOutcome::failed;
        }
    }
    return FileWriteOutcome::written;
}

// ---------------------------------------------------------------------------------------------
// PNG as float

/// sRGB-encoded 8-bit value -> linear.
float srgb_to_linear(unsigned char v) {
    const float c = v / 255.0f;
    return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

Image read_png_as_float(const std::string& path, bool srgb, const ImageReadLimits& limits) {
    PngReadLimits png_limits;
    png_limits.max_pixels = limits.max_pixels;
    png_limits.max_width = png_limits.max_height = limits.max_side;
    Png8 png;
    try {
        png = read_png(path, png_limits);
    } catch (const std::bad_alloc&) {
        throw InputError(path + ": not enough memory to read this PNG");
    } catch (const std::exception& e) {
        throw InputError(e.what());  // read_png's messages name the file
    }
    float table[256];
    for (int v = 0; v < 256; ++v) table[v] = srgb ? srgb_to_linear(static_cast<unsigned char>(v)) : v / 255.0f;
    Image image(png.width, png.height);
    const int n = png.channels;
    for (std::size_t i = 0; i < image.pixels.size(); ++i) {
        const unsigned char* p = png.data.data() + i * std::size_t(n);
        image.pixels[i] = n >= 3 ? glm::vec3(table[p[0]], table[p[1]], table[p[2]]) : glm::vec3(table[p[0]]);
    }
    return image;
}

}  // namespace

std::optional<ImageFormat> image_format_of(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (ext == ".png") return ImageFormat::png;
    if (ext == ".exr") return ImageFormat::exr;
    if (ext == ".pfm") return ImageFormat::pfm;
    return std::nullopt;
}

const char* image_format_name(ImageFormat format) {
    switch (format) {
        case ImageFormat::png: return "png";
        case ImageFormat::exr: return "exr";
        case ImageFormat::pfm: return "pfm";
    }
    return "png";
}

Image read_image_file(const std::string& path, bool srgb_png, const ImageReadLimits& limits) {
    unsigned char magic[8] = {};
    std::size_t got = 0;
    {
        Descriptor d;
        open_regular(path, d);
        got = read_at(d.fd, magic, sizeof magic, 0);
    }
    static const unsigned char png_signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    if (got == 8 && std::memcmp(magic, png_signature, 8) == 0) return read_png_as_float(path, srgb_png, limits);
    if (has_exr_magic({magic, got})) return read_exr_image(path, limits);
    if (got >= 2 && magic[0] == 'P' && (magic[1] == 'F' || magic[1] == 'f')) return read_pfm(path, limits);
    if (got == 0) throw InputError(path + ": the file is empty");
    throw InputError(path + ": not a PNG, OpenEXR or PFM file");
}

Image prepare_for_format(const Image& image, ImageFormat format, const ImageWriteSettings& settings) {
    Image out = image;
    if (format == ImageFormat::png) {
        if (settings.tonemap == Tonemap::clamp && settings.exposure_stops == 0.0f) return out;  // the encoder clamps
        for (glm::vec3& p : out.pixels) p = tonemap(p, settings.tonemap, settings.exposure_stops);
    } else if (settings.exposure_stops != 0.0f) {
        const float scale = exposure_scale(settings.exposure_stops);
        for (glm::vec3& p : out.pixels) p *= scale;
    }
    return out;
}

void write_pfm_atomic(const std::string& path, const Image& image, const std::atomic<bool>* cancel, OutputPlace place) {
    if (image.width <= 0 || image.height <= 0) throw std::runtime_error(path + ": cannot write an empty image");
    write_file_atomic(
        path, [&](std::FILE* file, std::string& error) { return write_pfm_stream(file, image, cancel, error); }, cancel,
        place);
}

void write_image_atomic(const std::string& path, const Image& image, const ImageWriteSettings& settings,
                        const ImageMetadata& metadata, const std::atomic<bool>* cancel, OutputPlace place) {
    const std::optional<ImageFormat> format = image_format_of(path);
    if (!format) throw std::runtime_error("cannot write '" + path + "': the name must end in .png, .exr or .pfm");
    const bool untouched = settings.exposure_stops == 0.0f && (*format != ImageFormat::png || settings.tonemap == Tonemap::clamp);
    // Without exposure or tone curve the image is written as it is (no copy of a large image).
    Image prepared;
    if (!untouched) prepared = prepare_for_format(image, *format, settings);
    const Image& source = untouched ? image : prepared;
    switch (*format) {
        case ImageFormat::png: write_png_atomic(path, source, settings.encoding, metadata, cancel, place); return;
        case ImageFormat::exr: write_exr_atomic(path, source, settings.exr_pixel, metadata, cancel, place); return;
        case ImageFormat::pfm: write_pfm_atomic(path, source, cancel, place); return;
    }
}

}  // namespace caustica
