#include "core/io/exr_io.h"

#include "core/scene/source_location.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfIO.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfStringAttribute.h>
#include <Imath/half.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <mutex>
#include <sys/stat.h>
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

/// Refuses what is not a regular file (a FIFO would block OpenEXR's reader) or does not exist.
void check_regular_file(const std::string& path) {
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0) throw InputError(path + ": " + std::strerror(errno));
    if (!S_ISREG(st.st_mode)) throw InputError(path + ": not a regular file");
}

}  // namespace

bool has_exr_magic(std::span<const unsigned char> bytes) {
    return bytes.size() >= 4 && bytes[0] == 0x76 && bytes[1] == 0x2f && bytes[2] == 0x31 && bytes[3] == 0x01;
}

Image read_exr_image(const std::string& path, const ImageReadLimits& limits) {
    check_regular_file(path);
    limit_openexr_sizes();
    try {
        Imf::InputFile file(path.c_str());
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
    } catch (const InputError&) {
        throw;
    } catch (const std::bad_alloc&) {
        throw InputError(path + ": not enough memory to read this OpenEXR file");
    } catch (const std::exception& e) {
        throw InputError(path + ": not a readable OpenEXR file: " + e.what());
    }
}

ImageMetadata read_exr_metadata(const std::string& path) {
    check_regular_file(path);
    limit_openexr_sizes();
    try {
        Imf::InputFile file(path.c_str());
        ImageMetadata metadata;
        for (auto it = file.header().begin(); it != file.header().end(); ++it)
            if (const auto* text = dynamic_cast<const Imf::StringAttribute*>(&it.attribute()))
                metadata.emplace_back(it.name(), text->value());
        return metadata;
    } catch (const std::exception& e) {
        throw InputError(path + ": not a readable OpenEXR file: " + e.what());
    }
}

void write_exr_atomic(const std::string& path, const Image& image, ExrPixel pixel, const ImageMetadata& metadata,
                      const std::atomic<bool>* cancel) {
    if (image.width <= 0 || image.height <= 0) throw std::runtime_error(path + ": cannot write an empty image");
    write_file_atomic(
        path,
        [&](std::FILE* file, std::string& error) {
            try {
                Imf::Header header(image.width, image.height);  // ZIP compression, increasing Y
                const Imf::PixelType type = pixel == ExrPixel::half ? Imf::HALF : Imf::FLOAT;
                for (const char* name : {"R", "G", "B"}) header.channels().insert(name, Imf::Channel(type));
                for (const auto& [key, value] : metadata) header.insert(key, Imf::StringAttribute(value));
                FileOStream stream(file, path);
                Imf::OutputFile out(stream, header, 1);
                // One row at a time through a row buffer (the slices' y stride is 0, so every row
                // reads the same buffer): OpenEXR copies the row at writePixels, converts nothing
                // (it refuses float data for half channels), and a cancel stops within a row.
                const std::size_t w = static_cast<std::size_t>(image.width);
                std::vector<Imath::half> half_row(pixel == ExrPixel::half ? w * 3 : 0);
                std::vector<float> float_row(pixel == ExrPixel::float32 ? w * 3 : 0);
                char* base = pixel == ExrPixel::half ? reinterpret_cast<char*>(half_row.data())
                                                     : reinterpret_cast<char*>(float_row.data());
                const std::size_t channel_bytes = pixel == ExrPixel::half ? sizeof(Imath::half) : sizeof(float);
                Imf::FrameBuffer frame;
                for (int c = 0; c < 3; ++c)
                    frame.insert(c == 0 ? "R" : c == 1 ? "G" : "B",
                                 Imf::Slice(type, base + c * channel_bytes, 3 * channel_bytes, 0));
                out.setFrameBuffer(frame);
                for (int y = 0; y < image.height; ++y) {
                    if (cancel && cancel->load(std::memory_order_relaxed)) return FileWriteOutcome::cancelled;
                    for (int x = 0; x < image.width; ++x)
                        for (int c = 0; c < 3; ++c) {
                            const float v = image.at(x, y)[c];
                            const std::size_t i = std::size_t(x) * 3 + c;
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
        cancel);
}

}  // namespace caustica
