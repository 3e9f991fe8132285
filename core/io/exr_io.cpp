#include "core/io/exr_io.h"

#include "core/io/regular_file.h"
#include "core/scene/source_location.h"
#include "core/util/printable_text.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfIO.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <IexBaseExc.h>
#include <ImfStringAttribute.h>
#include <Imath/half.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <mutex>
#include <sys/stat.h>
#include <unistd.h>
#include <vector>

namespace caustica {
namespace {

/// OpenEXR's output on an open C stream: write_file_atomic owns the stream (a fresh temporary).
class FileOStream : public Imf::OStream {
public:
    FileOStream(std::FILE* file, const std::string& name) : Imf::OStream(name.c_str()), file_(file) {}
    void write(const char c[], int n) override {
        if (n > 0 && std::fwrite(c, 1, static_cast<std::size_t>(n), file_) != static_cast<std::size_t>(n))
            throw std::runtime_error(std::strerror(errno));
    }
    uint64_t tellp() override {
        const off_t at = ::ftello(file_);
        if (at < 0) throw std::runtime_error(std::strerror(errno));
        return static_cast<uint64_t>(at);
    }
    void seekp(uint64_t pos) override {
        if (::fseeko(file_, static_cast<off_t>(pos), SEEK_SET) != 0) throw std::runtime_error(std::strerror(errno));
    }

private:
    std::FILE* file_;
};

/// OpenEXR's own header check (Header::sanityCheck) refuses data windows and tiles wider or
/// taller than this before it sizes its offset tables: a forged header cannot make the library
/// allocate gigabytes before our pixel budget is even looked at. Process-wide, set once.
void limit_openexr_sizes() {
    static std::once_flag once;
    std::call_once(once, [] {
        const int side = static_cast<int>(ImageReadLimits{}.max_side);
        Imf::Header::setMaxImageSize(side, side);
        Imf::Header::setMaxTileSize(side, side);
    });
}

using io::Descriptor;
using io::open_regular;
using io::read_at;

/// OpenEXR's input on the descriptor our header walk checked (the same file, not the path again),
/// and the header bytes from the very copy the walk checked: a file rewritten in place meanwhile
/// cannot slip OpenEXR a different header. A read past the end throws as OpenEXR's own stream does.
class DescriptorIStream : public Imf::IStream {
public:
    DescriptorIStream(int fd, std::uint64_t size, const std::vector<unsigned char>& checked, const std::string& name)
        : Imf::IStream(name.c_str()), fd_(fd), size_(size), checked_(checked) {}
    bool read(char c[], int n) override {
        if (n < 0) throw Iex::InputExc("negative read size");
        const std::size_t want = static_cast<std::size_t>(n);
        std::size_t got = 0;
        if (at_ < checked_.size()) {
            got = std::min<std::size_t>(want, checked_.size() - static_cast<std::size_t>(at_));
            std::memcpy(c, checked_.data() + at_, got);
        }
        got += read_at(fd_, c + got, want - got, at_ + got);
        at_ += got;
        if (got != want) throw Iex::InputExc("Early end of file: read " + std::to_string(got) + " out of " +
                                             std::to_string(want) + " requested bytes.");
        return at_ < size_;
    }
    uint64_t tellg() override { return at_; }
    void seekg(uint64_t pos) override { at_ = pos; }

private:
    int fd_;
    std::uint64_t size_;
    const std::vector<unsigned char>& checked_;
    std::uint64_t at_ = 0;
};

// ---------------------------------------------------------------------------------------------
// The header walk. OpenEXR trusts the sizes a header declares: an attribute claiming 2^31 - 1
// bytes (or a string vector element, or a preview image of 2^31 pixels) is allocated in full
// before the library notices the file is 29 bytes long, and setMaxImageSize does not cover
// attributes. So before OpenEXR sees a file we walk its header(s) from the bytes ourselves -- magic,
// version, then `name\0 type\0 int32 size data` until an empty name, repeated per part for
// multi-part files until an empty header -- and refuse any size the file cannot hold. Only the
// header region is read, at most `max_header_bytes`.

constexpr std::uint64_t max_header_bytes = 16u << 20;
constexpr int max_attributes_per_part = 1024;
constexpr int max_parts = 256;

/// The bytes of the header region, read from the descriptor on demand (never past the cap).
class HeaderBytes {
public:
    HeaderBytes(const std::string& path, int fd, std::uint64_t file_size)
        : path_(path), fd_(fd), file_size_(file_size), limit_(std::min(file_size, max_header_bytes)) {}

    /// The bytes read so far (the whole header region once the walk is done).
    std::vector<unsigned char> take() { return std::move(bytes_); }

