#include "core/io/png_io.h"

#include "core/io/atomic_file.h"
#include "core/util/printable_text.h"

#include <png.h>

#include <atomic>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <limits>
#include <memory>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

namespace caustica {
namespace {

// ---------------------------------------------------------------------------------------------
// libpng glue shared by reading and writing

/// Where libpng's error handler leaves its message; a fixed buffer, so that the handler (called
/// inside libpng) cannot throw.
struct PngErrorText {
    char text[200] = {};
};

[[noreturn]] void png_error_handler(png_structp png, png_const_charp message) {
    if (auto* error = static_cast<PngErrorText*>(png_get_error_ptr(png)))
        std::snprintf(error->text, sizeof error->text, "%s", message ? message : "libpng error");
    png_longjmp(png, 1);
}

void png_warning_handler(png_structp, png_const_charp) {}

std::string error_or_default(const PngErrorText& error) {
    return error.text[0] ? std::string(error.text) : std::string("libpng error");
}

// ---------------------------------------------------------------------------------------------
// Reading: a scan of the chunk structure and the header, then libpng with limits

/// A PNG refused for a reason; the public functions add the file's name.
class PngRejected : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

const char* const not_a_png = "not a PNG file";

std::uint32_t big_endian_32(const unsigned char* p) {
    return std::uint32_t(p[0]) << 24 | std::uint32_t(p[1]) << 16 | std::uint32_t(p[2]) << 8 | std::uint32_t(p[3]);
}

/// A chunk type for messages: "tEXt", or its bytes in hex when they are not letters.
std::string chunk_name(const unsigned char* type) {
    std::string name;
    for (int i = 0; i < 4; ++i)
        if (!std::isalpha(type[i])) {
            char hex[16];
            std::snprintf(hex, sizeof hex, "%02x%02x%02x%02x", type[0], type[1], type[2], type[3]);
            return std::string("0x") + hex;
        } else {
            name += static_cast<char>(type[i]);
        }
    return name;
}

/// Channels of the decoded image: palettes become RGB, tRNS becomes alpha.
int decoded_channels(int colour_type, bool has_transparency) {
    switch (colour_type) {
        case PNG_COLOR_TYPE_GRAY: return has_transparency ? 2 : 1;
        case PNG_COLOR_TYPE_GRAY_ALPHA: return 2;
        case PNG_COLOR_TYPE_RGB:
        case PNG_COLOR_TYPE_PALETTE: return has_transparency ? 4 : 3;
        default: return 4;
    }
}

/// Checks the IHDR fields the way the PNG specification constrains them.
PngHeader parse_ihdr(const unsigned char* body) {
    PngHeader h;
    const std::uint32_t width = big_endian_32(body), height = big_endian_32(body + 4);
    const int depth = body[8], type = body[9], compression = body[10], filter = body[11], interlace = body[12];
    if (width == 0 || height == 0)
        throw PngRejected("the header declares an empty image (" + std::to_string(width) + " x " + std::to_string(height) + " pixels)");
    constexpr std::uint32_t png_max = 0x7fffffffu;
    if (width > png_max || height > png_max)
        throw PngRejected("the header declares " + std::to_string(width) + " x " + std::to_string(height) +
                          " pixels, more than PNG allows");
    bool valid_depth = false;
    switch (type) {
        case PNG_COLOR_TYPE_GRAY: valid_depth = depth == 1 || depth == 2 || depth == 4 || depth == 8 || depth == 16; break;
        case PNG_COLOR_TYPE_PALETTE: valid_depth = depth == 1 || depth == 2 || depth == 4 || depth == 8; break;
        case PNG_COLOR_TYPE_RGB:
        case PNG_COLOR_TYPE_GRAY_ALPHA:
        case PNG_COLOR_TYPE_RGB_ALPHA: valid_depth = depth == 8 || depth == 16; break;
        default: throw PngRejected("the header declares an unknown colour type " + std::to_string(type));
    }
    if (!valid_depth)
        throw PngRejected("the header declares bit depth " + std::to_string(depth) + ", which colour type " +
                          std::to_string(type) + " does not allow");
    if (compression != 0 || filter != 0 || interlace > 1)
        throw PngRejected("the header declares an unknown compression, filter or interlace method");
    h.width = static_cast<int>(width);
    h.height = static_cast<int>(height);
    h.bit_depth = depth;
    h.colour_type = type;
    h.interlaced = interlace == 1;
    return h;
}

/// The header's size against the limits: the pixel budget first (the clearer message).
void check_limits(const PngHeader& h, const PngReadLimits& limits) {
    const std::string size = std::to_string(h.width) + " x " + std::to_string(h.height) + " pixels";
    const std::uint64_t pixels = std::uint64_t(h.width) * std::uint64_t(h.height);
    if (pixels > limits.max_pixels)
        throw PngRejected(size + " is more than the " + std::to_string(limits.max_pixels) + "-pixel " +
                          limits.budget_name + " budget");
    if (std::uint64_t(h.width) > limits.max_width)
        throw PngRejected(size + ": the width is more than the " + std::to_string(limits.max_width) + " allowed");
    if (std::uint64_t(h.height) > limits.max_height)
        throw PngRejected(size + ": the height is more than the " + std::to_string(limits.max_height) + " allowed");
}

/// Walks the chunks: every chunk must lie inside the bytes (so no declared length makes libpng
/// allocate more than the file holds), IHDR first, IEND last. Returns the checked header.
PngHeader scan_png(std::span<const unsigned char> bytes, const PngReadLimits& limits) {
    if (bytes.size() < 8 || png_sig_cmp(bytes.data(), 0, 8) != 0) throw PngRejected(not_a_png);
    std::size_t at = 8;
    bool seen_header = false, has_transparency = false, seen_end = false;
    PngHeader header;
    while (at < bytes.size() && !seen_end) {
        if (bytes.size() - at < 8) throw PngRejected("truncated: a chunk is cut off at byte " + std::to_string(at));
        const std::size_t remain = bytes.size() - at - 8;  // after the length and type fields
        const std::uint32_t length = big_endian_32(bytes.data() + at);
        const unsigned char* type = bytes.data() + at + 4;
        if (length > 0x7fffffffu || length > remain)
            throw PngRejected("chunk '" + chunk_name(type) + "' at byte " + std::to_string(at) + " declares " +
                              std::to_string(length) + " bytes but only " + std::to_string(remain) +
                              " remain in the file");
        if (length + std::size_t(4) > remain)
            throw PngRejected("truncated: the CRC of chunk '" + chunk_name(type) + "' is cut off");
        if (!seen_header) {
            if (std::memcmp(type, "IHDR", 4) != 0 || length != 13)
                throw PngRejected("the first chunk is not a valid IHDR header");
            header = parse_ihdr(type + 4);
            seen_header = true;
        }
        if (std::memcmp(type, "tRNS", 4) == 0) has_transparency = true;
        if (std::memcmp(type, "IEND", 4) == 0) seen_end = true;
        at += 12 + std::size_t(length);
    }
    if (!seen_header) throw PngRejected("truncated: no IHDR header");
    if (!seen_end) throw PngRejected("truncated: no IEND chunk");
    header.channels = decoded_channels(header.colour_type, has_transparency);
    check_limits(header, limits);
    return header;
}

/// libpng's input: the bytes in memory.
struct MemoryInput {
    const unsigned char* data = nullptr;
    std::size_t size = 0, at = 0;
};

void read_from_memory(png_structp png, png_bytep out, png_size_t count) {
    auto* in = static_cast<MemoryInput*>(png_get_io_ptr(png));
    if (count > in->size - in->at) png_error(png, "truncated");
    std::memcpy(out, in->data + in->at, count);
    in->at += count;
}

/// Owns libpng's read structures.
struct PngReader {
    png_structp png = nullptr;
    png_infop info = nullptr;
    PngErrorText error;
    MemoryInput input;
    ~PngReader() { png_destroy_read_struct(&png, info ? &info : nullptr, nullptr); }
};

/// Reads the chunks up to the image data and sets up 8-bit expansion; false on a libpng error.
/// Only trivially destructible locals here: libpng's errors longjmp out of this frame.
bool read_info(PngReader& r, const PngReadLimits& limits) {
    if (setjmp(png_jmpbuf(r.png))) return false;
    png_set_user_limits(r.png, limits.max_width, limits.max_height);
    png_set_chunk_malloc_max(r.png, limits.max_chunk_bytes);
    png_set_chunk_cache_max(r.png, limits.max_ancillary_chunks);
    // Compressed text can inflate without bound over many chunks; tEXt is enough for us.
    static const png_byte ignored[] = {'z', 'T', 'X', 't', '\0', 'i', 'T', 'X', 't', '\0'};
    png_set_keep_unknown_chunks(r.png, PNG_HANDLE_CHUNK_NEVER, ignored, 2);
    png_set_read_fn(r.png, &r.input, read_from_memory);
    png_set_sig_bytes(r.png, 8);
    png_read_info(r.png, r.info);
    png_set_scale_16(r.png);  // 16 bits -> the nearest 8-bit value (v * 255 / 65535, rounded)
    png_set_packing(r.png);
    png_set_expand(r.png);  // palette -> RGB, low-bit gray -> 8 bit, tRNS -> alpha
    png_set_interlace_handling(r.png);
    png_read_update_info(r.png, r.info);
    return true;
}

/// Decodes the image data into `rows` and reads the chunks after it; false on a libpng error.
bool read_rows(PngReader& r, png_bytepp rows) {
    if (setjmp(png_jmpbuf(r.png))) return false;
    png_read_image(r.png, rows);
    png_read_end(r.png, r.info);
    return true;
}

/// Decodes, or throws PngRejected with the reason.
Png8 decode_png(std::span<const unsigned char> bytes, const PngReadLimits& limits) {
    const PngHeader header = scan_png(bytes, limits);
    PngReader r;
    r.input = {bytes.data(), bytes.size(), 8};
    r.png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &r.error, png_error_handler, png_warning_handler);
    if (r.png) r.info = png_create_info_struct(r.png);
    if (!r.png || !r.info) throw std::bad_alloc();
    if (!read_info(r, limits)) throw PngRejected(error_or_default(r.error));
    Png8 result;
    result.width = static_cast<int>(png_get_image_width(r.png, r.info));
    result.height = static_cast<int>(png_get_image_height(r.png, r.info));
    result.channels = png_get_channels(r.png, r.info);
    if (result.width != header.width || result.height != header.height || result.channels != header.channels ||
        png_get_rowbytes(r.png, r.info) != std::size_t(result.width) * std::size_t(result.channels))
        throw PngRejected("the decoded layout differs from the header");  // cannot happen with a valid scan
    result.data.resize(header.decoded_bytes());
    std::vector<png_bytep> rows(static_cast<std::size_t>(result.height));
    const std::size_t stride = std::size_t(result.width) * std::size_t(result.channels);
    for (std::size_t y = 0; y < rows.size(); ++y) rows[y] = result.data.data() + y * stride;
    if (!read_rows(r, rows.data())) throw PngRejected(error_or_default(r.error));
    png_textp texts = nullptr;
    int count = 0;
    png_get_text(r.png, r.info, &texts, &count);
    for (int i = 0; i < count; ++i) result.text.emplace_back(texts[i].key, texts[i].text ? texts[i].text : "");
    return result;
}

/// The whole of a regular file of at most `max_bytes`; throws std::runtime_error with the reason.
std::vector<unsigned char> read_regular_file(const std::string& path, std::uint64_t max_bytes) {
    // O_NONBLOCK: opening a FIFO must not wait for a writer; it is refused just below.
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
    if (fd < 0) throw std::runtime_error(std::strerror(errno));
    struct Closer {
        int fd;
        ~Closer() { ::close(fd); }
    } closer{fd};
    struct stat st {};
    if (::fstat(fd, &st) != 0) throw std::runtime_error(std::strerror(errno));
    if (!S_ISREG(st.st_mode)) throw std::runtime_error("not a regular file");
    if (std::uint64_t(st.st_size) > max_bytes)
        throw std::runtime_error("the file has " + std::to_string(st.st_size) + " bytes, more than the " +
                                 std::to_string(max_bytes) + " allowed");
    ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
    std::vector<unsigned char> bytes(static_cast<std::size_t>(st.st_size));
    std::size_t got = 0;
    while (got < bytes.size()) {
        const ssize_t n = ::read(fd, bytes.data() + got, bytes.size() - got);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) throw std::runtime_error(std::strerror(errno));
        if (n == 0) break;  // the file shrank: decode what is there
        got += std::size_t(n);
    }
    bytes.resize(got);
    return bytes;
}

