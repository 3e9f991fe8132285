#include "core/png_io.h"

#include <png.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <random>
#include <stdexcept>
#include <unistd.h>

namespace caustica {
namespace {

struct FileCloser {
    void operator()(FILE* f) const {
        if (f) std::fclose(f);
    }
};

[[noreturn]] void png_error_handler(png_structp png, png_const_charp message) {
    auto* text = static_cast<std::string*>(png_get_error_ptr(png));
    if (text) *text = message;
    png_longjmp(png, 1);
}

void png_warning_handler(png_structp, png_const_charp) {}

std::string temporary_name(const std::string& path) {
    std::random_device rd;
    return path + ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(rd() & 0xffffff);
}

/// Buffers the libpng calls use; kept outside the setjmp frame so no C++ object lives in it.
struct PngWriteBuffers {
    std::vector<unsigned char> row;
    std::vector<png_text> texts;
    std::string error;
};

/// The libpng calls under its setjmp error protocol; only trivially destructible locals here.
bool write_png_rows(FILE* file, const Image& image, PixelEncoding encoding, PngWriteBuffers& buffers) {
    png_structp png =
        png_create_write_struct(PNG_LIBPNG_VER_STRING, &buffers.error, png_error_handler, png_warning_handler);
    if (!png) return false;
    png_infop info = png_create_info_struct(png);
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        return false;
    }
    png_init_io(png, file);
    png_set_IHDR(png, info, static_cast<png_uint_32>(image.width), static_cast<png_uint_32>(image.height), 8,
                 PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    if (encoding == PixelEncoding::srgb) png_set_sRGB(png, info, PNG_sRGB_INTENT_PERCEPTUAL);
    if (!buffers.texts.empty()) png_set_text(png, info, buffers.texts.data(), static_cast<int>(buffers.texts.size()));
    png_write_info(png, info);
    unsigned char* row = buffers.row.data();
    for (int y = 0; y < image.height; ++y) {
        for (int x = 0; x < image.width; ++x) {
            const glm::vec3& p = image.at(x, y);
            for (int c = 0; c < 3; ++c) row[x * 3 + c] = encode_channel(p[c], encoding);
        }
        png_write_row(png, row);
    }
    png_write_end(png, info);
    png_destroy_write_struct(&png, &info);
    return true;
}

/// Writes the PNG stream; returns "" or the error.
std::string write_png_stream(FILE* file, const Image& image, PixelEncoding encoding,
                             const std::vector<std::pair<std::string, std::string>>& text_chunks) {
    PngWriteBuffers buffers;
    buffers.row.resize(static_cast<std::size_t>(image.width) * 3);
    buffers.texts.resize(text_chunks.size());
    for (std::size_t i = 0; i < text_chunks.size(); ++i) {
        buffers.texts[i].compression = PNG_TEXT_COMPRESSION_NONE;
        buffers.texts[i].key = const_cast<char*>(text_chunks[i].first.c_str());
        buffers.texts[i].text = const_cast<char*>(text_chunks[i].second.c_str());
        buffers.texts[i].text_length = text_chunks[i].second.size();
    }
    if (write_png_rows(file, image, encoding, buffers)) return {};
    return buffers.error.empty() ? "libpng error" : buffers.error;
}

}  // namespace

unsigned char encode_channel(float value, PixelEncoding encoding) {
    float v = std::isnan(value) ? 0.0f : std::fmin(std::fmax(value, 0.0f), 1.0f);
    if (encoding == PixelEncoding::srgb)
        v = v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
    return static_cast<unsigned char>(std::lround(v * 255.0f));
}

void write_png_atomic(const std::string& path, const Image& image, PixelEncoding encoding,
                      const std::vector<std::pair<std::string, std::string>>& text) {
    if (image.width <= 0 || image.height <= 0) throw std::runtime_error(path + ": cannot write an empty image");
    const std::string temporary = temporary_name(path);
    std::unique_ptr<FILE, FileCloser> file(std::fopen(temporary.c_str(), "wb"));
    if (!file) throw std::runtime_error("cannot write '" + path + "': " + std::strerror(errno));
    std::string error = write_png_stream(file.get(), image, encoding, text);
    if (error.empty() && (std::fflush(file.get()) != 0 || ::fsync(::fileno(file.get())) != 0))
        error = std::strerror(errno);
    FILE* raw = file.release();
    if (std::fclose(raw) != 0 && error.empty()) error = std::strerror(errno);
    if (error.empty() && std::rename(temporary.c_str(), path.c_str()) != 0) error = std::strerror(errno);
    if (!error.empty()) {
        std::remove(temporary.c_str());
        throw std::runtime_error("cannot write '" + path + "': " + error);
    }
}

Png8 read_png(const std::string& path) {
    std::unique_ptr<FILE, FileCloser> file(std::fopen(path.c_str(), "rb"));
    if (!file) throw std::runtime_error("cannot open '" + path + "': " + std::strerror(errno));
    unsigned char signature[8];
    if (std::fread(signature, 1, 8, file.get()) != 8 || png_sig_cmp(signature, 0, 8) != 0)
        throw std::runtime_error("'" + path + "' is not a PNG file");
    std::string error;
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &error, png_error_handler, png_warning_handler);
    png_infop info = png_create_info_struct(png);
    Png8 result;
    std::vector<png_bytep> rows;
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_read_struct(&png, &info, nullptr);
        throw std::runtime_error("cannot read '" + path + "': " + (error.empty() ? "libpng error" : error));
    }
    png_init_io(png, file.get());
    png_set_sig_bytes(png, 8);
    png_read_info(png, info);
    png_set_strip_16(png);
    png_set_packing(png);
    png_set_expand(png);  // palette -> RGB, low-bit gray -> 8 bit, tRNS -> alpha
    png_read_update_info(png, info);
    result.width = static_cast<int>(png_get_image_width(png, info));
    result.height = static_cast<int>(png_get_image_height(png, info));
    result.channels = png_get_channels(png, info);
    if (static_cast<double>(result.width) * result.height > double(1 << 28))
        png_error(png, "image too large");
    result.data.resize(static_cast<std::size_t>(result.width) * result.height * result.channels);
    rows.resize(static_cast<std::size_t>(result.height));
    for (int y = 0; y < result.height; ++y)
        rows[y] = result.data.data() + static_cast<std::size_t>(y) * result.width * result.channels;
    png_read_image(png, rows.data());
    png_read_end(png, info);
    png_textp texts = nullptr;
    int count = 0;
    png_get_text(png, info, &texts, &count);
    for (int i = 0; i < count; ++i) result.text.emplace_back(texts[i].key, texts[i].text ? texts[i].text : "");
    png_destroy_read_struct(&png, &info, nullptr);
    return result;
}

}  // namespace caustica