    /// Makes bytes [0, end) available; throws when the file or the header cap ends before.
    const unsigned char* need(std::uint64_t end, const char* what) {
        if (end > file_size_)
            throw InputError(path_ + ": the OpenEXR header ends early (the file is " + std::to_string(file_size_) +
                             " bytes, cut in the " + what + ")");
        if (end > limit_)
            throw InputError(path_ + ": the OpenEXR header is larger than " + std::to_string(max_header_bytes >> 20) +
                             " MiB");
        if (end > bytes_.size()) {
            // Grow geometrically in steps of at least 64 KiB: a normal header is one read.
            const std::uint64_t target = std::min<std::uint64_t>(limit_, std::max<std::uint64_t>(end, std::max<std::uint64_t>(bytes_.size() * 2, 64u << 10)));
            const std::size_t old = bytes_.size();
            bytes_.resize(static_cast<std::size_t>(target));
            const std::size_t got = read_at(fd_, bytes_.data() + old, bytes_.size() - old, old);
            bytes_.resize(old + got);
            if (end > bytes_.size()) throw InputError(path_ + ": the file shrank while its OpenEXR header was read");
        }
        return bytes_.data();
    }

private:
    const std::string& path_;
    int fd_;
    std::uint64_t file_size_, limit_;
    std::vector<unsigned char> bytes_;
};

std::int32_t le_i32(const unsigned char* p) {
    return static_cast<std::int32_t>(std::uint32_t(p[0]) | std::uint32_t(p[1]) << 8 | std::uint32_t(p[2]) << 16 |
                                     std::uint32_t(p[3]) << 24);
}

/// What the walk learns about one part (for the sizes OpenEXR derives from it).
struct PartShape {
    bool has_window = false, has_tiles = false;
    std::int64_t width = 0, height = 0;
    std::uint32_t tile_x = 0, tile_y = 0;
    int level_mode = 0, rounding = 0;
};

/// floor(log2(n)) or ceil(log2(n)) for n >= 1.
int round_log2(std::int64_t n, int rounding) {
    int l = 0;
    while ((std::int64_t(1) << (l + 1)) <= n) ++l;
    if (rounding == 1 && (std::int64_t(1) << l) < n) ++l;
    return l;
}

std::int64_t level_size(std::int64_t n, int level, int rounding) {
    const std::int64_t s = rounding == 1 ? (n + (std::int64_t(1) << level) - 1) >> level : n >> level;
    return std::max<std::int64_t>(s, 1);
}

/// How many tiles (chunks) a tiled part has: OpenEXR allocates an offset per tile from the header.
std::uint64_t tile_count(const PartShape& s) {
    auto across = [](std::int64_t n, std::uint32_t tile) { return std::uint64_t((n + tile - 1) / tile); };
    if (s.level_mode == 0) return across(s.width, s.tile_x) * across(s.height, s.tile_y);
    if (s.level_mode == 1) {
        std::uint64_t total = 0;
        const int levels = round_log2(std::max(s.width, s.height), s.rounding) + 1;
        for (int l = 0; l < levels; ++l)
            total += across(level_size(s.width, l, s.rounding), s.tile_x) * across(level_size(s.height, l, s.rounding), s.tile_y);
        return total;
    }
    std::uint64_t xs = 0, ys = 0;  // rip maps: every x level with every y level
    for (int l = 0; l <= round_log2(s.width, s.rounding); ++l) xs += across(level_size(s.width, l, s.rounding), s.tile_x);
    for (int l = 0; l <= round_log2(s.height, s.rounding); ++l) ys += across(level_size(s.height, l, s.rounding), s.tile_y);
    return xs * ys;
}

/// Checks one attribute's data (`size` bytes at `data`, inside the file) for the sizes OpenEXR
/// reads from inside it, and records the part's shape.
void check_attribute(const std::string& path, const std::string& name, const std::string& type,
                     const unsigned char* data, std::uint64_t size, std::uint64_t file_size,
                     const ImageReadLimits& limits, PartShape& shape) {
    auto fail = [&](const std::string& why) { return InputError(path + ": header attribute '" + name + "' " + why); };
    if (type == "stringvector") {
        for (std::uint64_t i = 0; i < size;) {
            if (size - i < 4) throw fail("(a string vector) ends inside a string length");
            const std::int32_t n = le_i32(data + i);
            i += 4;
            if (n < 0 || std::uint64_t(n) > size - i)
                throw fail("holds a string of " + std::to_string(n) + " bytes, the attribute has " +
                           std::to_string(size - i) + " left");
            i += std::uint64_t(n);
        }
    } else if (type == "preview") {
        if (size < 8) throw fail("(a preview image) is " + std::to_string(size) + " bytes");
        const std::uint64_t w = std::uint32_t(le_i32(data)), h = std::uint32_t(le_i32(data + 4));
        if (w * h * 4 != size - 8)
            throw fail("claims a " + std::to_string(w) + " x " + std::to_string(h) + " preview image in " +
                       std::to_string(size - 8) + " bytes");
    } else if (name == "type" && type == "string" &&
               std::string(reinterpret_cast<const char*>(data), size).rfind("deep", 0) == 0) {
        throw InputError(path + ": deep OpenEXR images are not supported");
    } else if (name == "dataWindow" && type == "box2i") {
        if (size != 16) throw fail("(a box) is " + std::to_string(size) + " bytes, not 16");
        shape.has_window = true;
        shape.width = std::int64_t(le_i32(data + 8)) - le_i32(data) + 1;
        shape.height = std::int64_t(le_i32(data + 12)) - le_i32(data + 4) + 1;
        const std::string dims = std::to_string(shape.width) + " x " + std::to_string(shape.height) + " pixels";
        if (shape.width <= 0 || shape.height <= 0)
            throw InputError(path + ": the data window is empty (" + dims + ")");
        if (std::uint64_t(shape.width) * std::uint64_t(shape.height) > limits.max_pixels)
            throw InputError(path + ": " + dims + " is more than the " + std::to_string(limits.max_pixels) +
                             "-pixel image budget");
        if (shape.width > limits.max_side || shape.height > limits.max_side)
            throw InputError(path + ": " + dims + ": a side is more than the " + std::to_string(limits.max_side) +
                             " allowed");
    } else if (name == "tiles" && type == "tiledesc") {
        if (size != 9) throw fail("(a tile description) is " + std::to_string(size) + " bytes, not 9");
        shape.has_tiles = true;
        shape.tile_x = std::uint32_t(le_i32(data));
        shape.tile_y = std::uint32_t(le_i32(data + 4));
        shape.level_mode = data[8] & 0x0f;
        shape.rounding = data[8] >> 4;
        if (shape.tile_x == 0 || shape.tile_y == 0 || shape.level_mode > 2 || shape.rounding > 1)
            throw fail("is not a valid tile description");
    } else if (name == "chunkCount" && type == "int") {
        if (size != 4) throw fail("(an int) is " + std::to_string(size) + " bytes, not 4");
        const std::int32_t n = le_i32(data);
        if (n < 0 || std::uint64_t(n) * 8 > file_size)
            throw fail("claims " + std::to_string(n) + " chunks, the file has room for " +
                       std::to_string(file_size / 8) + " offsets");
    }
}

/// Walks every header of the OpenEXR file open on `fd` (see above); throws InputError("PATH: ...")
/// for anything OpenEXR would size from the file without checking it against the file. Returns the
/// bytes it read (from the file's start, the whole header region at least).
std::vector<unsigned char> check_exr_headers(const std::string& path, int fd, std::uint64_t file_size,
                                             const ImageReadLimits& limits) {
    HeaderBytes bytes(path, fd, file_size);
    const unsigned char* b = bytes.need(8, "version field");
    if (!has_exr_magic({b, 4})) throw InputError(path + ": not an OpenEXR file");
    const std::uint32_t version = std::uint32_t(le_i32(b + 4));
    if ((version & 0xff) != 2)
        throw InputError(path + ": OpenEXR file format version " + std::to_string(version & 0xff) + " is not supported");
    if (version & 0x800) throw InputError(path + ": deep OpenEXR images are not supported");
    const bool long_names = version & 0x400, multipart = version & 0x1000;
    const std::size_t max_name = long_names ? 255 : 31;
    std::uint64_t at = 8;

    // A NUL-terminated name of at most max_name bytes at `at` ("" for the terminating NUL).
    auto read_name = [&](const char* what) {
        if (at >= file_size) bytes.need(at + 1, what);  // throws: the file ends before the name
        const std::uint64_t end = std::min({at + max_name + 1, file_size, max_header_bytes});
        const unsigned char* p = bytes.need(end, what);
        for (std::uint64_t i = at; i < end; ++i)
            if (p[i] == 0) {
                std::string name(reinterpret_cast<const char*>(p + at), i - at);
                at = i + 1;
                return name;
            }
        if (end == file_size || end == max_header_bytes) bytes.need(end + 1, what);  // throws: ends inside the name
        throw InputError(path + ": an OpenEXR header " + what + " is longer than " + std::to_string(max_name) +
                         " bytes (or not NUL-terminated)");
    };

    std::vector<PartShape> shapes;
    for (int part = 0;; ++part) {
        if (multipart && part > 0 && bytes.need(at + 1, "part list")[at] == 0) {
            ++at;  // the empty header that ends the list of parts
            break;
        }
        if (part >= max_parts) throw InputError(path + ": more than " + std::to_string(max_parts) + " OpenEXR parts");
        PartShape shape;
        for (int count = 0;; ++count) {
            const std::string name = read_name("attribute name");
            if (name.empty()) break;
            if (count >= max_attributes_per_part)
                throw InputError(path + ": more than " + std::to_string(max_attributes_per_part) +
                                 " attributes in an OpenEXR header");
            const std::string type = read_name("attribute type");
            if (type.empty()) throw InputError(path + ": header attribute '" + name + "' has no type");
            const std::int32_t size = le_i32(bytes.need(at + 4, "attribute size") + at);
            at += 4;
            if (size < 0 || std::uint64_t(size) > file_size - at)
                throw InputError(path + ": header attribute '" + name + "' claims " + std::to_string(size) +
                                 " bytes, the file has " + std::to_string(file_size - at) + " left");
            const unsigned char* data = bytes.need(at + std::uint64_t(size), "attribute data") + at;
            check_attribute(path, name, type, data, std::uint64_t(size), file_size, limits, shape);
            at += std::uint64_t(size);
        }
        shapes.push_back(shape);
        if (!multipart) break;
    }
    // Offset tables: OpenEXR allocates one 64-bit offset per chunk from the header alone, so a
    // tiled part of tiny tiles would cost gigabytes; the file must at least hold those offsets.
    std::uint64_t chunks = 0;
    for (const PartShape& s : shapes)
        if (s.has_window && s.has_tiles) chunks += tile_count(s);
    if (chunks > (file_size - at) / 8)
        throw InputError(path + ": the OpenEXR tiles need " + std::to_string(chunks) + " chunk offsets (" +
                         std::to_string(chunks * 8) + " bytes), the file has " + std::to_string(file_size - at) +
                         " bytes after its header");
    return bytes.take();
}

/// Opens `path` as a checked OpenEXR file (check_exr_headers, then OpenEXR on the same descriptor
/// and the checked header bytes) and returns `read(file)`; every failure reads "PATH: reason".
template <class Read>
auto read_checked_exr(const std::string& path, const ImageReadLimits& limits, Read read) {
    Descriptor d;
    const std::uint64_t file_size = open_regular(path, d);
    const std::vector<unsigned char> checked = check_exr_headers(path, d.fd, file_size, limits);
    limit_openexr_sizes();
    try {
        DescriptorIStream stream(d.fd, file_size, checked, path);
        Imf::InputFile file(stream);
        return read(file);
    } catch (const InputError&) {
        throw;
    } catch (const std::bad_alloc&) {
        throw InputError(path + ": not enough memory to read this OpenEXR file");
    } catch (const std::exception& e) {
        throw InputError(path + ": not a readable OpenEXR file: " + e.what());
    }
}

}  // namespace

bool has_exr_magic(std::span<const unsigned char> bytes) {
    return bytes.size() >= 4 && bytes[0] == 0x76 && bytes[1] == 0x2f && bytes[2] == 0x31 && bytes[3] == 0x01;
}

Image read_exr_image(const std::string& path, const ImageReadLimits& limits) {
    return read_checked_exr(path, limits, [&](Imf::InputFile& file) {
        const Imath::Box2i window = file.header().dataWindow();
        const std::int64_t width = std::int64_t(window.max.x) - window.min.x + 1;
        const std::int64_t height = std::int64_t(window.max.y) - window.min.y + 1;
        const std::string size = std::to_string(width) + " x " + std::to_string(height) + " pixels";
        if (width <= 0 || height <= 0) throw InputError(path + ": the data window is empty (" + size + ")");
        if (std::uint64_t(width) * std::uint64_t(height) > limits.max_pixels)
            throw InputError(path + ": " + size + " is more than the " + std::to_string(limits.max_pixels) +
                             "-pixel image budget");
        if (width > limits.max_side || height > limits.max_side)
            throw InputError(path + ": " + size + ": a side is more than the " + std::to_string(limits.max_side) +
                             " allowed");
        const Imf::ChannelList& channels = file.header().channels();
        const bool colour = channels.findChannel("R") || channels.findChannel("G") || channels.findChannel("B");
        const bool luminance = !colour && channels.findChannel("Y");
        Image image(static_cast<int>(width), static_cast<int>(height));
        char* base = reinterpret_cast<char*>(image.pixels.data());
        const std::size_t x_stride = sizeof(glm::vec3), y_stride = x_stride * static_cast<std::size_t>(width);
        Imf::FrameBuffer frame;
        if (luminance) {
            frame.insert("Y", Imf::Slice::Make(Imf::FLOAT, base, window, x_stride, y_stride));
        } else {
            const char* names[3] = {"R", "G", "B"};
            for (int c = 0; c < 3; ++c)
                frame.insert(names[c], Imf::Slice::Make(Imf::FLOAT, base + c * sizeof(float), window, x_stride, y_stride));
        }
        file.setFrameBuffer(frame);
        file.readPixels(window.min.y, window.max.y);
        if (luminance)
            for (glm::vec3& p : image.pixels) p.y = p.z = p.x;
        return image;
    });
}

ImageMetadata read_exr_metadata(const std::string& path) {
    return read_checked_exr(path, ImageReadLimits{}, [](Imf::InputFile& file) {
        ImageMetadata metadata;
        for (auto it = file.header().begin(); it != file.header().end(); ++it)
            if (const auto* text = dynamic_cast<const Imf::StringAttribute*>(&it.attribute()))
                metadata.emplace_back(it.name(), text->value());
        return metadata;
    });
}

void write_exr_atomic(const std::string& path, const Image& image, ExrPixel pixel, const ImageMetadata& metadata,
                      const std::atomic<bool>* cancel, OutputPlace place) {
    write_exr_channels_atomic(path, image.width, image.height, {{"R", &image, 0}, {"G", &image, 1}, {"B", &image, 2}},
                              pixel, metadata, cancel, place);
}

void write_exr_channels_atomic(const std::string& path, int width, int height, const std::vector<ExrChannel>& channels,
                               ExrPixel pixel, const ImageMetadata& metadata, const std::atomic<bool>* cancel,
                               OutputPlace place) {
    if (width <= 0 || height <= 0) throw std::runtime_error(path + ": cannot write an empty image");
    for (const ExrChannel& c : channels)
        if (c.image && (c.image->width != width || c.image->height != height))
            throw std::logic_error(path + ": channel " + c.name + " is not of the image's size");
    write_file_atomic(
        path,
        [&](std::FILE* file, std::string& error) {
            try {
                Imf::Header header(width, height);  // ZIP compression, increasing Y
                const Imf::PixelType type = pixel == ExrPixel::half ? Imf::HALF : Imf::FLOAT;
                for (const ExrChannel& c : channels) header.channels().insert(c.name, Imf::Channel(type));
                for (const auto& [key, value] : metadata)  // printable, as the PNG's (png_io.cpp)
                    header.insert(key, Imf::StringAttribute(printable_text(value)));
                FileOStream stream(file, path);
                Imf::OutputFile out(stream, header, 1);
                // One row at a time through a row buffer (the slices' y stride is 0, so every row
                // reads the same buffer): OpenEXR copies the row at writePixels, converts nothing
                // (it refuses float data for half channels), and a cancel stops within a row.
                const std::size_t w = static_cast<std::size_t>(width), n = channels.size();
                std::vector<Imath::half> half_row(pixel == ExrPixel::half ? w * n : 0);
                std::vector<float> float_row(pixel == ExrPixel::float32 ? w * n : 0);
                char* base = pixel == ExrPixel::half ? reinterpret_cast<char*>(half_row.data())
                                                     : reinterpret_cast<char*>(float_row.data());
                const std::size_t channel_bytes = pixel == ExrPixel::half ? sizeof(Imath::half) : sizeof(float);
                Imf::FrameBuffer frame;
                for (std::size_t c = 0; c < n; ++c)
                    frame.insert(channels[c].name, Imf::Slice(type, base + c * channel_bytes, n * channel_bytes, 0));
                out.setFrameBuffer(frame);
                for (int y = 0; y < height; ++y) {
                    if (cancel && cancel->load(std::memory_order_relaxed)) return FileWriteOutcome::cancelled;
                    for (int x = 0; x < width; ++x)
                        for (std::size_t c = 0; c < n; ++c) {
                            const ExrChannel& channel = channels[c];
                            const float v = channel.image ? channel.image->at(x, y)[channel.component] : channel.constant;
                            const std::size_t i = std::size_t(x) * n + c;
                            if (pixel == ExrPixel::half) half_row[i] = Imath::half(v);  // rounds to nearest
                            else float_row[i] = v;
                        }
                    out.writePixels(1);
                }
                return FileWriteOutcome::written;
            } catch (const std::exception& e) {
                error = e.what();
                return FileWriteOutcome::failed;
            }
        },
        cancel, place);
}

}  // namespace caustica