// ---------------------------------------------------------------------------------------------
// Writing: the PNG stream (the atomic file around it: core/io/atomic_file.h)

/// How writing the rows ended.
enum class WriteOutcome { written, failed, cancelled };

struct PngWriter {
    png_structp png = nullptr;
    png_infop info = nullptr;
    PngErrorText error;
    std::vector<unsigned char> row;
    std::vector<std::string> text_values;  ///< the metadata's values as printable_text shows them
    std::vector<png_text> texts;
    ~PngWriter() { png_destroy_write_struct(&png, info ? &info : nullptr); }
};

/// Encodes the rows under libpng's setjmp protocol; only trivially destructible locals here.
WriteOutcome write_png_rows(PngWriter& w, FILE* file, const Image& image, PixelEncoding encoding,
                            const std::atomic<bool>* cancel) {
    if (setjmp(png_jmpbuf(w.png))) return WriteOutcome::failed;
    png_init_io(w.png, file);
    png_set_IHDR(w.png, w.info, static_cast<png_uint_32>(image.width), static_cast<png_uint_32>(image.height), 8,
                 PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    if (encoding == PixelEncoding::srgb) png_set_sRGB(w.png, w.info, PNG_sRGB_INTENT_PERCEPTUAL);
    if (!w.texts.empty()) png_set_text(w.png, w.info, w.texts.data(), static_cast<int>(w.texts.size()));
    png_write_info(w.png, w.info);
    unsigned char* row = w.row.data();
    for (int y = 0; y < image.height; ++y) {
        if (cancel && cancel->load(std::memory_order_relaxed)) return WriteOutcome::cancelled;
        for (int x = 0; x < image.width; ++x) {
            const glm::vec3& p = image.at(x, y);
            for (int c = 0; c < 3; ++c) row[x * 3 + c] = encode_channel(p[c], encoding);
        }
        png_write_row(w.png, row);
    }
    png_write_end(w.png, w.info);
    return WriteOutcome::written;
}

/// Writes the PNG stream to `file`; returns the outcome and, when failed, the reason.
WriteOutcome write_png_stream(FILE* file, const Image& image, PixelEncoding encoding,
                              const std::vector<std::pair<std::string, std::string>>& text_chunks,
                              const std::atomic<bool>* cancel, std::string& error) {
    PngWriter w;
    w.row.resize(static_cast<std::size_t>(image.width) * 3);
    // Values may hold a script's or a path's text: written printable (docs/RELIABILITY.md, "Script
    // text reaches the user bounded and visible").
    for (const auto& chunk : text_chunks) w.text_values.push_back(printable_text(chunk.second));
    w.texts.resize(text_chunks.size());
    for (std::size_t i = 0; i < text_chunks.size(); ++i) {
        w.texts[i].compression = PNG_TEXT_COMPRESSION_NONE;
        w.texts[i].key = const_cast<char*>(text_chunks[i].first.c_str());
        w.texts[i].text = const_cast<char*>(w.text_values[i].c_str());
        w.texts[i].text_length = w.text_values[i].size();
    }
    w.png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &w.error, png_error_handler, png_warning_handler);
    if (w.png) w.info = png_create_info_struct(w.png);
    if (!w.png || !w.info) throw std::bad_alloc();
    const WriteOutcome outcome = write_png_rows(w, file, image, encoding, cancel);
    if (outcome == WriteOutcome::failed) error = error_or_default(w.error);
    return outcome;
}

}  // namespace

unsigned char encode_channel(float value, PixelEncoding encoding) {
    float v = std::isnan(value) ? 0.0f : std::fmin(std::fmax(value, 0.0f), 1.0f);
    // Linear: x255 and truncate, no rounding, as the original wrote its images
    // (docs/SCENE_LANGUAGE.md, "PNG bytes"), so 0.999 -> 254 and 0.5 -> 127.
    if (encoding != PixelEncoding::srgb) return static_cast<unsigned char>(v * 255.0f);
    // --srgb is ours, not the original's: the sRGB curve, rounded to the nearest value (v * 255
    // lies in [0, 255], so adding 0.5 in double is exact and truncating rounds half up).
    v = v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
    return static_cast<unsigned char>(static_cast<double>(v * 255.0f) + 0.5);
}

void write_png_atomic(const std::string& path, const Image& image, PixelEncoding encoding,
                      const std::vector<std::pair<std::string, std::string>>& text,
                      const std::atomic<bool>* cancel, OutputPlace place) {
    if (image.width <= 0 || image.height <= 0) throw std::runtime_error(path + ": cannot write an empty image");
    write_file_atomic(
        path,
        [&](FILE* file, std::string& error) {
            switch (write_png_stream(file, image, encoding, text, cancel, error)) {
                case WriteOutcome::written: return FileWriteOutcome::written;
                case WriteOutcome::cancelled: return FileWriteOutcome::cancelled;
                case WriteOutcome::failed: break;
            }
            return FileWriteOutcome::failed;
        },
        cancel, place);
}

PngHeader read_png_header(std::span<const unsigned char> bytes, const std::string& display_name,
                          const PngReadLimits& limits) {
    try {
        return scan_png(bytes, limits);
    } catch (const PngRejected& e) {
        throw std::runtime_error(display_name + ": " + e.what());
    }
}

Png8 read_png_memory(std::span<const unsigned char> bytes, const std::string& display_name,
                     const PngReadLimits& limits) {
    try {
        return decode_png(bytes, limits);
    } catch (const PngRejected& e) {
        throw std::runtime_error(display_name + ": " + e.what());
    }
}

Png8 read_png(const std::string& path, const PngReadLimits& limits) {
    std::vector<unsigned char> bytes;
    try {
        bytes = read_regular_file(path, limits.max_file_bytes);
    } catch (const std::runtime_error& e) {
        throw std::runtime_error("cannot open '" + path + "': " + e.what());
    }
    try {
        return decode_png(bytes, limits);
    } catch (const PngRejected& e) {
        if (std::strcmp(e.what(), not_a_png) == 0) throw std::runtime_error("'" + path + "' is not a PNG file");
        throw std::runtime_error("cannot read '" + path + "': " + e.what());
    }
}

}  // namespace caustica
