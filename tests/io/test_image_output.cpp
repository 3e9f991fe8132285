// Image output (docs/OUTPUT.md): tone curves, OpenEXR and PFM writing and reading (round trips
// through OpenEXR's own reader, orientation, metadata), hostile files, and `caustica render -o` by
// extension.
#include "core/io/image_io.h"
#include "core/io/png_io.h"
#include "core/io/tonemap.h"
#include "core/scene/source_location.h"
#include "core/util/sanitized.h"
#include "tests/temp_folder.h"
#include "tests/time_bounds.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfStringAttribute.h>
#include <ImfTiledOutputFile.h>
#include <Imath/half.h>

#include <gtest/gtest.h>

#include <bit>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <optional>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

using namespace caustica;
using caustica::testing::TempFolder;
namespace fs = std::filesystem;

namespace {

/// A small image whose every pixel differs: values across [0, 40], some above 1, one tiny.
Image test_image(int w = 7, int h = 5) {
    Image image(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            image.at(x, y) = {0.013f * float(x + 1) * float(y + 1), 0.5f + float(x) - 0.25f * float(y),
                              std::ldexp(1.0f + 0.1f * float(x), y * 2 - 3)};
    image.at(0, 0) = {0.0f, 40.0f, 1e-4f};
    return image;
}

std::string file_bytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// The pixels of an EXR read with OpenEXR's own reader (not ours), as float RGB.
Image read_with_openexr(const std::string& path, Imf::PixelType* channel_type = nullptr) {
    Imf::InputFile file(path.c_str());
    const Imath::Box2i w = file.header().dataWindow();
    Image image(w.max.x - w.min.x + 1, w.max.y - w.min.y + 1);
    if (channel_type) *channel_type = file.header().channels().findChannel("R")->type;
    Imf::FrameBuffer frame;
    char* base = reinterpret_cast<char*>(image.pixels.data());
    for (int c = 0; c < 3; ++c)
        frame.insert(c == 0 ? "R" : c == 1 ? "G" : "B",
                     Imf::Slice::Make(Imf::FLOAT, base + 4 * c, w, sizeof(glm::vec3), sizeof(glm::vec3) * image.width));
    file.setFrameBuffer(frame);
    file.readPixels(w.min.y, w.max.y);
    return image;
}

/// The message read_image_file throws for `path`, or "" when it reads.
std::string read_error(const std::string& path, const ImageReadLimits& limits = {}) {
    try {
        read_image_file(path, false, limits);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

/// Every file name in `folder` (temporaries included).
std::vector<std::string> listing(const fs::path& folder) {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(folder)) names.push_back(entry.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
}

}  // namespace

// --- tone curves

TEST(Tonemap, ClampIsTheOriginalAndExposureDoublesPerStop) {
    EXPECT_EQ(tonemap_channel(0.0f, Tonemap::clamp, 0.0f), 0.0f);
    EXPECT_EQ(tonemap_channel(0.3f, Tonemap::clamp, 0.0f), 0.3f);
    EXPECT_EQ(tonemap_channel(2.5f, Tonemap::clamp, 0.0f), 1.0f);
    EXPECT_EQ(tonemap_channel(-1.0f, Tonemap::clamp, 0.0f), 0.0f);
    EXPECT_EQ(tonemap_channel(std::nanf(""), Tonemap::clamp, 0.0f), 0.0f);
    for (int stops = -4; stops <= 3; ++stops)  // powers of two: exact
        EXPECT_EQ(tonemap_channel(0.1f, Tonemap::clamp, float(stops)), std::ldexp(0.1f, stops)) << stops;
    EXPECT_EQ(exposure_scale(1.0f), 2.0f);
    EXPECT_EQ(exposure_scale(-2.0f), 0.25f);
    // Every 8-bit value the default writes equals the plain encoder's: bit for bit the original.
    for (float v : {-0.5f, 0.0f, 0.001f, 0.5f, 0.999f, 1.0f, 7.0f})
        EXPECT_EQ(encode_channel(tonemap_channel(v, Tonemap::clamp, 0.0f), PixelEncoding::clamped_linear),
                  encode_channel(v, PixelEncoding::clamped_linear))
            << v;
}

TEST(Tonemap, ReinhardIsXOverOnePlusXPerChannel) {
    EXPECT_EQ(tonemap_channel(1.0f, Tonemap::reinhard, 0.0f), 0.5f);
    EXPECT_EQ(tonemap_channel(3.0f, Tonemap::reinhard, 0.0f), 0.75f);
    EXPECT_FLOAT_EQ(tonemap_channel(1.0f, Tonemap::reinhard, 1.0f), 2.0f / 3.0f);  // 2 / (1 + 2)
    EXPECT_FLOAT_EQ(tonemap_channel(1.0f, Tonemap::reinhard, -1.0f), 1.0f / 3.0f);
    EXPECT_EQ(tonemap_channel(std::numeric_limits<float>::infinity(), Tonemap::reinhard, 0.0f), 1.0f);
    const glm::vec3 mapped = tonemap({1.0f, 3.0f, 0.0f}, Tonemap::reinhard, 0.0f);  // channels apart
    EXPECT_EQ(mapped, glm::vec3(0.5f, 0.75f, 0.0f));
}

TEST(Tonemap, FilmicFollowsTheFittedAcesCurve) {
    auto aces = [](double x) { return std::min(1.0, x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14)); };
    for (float x : {0.01f, 0.18f, 0.5f, 1.0f, 2.0f, 5.0f})
        EXPECT_NEAR(tonemap_channel(x, Tonemap::filmic, 0.0f), aces(x), 1e-6) << x;
    EXPECT_NEAR(tonemap_channel(0.5f, Tonemap::filmic, 0.0f), 0.6425 / 1.0425, 1e-6);  // worked by hand
    EXPECT_NEAR(tonemap_channel(0.25f, Tonemap::filmic, 1.0f), aces(0.5), 1e-6);      // exposure first
    EXPECT_EQ(tonemap_channel(100.0f, Tonemap::filmic, 0.0f), 1.0f);
}

TEST(Tonemap, EveryCurveMapsZeroToZeroRisesAndStaysInTheUnitRange) {
    for (Tonemap op : {Tonemap::clamp, Tonemap::reinhard, Tonemap::filmic}) {
        EXPECT_EQ(tonemap_channel(0.0f, op, 0.0f), 0.0f) << tonemap_name(op);
        float previous = 0.0f;
        for (float x = 1e-4f; x < 1e6f; x *= 1.05f) {
            const float y = tonemap_channel(x, op, 0.0f);
            ASSERT_GE(y, previous) << tonemap_name(op) << " at " << x;
            ASSERT_LE(y, 1.0f) << tonemap_name(op) << " at " << x;
            previous = y;
        }
        EXPECT_GT(previous, 0.99f) << tonemap_name(op);
        for (float huge : {1e30f, std::numeric_limits<float>::infinity()})
            EXPECT_LE(tonemap_channel(huge, op, 0.0f), 1.0f) << tonemap_name(op);
        EXPECT_EQ(parse_tonemap(tonemap_name(op)), op);
    }
    EXPECT_FALSE(parse_tonemap("aces"));
}

// --- formats by name

TEST(ImageFormats, ChosenByExtensionInAnyCase) {
    EXPECT_EQ(image_format_of("a/b.png"), ImageFormat::png);
    EXPECT_EQ(image_format_of("x.EXR"), ImageFormat::exr);
    EXPECT_EQ(image_format_of("x.Pfm"), ImageFormat::pfm);
    EXPECT_FALSE(image_format_of("x.tif"));
    EXPECT_FALSE(image_format_of("exr"));
    EXPECT_FALSE(image_format_of("x.png.bak"));
}

TEST(ImageFormats, DefaultPngIsByteForByteTheDirectWrite) {
    const TempFolder folder("caustica_output");
    const Image image = test_image();
    const ImageMetadata text = {{"Software", "test"}};
    write_png_atomic(folder.file("direct.png"), image, PixelEncoding::clamped_linear, text);
    write_image_atomic(folder.file("chosen.png"), image, ImageWriteSettings{}, text);
    EXPECT_EQ(file_bytes(folder.file("chosen.png")), file_bytes(folder.file("direct.png")));
    const Image prepared = prepare_for_format(image, ImageFormat::png, ImageWriteSettings{});
    EXPECT_EQ(prepared.pixels, image.pixels);
}

TEST(ImageFormats, PngToneCurveAndExposureReachTheBytes) {
    const TempFolder folder("caustica_output");
    const Image image = test_image();
    ImageWriteSettings settings;
    settings.tonemap = Tonemap::reinhard;
    settings.exposure_stops = 1.0f;
    write_image_atomic(folder.file("r.png"), image, settings);
    const Png8 png = read_png(folder.file("r.png"));
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x)
            for (int c = 0; c < 3; ++c) {
                const float v = image.at(x, y)[c] * 2.0f;
                ASSERT_EQ(png.data[(std::size_t(y) * image.width + x) * 3 + c],
                          encode_channel(v / (1.0f + v), PixelEncoding::clamped_linear));
            }
}

// --- OpenEXR

TEST(Exr, FloatRoundTripIsExactThroughOpenExrsOwnReader) {
    const TempFolder folder("caustica_output");
    Image image = test_image();
    image.at(1, 0) = {1e6f, -3.5f, 123456.789f};  // unclamped, beyond half's range, negative
    write_exr_atomic(folder.file("f.exr"), image, ExrPixel::float32);
    Imf::PixelType type{};
    const Image theirs = read_with_openexr(folder.file("f.exr"), &type);
    EXPECT_EQ(type, Imf::FLOAT);
    ASSERT_EQ(theirs.width, image.width);
    ASSERT_EQ(theirs.height, image.height);
    EXPECT_EQ(theirs.pixels, image.pixels);
    EXPECT_EQ(read_image_file(folder.file("f.exr")).pixels, image.pixels);  // ours agrees
}

TEST(Exr, HalfRoundTripIsWithinHalfPrecision) {
    const TempFolder folder("caustica_output");
    const Image image = test_image(9, 4);
    write_exr_atomic(folder.file("h.exr"), image, ExrPixel::half);
    Imf::PixelType type{};
    const Image theirs = read_with_openexr(folder.file("h.exr"), &type);
    EXPECT_EQ(type, Imf::HALF);
    ASSERT_EQ(theirs.pixels.size(), image.pixels.size());
    for (std::size_t i = 0; i < image.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            const float v = image.pixels[i][c], got = theirs.pixels[i][c];
            EXPECT_EQ(got, float(Imath::half(v))) << i;  // rounded to the nearest half
            if (std::fabs(v) >= 6.2e-5f) {  // normal halves: 11 significant bits
                EXPECT_LE(std::fabs(got - v), std::ldexp(std::fabs(v), -11)) << v;
            }
        }
    EXPECT_EQ(read_image_file(folder.file("h.exr")).pixels, theirs.pixels);
    // Top row first, as in our Image: the bright pixel (0, 0) is at OpenEXR's y = 0 (increasing Y).
    EXPECT_EQ(theirs.at(0, 0).y, 40.0f);
}

TEST(Exr, ParametersAreStringAttributesOfTheHeader) {
    const TempFolder folder("caustica_output");
    const ImageMetadata metadata = {{"Software", "caustica test"},
                                    {"caustica:camera", "eye 0 0 5 view 0 0 -1 up 0 1 0 fovy 50"},
                                    {"caustica:options", "--integrator progressive"}};
    write_exr_atomic(folder.file("m.exr"), test_image(), ExrPixel::half, metadata);
    Imf::InputFile file(folder.file("m.exr").c_str());
    for (const auto& [key, value] : metadata) {
        const auto* attribute = file.header().findTypedAttribute<Imf::StringAttribute>(key);
        ASSERT_NE(attribute, nullptr) << key;
        EXPECT_EQ(attribute->value(), value);
    }
    const ImageMetadata ours = read_exr_metadata(folder.file("m.exr"));
    for (const auto& pair : metadata) EXPECT_NE(std::find(ours.begin(), ours.end(), pair), ours.end()) << pair.first;
}

TEST(Metadata, IsWrittenPrintableInBothFormats) {
    // A scene path holding escape sequences (screen clear, window title, clipboard write) and a C1
    // control reaches the file made visible; UTF-8 passes unchanged (docs/RELIABILITY.md, "Script
    // text reaches the user bounded and visible").
    const TempFolder folder("caustica_output");
    const std::string source = "scenes/\x1b[2J\x1b]0;title\x07\x1b]52;c;ZXZpbA==\x07\xc2\x9b" "café.lua";
    const std::string shown = "scenes/\\x1b[2J\\x1b]0;title\\x07\\x1b]52;c;ZXZpbA==\\x07\\u009bcafé.lua";
    const ImageMetadata metadata = {{"Source", source}};
    write_image_atomic(folder.file("m.png"), test_image(), ImageWriteSettings{}, metadata);
    write_image_atomic(folder.file("m.exr"), test_image(), ImageWriteSettings{}, metadata);
    EXPECT_EQ(read_png(folder.file("m.png")).text, (ImageMetadata{{"Source", shown}}));
    EXPECT_EQ(read_exr_metadata(folder.file("m.exr")), (ImageMetadata{{"Source", shown}}));
}

TEST(Exr, CancelledWriteLeavesNothing) {
    const TempFolder folder("caustica_output");
    const std::atomic<bool> cancel{true};
    EXPECT_THROW(write_exr_atomic(folder.file("c.exr"), test_image(), ExrPixel::half, {}, &cancel), ImageWriteCancelled);
    EXPECT_THROW(write_pfm_atomic(folder.file("c.pfm"), test_image(), &cancel), ImageWriteCancelled);
    EXPECT_THROW(write_image_atomic(folder.file("c.png"), test_image(), {}, {}, &cancel), ImageWriteCancelled);
    EXPECT_TRUE(listing(folder.path()).empty()) << listing(folder.path())[0];
}

TEST(Exr, CorruptTruncatedAndOversizedFilesFailNamingTheFile) {
    const TempFolder folder("caustica_output");
    write_exr_atomic(folder.file("good.exr"), test_image(64, 48), ExrPixel::float32);
    const std::string good = file_bytes(folder.file("good.exr"));

    const std::string cut = folder.write("cut.exr", good.substr(0, good.size() / 2));
    EXPECT_EQ(read_error(cut).rfind(cut + ": ", 0), 0u) << read_error(cut);

    const std::string header_only = folder.write("header.exr", good.substr(0, 40));
    EXPECT_EQ(read_error(header_only).rfind(header_only + ": ", 0), 0u) << read_error(header_only);

    const std::string garbage = folder.write("garbage.exr", std::string("\x76\x2f\x31\x01", 4) + std::string(500, '\xff'));
    EXPECT_EQ(read_error(garbage).rfind(garbage + ": ", 0), 0u) << read_error(garbage);

    // A forged data window of 100000 x 100000 pixels: refused from the header, nothing allocated.
    std::string forged = good;
    const std::string key = std::string("dataWindow\0box2i\0", 17);
    const std::size_t at = forged.find(key);
    ASSERT_NE(at, std::string::npos);
    const std::int32_t box[4] = {0, 0, 99999, 99999};  // little-endian on disk, as on x86
    std::memcpy(forged.data() + at + key.size() + 4, box, sizeof box);
    const std::string huge = folder.write("huge.exr", forged);
    const std::string message = read_error(huge);
    EXPECT_EQ(message.rfind(huge + ": ", 0), 0u) << message;

    // Within OpenEXR's limits but over our budget: our message, before the pixels.
    ImageReadLimits small;
    small.max_pixels = 1000;
    EXPECT_EQ(read_error(folder.file("good.exr"), small),
              folder.file("good.exr") + ": 64 x 48 pixels is more than the 1000-pixel image budget");
}

// --- Hostile OpenEXR headers: OpenEXR allocates what an attribute declares before it finds the
// file too short, so our header walk must refuse those sizes first (fast, bounded memory).

namespace {

std::string le32(std::int32_t v) {
    const std::uint32_t u = static_cast<std::uint32_t>(v);
    const char b[4] = {char(u & 0xff), char(u >> 8 & 0xff), char(u >> 16 & 0xff), char(u >> 24 & 0xff)};
    return std::string(b, 4);
}

std::string attribute(const std::string& name, const std::string& type, const std::string& data,
                      std::optional<std::int32_t> size = std::nullopt) {
    return name + '\0' + type + '\0' + le32(size ? *size : std::int32_t(data.size())) + data;
}

/// Offset of the NUL that ends the (single-part) header of an EXR file's bytes.
std::size_t header_end(const std::string& b) {
    std::size_t at = 8;
    for (;;) {
        const std::size_t name_end = b.find('\0', at);
        if (name_end == at) return at;
        const std::size_t type_end = b.find('\0', name_end + 1);
        std::int32_t size;
        std::memcpy(&size, b.data() + type_end + 1, 4);
        at = type_end + 5 + std::size_t(size);
    }
}

/// `exr` (a scan-line file of `chunks` chunks, as our writer makes) with `extra` appended to its
/// header and its chunk offsets moved along: still a valid file.
std::string with_attributes(const std::string& exr, const std::string& extra, int chunks) {
    const std::size_t end = header_end(exr);
    std::string out = exr.substr(0, end) + extra + exr.substr(end);
    for (int i = 0; i < chunks; ++i) {
        std::uint64_t offset;
        char* at = out.data() + end + extra.size() + 1 + 8 * i;
        std::memcpy(&offset, at, 8);
        offset += extra.size();
        std::memcpy(at, &offset, 8);
    }
    return out;
}

/// Runs `read` and returns its InputError message ("" when it read), failing when it took 0.5 s or more.
template <class Read>
std::string fast_error(const std::string& path, Read read) {
    const auto start = std::chrono::steady_clock::now();
    std::string message;
    try {
        read(path);
    } catch (const InputError& e) {
        message = e.what();
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_LT(seconds, caustica::testing::time_bound(0.5)) << path;
    return message;
}

}  // namespace

TEST(ExrHostile, ForgedAttributeSizesFailFastNamingTheFileAndTheAttribute) {
    const TempFolder folder("caustica_output");
    // 29 bytes: magic, version 2, one string attribute claiming 2^31 - 1 bytes.
    const std::string tiny = folder.write(
        "tiny.exr", std::string("\x76\x2f\x31\x01\x02\0\0\0", 8) + attribute("a", "string", std::string(8, '\0'), 0x7fffffff));
    ASSERT_EQ(file_bytes(tiny).size(), 29u);
    EXPECT_EQ(fast_error(tiny, [](const std::string& p) { read_image_file(p); }),
              tiny + ": header attribute 'a' claims 2147483647 bytes, the file has 8 left");
    EXPECT_EQ(fast_error(tiny, read_exr_metadata), tiny + ": header attribute 'a' claims 2147483647 bytes, the file has 8 left");

    write_exr_atomic(folder.file("good.exr"), test_image(7, 5), ExrPixel::half, {{"note", "hello"}});
    const std::string good = file_bytes(folder.file("good.exr"));
    const std::int32_t huge = 0x7fffffff;
    const std::string sv = le32(3) + "abc" + le32(2) + "de";
    const std::pair<std::string, std::string> cases[] = {
        {"string", attribute("s", "string", "hello", huge)},
        {"stringvector", attribute("sv", "stringvector", sv, huge)},
        {"floatvector", attribute("fv", "floatvector", std::string(12, '\0'), huge)},
        {"unknown type", attribute("zz", "someothertype", "1234", huge)},
        {"negative", attribute("n", "string", "x", -1)},
    };
    for (const auto& [what, extra] : cases) {
        const std::string bytes = with_attributes(good, extra, 1);
        const std::string path = folder.write("forged.exr", bytes);
        const std::string name = extra.substr(0, extra.find('\0'));
        const std::size_t left = bytes.size() - (header_end(good) + extra.find('\0', name.size() + 1) + 5);
        const std::string expected = path + ": header attribute '" + name + "' claims " +
                                     (what == "negative" ? "-1" : "2147483647") + " bytes, the file has " +
                                     std::to_string(left) + " left";
        EXPECT_EQ(fast_error(path, [](const std::string& p) { read_image_file(p); }), expected) << what;
        EXPECT_EQ(fast_error(path, read_exr_metadata), expected) << what;
    }

    // An attribute of the valid file itself (our "note") with its size forged.
    std::string forged = good;
    const std::string key = std::string("note\0string\0", 12);
    const std::size_t at = forged.find(key);
    ASSERT_NE(at, std::string::npos);
    forged.replace(at + key.size(), 4, le32(huge));
    const std::string note = folder.write("note.exr", forged);
    EXPECT_EQ(fast_error(note, [](const std::string& p) { read_image_file(p); }),
              note + ": header attribute 'note' claims 2147483647 bytes, the file has " +
                  std::to_string(good.size() - (at + key.size() + 4)) + " left");

    // Sizes inside an attribute: a string vector element, a preview image, a chunk count.
    const std::string element = folder.write("element.exr", with_attributes(good, attribute("sv", "stringvector", le32(huge) + "abcd"), 1));
    EXPECT_EQ(fast_error(element, [](const std::string& p) { read_image_file(p); }),
              element + ": header attribute 'sv' holds a string of 2147483647 bytes, the attribute has 4 left");
    const std::string preview = folder.write("preview.exr", with_attributes(good, attribute("pv", "preview", le32(50000) + le32(50000) + "12345678"), 1));
    EXPECT_EQ(fast_error(preview, [](const std::string& p) { read_image_file(p); }),
              preview + ": header attribute 'pv' claims a 50000 x 50000 preview image in 8 bytes");
    const std::string chunks = folder.write("chunks.exr", with_attributes(good, attribute("chunkCount", "int", le32(huge)), 1));
    EXPECT_EQ(fast_error(chunks, [](const std::string& p) { read_image_file(p); }).rfind(chunks + ": header attribute 'chunkCount' claims 2147483647 chunks", 0), 0u);

    // Names without their NUL, too many attributes, a header over 16 MiB, deep data.
    const std::string unterminated = folder.write("name.exr", std::string("\x76\x2f\x31\x01\x02\0\0\0", 8) + std::string(64, 'n'));
    EXPECT_EQ(fast_error(unterminated, [](const std::string& p) { read_image_file(p); }),
              unterminated + ": an OpenEXR header attribute name is longer than 31 bytes (or not NUL-terminated)");
    std::string many;
    for (int i = 0; i < 1100; ++i) many += attribute(std::string("a").append(std::to_string(i)), "int", le32(i));
    const std::string crowd = folder.write("crowd.exr", with_attributes(good, many, 1));
    EXPECT_EQ(fast_error(crowd, [](const std::string& p) { read_image_file(p); }),
              crowd + ": more than 1024 attributes in an OpenEXR header");
    const std::string big = folder.write("big.exr", with_attributes(good, attribute("big", "string", std::string(17 << 20, 'x')), 1));
    EXPECT_EQ(fast_error(big, [](const std::string& p) { read_image_file(p); }), big + ": the OpenEXR header is larger than 16 MiB");
    std::string deep_bytes = good;
    deep_bytes[5] = char(deep_bytes[5] | 0x08);  // version bit 11: non-image (deep) data
    const std::string deep = folder.write("deep.exr", deep_bytes);
    EXPECT_EQ(fast_error(deep, [](const std::string& p) { read_image_file(p); }), deep + ": deep OpenEXR images are not supported");
}

TEST(ExrHostile, ForgedAttributesAreRefusedWithinBoundedMemory) {
    // Deterministic, not timing: a child process limited to its current address space + 256 MiB
    // reads the 29-byte bomb; OpenEXR alone would try 2 GiB (and fail with "not enough memory",
    // which is why the child insists on the header walk's message). ASan reserves terabytes of
    // address space, so RLIMIT_AS cannot be used there.
    if (sanitized_build) GTEST_SKIP() << "RLIMIT_AS does not work under sanitizers";
    const TempFolder folder("caustica_output");
    const std::string tiny = folder.write(
        "tiny.exr", std::string("\x76\x2f\x31\x01\x02\0\0\0", 8) + attribute("a", "floatvector", std::string(8, '\0'), 0x7fffffff));
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
        long pages = 0;
        if (FILE* statm = std::fopen("/proc/self/statm", "r")) {
            if (std::fscanf(statm, "%ld", &pages) != 1) pages = 0;
            std::fclose(statm);
        }
        const rlim_t limit = rlim_t(pages) * rlim_t(::sysconf(_SC_PAGESIZE)) + (rlim_t(256) << 20);
        const struct rlimit r{limit, limit};
        if (pages == 0 || ::setrlimit(RLIMIT_AS, &r) != 0) ::_exit(3);
        try {
            read_image_file(tiny);
        } catch (const InputError& e) {
            ::_exit(std::string(e.what()).find("header attribute 'a' claims 2147483647 bytes") != std::string::npos ? 0 : 1);
        } catch (...) {
            ::_exit(2);
        }
        ::_exit(4);
    }
    int status = 0;
    ASSERT_EQ(::waitpid(child, &status, 0), child);
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 0);
}

TEST(ExrHostile, ValidFilesWithOtherAttributeKindsAndTilesStillRead) {
    const TempFolder folder("caustica_output");
    const Image image = test_image(7, 40);  // 40 rows: 3 ZIP chunks of 16 lines
    write_exr_atomic(folder.file("f.exr"), image, ExrPixel::float32, {{"note", "hello"}});
    const std::string extra = attribute("sv", "stringvector", le32(3) + "abc" + le32(0) + le32(2) + "de") +
                              attribute("fv", "floatvector", std::string(12, '\0')) +
                              attribute("pv", "preview", le32(2) + le32(1) + "rgbargba") +
                              attribute("chunkCount", "int", le32(3));
    const std::string path = folder.write("multi.exr", with_attributes(file_bytes(folder.file("f.exr")), extra, 3));
    EXPECT_EQ(read_with_openexr(path).pixels, image.pixels);  // the file is valid for OpenEXR itself
    EXPECT_EQ(read_image_file(path).pixels, image.pixels);
    EXPECT_EQ(read_exr_metadata(path), (ImageMetadata{{"note", "hello"}}));

    // A tiled file of 1 x 1 tiles reads; the same header with a forged 8000 x 8000 data window
    // (within the pixel budget) would make OpenEXR allocate 64 M tile offsets: refused.
    {
        Imf::Header header(16, 16);
        header.channels().insert("R", Imf::Channel(Imf::FLOAT));
        header.setTileDescription(Imf::TileDescription(1, 1, Imf::ONE_LEVEL));
        Imf::TiledOutputFile out(folder.file("tiled.exr").c_str(), header, 1);
        std::vector<float> red(256);
        for (int i = 0; i < 256; ++i) red[i] = float(i);
        Imf::FrameBuffer frame;
        frame.insert("R", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(red.data()), 4, 64));
        out.setFrameBuffer(frame);
        out.writeTiles(0, 15, 0, 15);
    }
    const Image tiled = read_image_file(folder.file("tiled.exr"));
    EXPECT_EQ(tiled.at(3, 2), glm::vec3(35.0f, 0.0f, 0.0f));
    std::string forged = file_bytes(folder.file("tiled.exr"));
    const std::string key = std::string("dataWindow\0box2i\0", 17);
    const std::size_t at = forged.find(key);
    ASSERT_NE(at, std::string::npos);
    forged.replace(at + key.size() + 4, 16, le32(0) + le32(0) + le32(7999) + le32(7999));
    const std::string many_tiles = folder.write("tiles.exr", forged);
    EXPECT_EQ(fast_error(many_tiles, [](const std::string& p) { read_image_file(p); }).rfind(
                  many_tiles + ": the OpenEXR tiles need 64000000 chunk offsets (512000000 bytes), the file has ", 0),
              0u);
}

// --- PFM

TEST(Pfm, RoundTripIsExactAndTheFileRunsBottomToTop) {
    const TempFolder folder("caustica_output");
    const Image image = test_image(6, 3);
    write_pfm_atomic(folder.file("p.pfm"), image);
    const std::string bytes = file_bytes(folder.file("p.pfm"));
    const std::string header = "PF\n6 3\n-1.0\n";
    ASSERT_EQ(bytes.substr(0, header.size()), header);
    ASSERT_EQ(bytes.size(), header.size() + 6 * 3 * 3 * 4);
    // The file's last row is the image's top row; its first is the bottom row.
    float last_row_first_pixel[3], first_row_first_pixel[3];
    std::memcpy(last_row_first_pixel, bytes.data() + header.size() + 2 * 6 * 12, 12);
    std::memcpy(first_row_first_pixel, bytes.data() + header.size(), 12);
    EXPECT_EQ(glm::vec3(last_row_first_pixel[0], last_row_first_pixel[1], last_row_first_pixel[2]), image.at(0, 0));
    EXPECT_EQ(glm::vec3(first_row_first_pixel[0], first_row_first_pixel[1], first_row_first_pixel[2]), image.at(0, 2));
    const Image back = read_image_file(folder.file("p.pfm"));
    EXPECT_EQ(back.width, 6);
    EXPECT_EQ(back.height, 3);
    EXPECT_EQ(back.pixels, image.pixels);
}

TEST(Pfm, ReadsBigEndianAndGray) {
    const TempFolder folder("caustica_output");
    auto big_endian = [](float v) {
        const std::uint32_t bits = __builtin_bswap32(std::bit_cast<std::uint32_t>(v));
        return std::string(reinterpret_cast<const char*>(&bits), 4);
    };
    // 1 x 2 colour, big-endian (positive scale): bottom pixel first in the file.
    const std::string colour = folder.write("be.pfm", "PF\n1 2\n1.0\n" + big_endian(1) + big_endian(2) + big_endian(3) +
                                                          big_endian(4) + big_endian(5) + big_endian(6));
    const Image c = read_image_file(colour);
    EXPECT_EQ(c.at(0, 0), glm::vec3(4, 5, 6));
    EXPECT_EQ(c.at(0, 1), glm::vec3(1, 2, 3));
    const float gray_values[2] = {0.25f, 8.0f};  // little-endian gray, 2 x 1
    const std::string gray = folder.write("g.pfm", "Pf 2 1 -1\n" + std::string(reinterpret_cast<const char*>(gray_values), 8));
    const Image g = read_image_file(gray);
    EXPECT_EQ(g.at(0, 0), glm::vec3(0.25f));
    EXPECT_EQ(g.at(1, 0), glm::vec3(8.0f));
}

TEST(Pfm, HostileHeadersAndTruncationFailBeforeAllocating) {
    const TempFolder folder("caustica_output");
    const std::string f = folder.write("t.pfm", "PF\n4 4\n-1.0\n" + std::string(4 * 4 * 12 - 1, '\0'));
    EXPECT_EQ(read_error(f), f + ": truncated PFM: 4 x 4 pixels need 192 bytes of data, the file has 191");
    const std::string huge = folder.write("h.pfm", "PF\n100000 100000\n-1.0\n" + std::string(16, '\0'));
    EXPECT_EQ(read_error(huge), huge + ": 100000 x 100000 pixels is more than the 67108864-pixel image budget");
    const std::string longer = folder.write("l.pfm", "PF\n99999999999 1\n-1.0\n");
    EXPECT_EQ(read_error(longer).rfind(longer + ": PFM header: the width", 0), 0u) << read_error(longer);
    const std::string negative = folder.write("n.pfm", "PF\n-5 3\n-1.0\n");
    EXPECT_EQ(read_error(negative).rfind(negative + ": PFM header: the width", 0), 0u) << read_error(negative);
    const std::string zero = folder.write("z.pfm", "PF\n0 3\n-1.0\n");
    EXPECT_EQ(read_error(zero), zero + ": PFM header: the width is 0");
    const std::string scale = folder.write("s.pfm", "PF\n1 1\nnan\n" + std::string(12, '\0'));
    EXPECT_EQ(read_error(scale).rfind(scale + ": PFM header: the scale", 0), 0u) << read_error(scale);
    const std::string cut = folder.write("c.pfm", "PF\n1 1");
    EXPECT_EQ(read_error(cut).rfind(cut + ": truncated PFM header", 0), 0u) << read_error(cut);
    EXPECT_EQ(read_error(folder.file("absent.pfm")), folder.file("absent.pfm") + ": No such file or directory");
    EXPECT_EQ(read_error(folder.path().string()), folder.path().string() + ": not a regular file");
    const std::string other = folder.write("x.pfm", "P6\n1 1\n255\nabc");
    EXPECT_EQ(read_error(other), other + ": not a PNG, OpenEXR or PFM file");
    EXPECT_EQ(read_error(folder.write("e.pfm", "")), folder.file("e.pfm") + ": the file is empty");
}

TEST(Pfm, LongWhiteSpaceInTheHeaderAndACrLfAfterTheScale) {
    const TempFolder folder("caustica_output");
    const float values[3] = {1.5f, -2.0f, 1e9f};
    const std::string data(reinterpret_cast<const char*>(values), 12);
    // Any white space between the fields (here 600 bytes), as long as the header fits in 4 KiB.
    const std::string spaced = folder.write("w.pfm", "PF" + std::string(300, ' ') + "1" + std::string(300, '\n') + "1 -1\n" + data);
    EXPECT_EQ(read_image_file(spaced).at(0, 0), glm::vec3(1.5f, -2.0f, 1e9f));
    const std::string endless = folder.write("x.pfm", "PF" + std::string(5000, ' ') + "1 1 -1\n" + data);
    EXPECT_EQ(read_error(endless), endless + ": the PFM header is longer than 4096 bytes");
    // "\r\n" after the scale: a two-byte separator when exactly the pixel data follows it...
    const std::string crlf = folder.write("crlf.pfm", "PF\r\n1 1\r\n-1\r\n" + data);
    EXPECT_EQ(read_image_file(crlf).at(0, 0), glm::vec3(1.5f, -2.0f, 1e9f));
    // ...otherwise the format's one byte: here the '\n' is the first byte of the data.
    float first;
    const std::string starts_with_newline = "\n" + data.substr(0, 11);
    std::memcpy(&first, starts_with_newline.data(), 4);
    const std::string cr = folder.write("cr.pfm", "PF\n1 1\n-1\r" + starts_with_newline);
    const glm::vec3 read = read_image_file(cr).at(0, 0);
    EXPECT_EQ(std::bit_cast<std::uint32_t>(read.x), std::bit_cast<std::uint32_t>(first));
    float second;
    std::memcpy(&second, starts_with_newline.data() + 4, 4);
    EXPECT_EQ(std::bit_cast<std::uint32_t>(read.y), std::bit_cast<std::uint32_t>(second));
    // One byte too many after "\r\n" is neither: the data is one byte longer than 12 with either reading.
    const std::string extra = folder.write("e2.pfm", "PF\n1 1\n-1\r\n" + data + "z");
    EXPECT_EQ(std::bit_cast<std::uint32_t>(read_image_file(extra).at(0, 0).x),
              std::bit_cast<std::uint32_t>(std::bit_cast<float>(std::uint32_t(0x0a) | std::bit_cast<std::uint32_t>(1.5f) << 8)));
}

TEST(Png, ReadsAsLinearOrSrgbDecodedFloats) {
    const TempFolder folder("caustica_output");
    Image image(2, 1);
    image.at(0, 0) = glm::vec3(1.0f, 0.5f, 0.0f);
    image.at(1, 0) = glm::vec3(0.2f);
    write_png_atomic(folder.file("p.png"), image, PixelEncoding::clamped_linear);
    const Image linear = read_image_file(folder.file("p.png"));
    EXPECT_EQ(linear.at(0, 0), glm::vec3(1.0f, 127 / 255.0f, 0.0f));  // 0.5 -> 127, truncated
    EXPECT_EQ(linear.at(1, 0), glm::vec3(51 / 255.0f));
    const Image decoded = read_image_file(folder.file("p.png"), true);
    EXPECT_NEAR(decoded.at(0, 0).y, std::pow((127 / 255.0 + 0.055) / 1.055, 2.4), 1e-6);
    const std::string bad = folder.write("bad.png", std::string("\x89PNG\r\n\x1a\n", 8) + "nonsense");
    EXPECT_NE(read_error(bad).find(bad), std::string::npos) << read_error(bad);
}

// --- the command line

namespace {

struct CliRun {
    int code = -1;
    std::string output;
};

CliRun caustica_in(const fs::path& dir, const std::string& args) {
    const std::string command = "cd '" + dir.string() + "' && '" CAUSTICA_BINARY "' " + args + " 2>&1";
    CliRun r;
    FILE* pipe = ::popen(command.c_str(), "r");
    char buffer[4096];
    for (std::size_t n; (n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0;) r.output.append(buffer, n);
    const int status = ::pclose(pipe);
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return r;
}

// A bright light, so that some pixels pass 1 and clamping, tone curves and exposure all matter.
const char* bright_scene =
    "m = gr.material({0.8, 0.5, 0.2}, {0.6, 0.6, 0.6}, 20)\n"
    "s = gr.nh_sphere('s', {0, 0, 0}, 1)\n"
    "s:set_material(m)\n"
    "root = gr.node('root')\n"
    "root:add_child(s)\n"
    "l = gr.light({5, 5, 5}, {4, 4, 4}, {1, 0, 0})\n"
    "gr.render(root, 'out.png', 12, 9, {0, 0, 5}, {0, 0, -1}, {0, 1, 0}, 50, {0.1, 0.1, 0.1}, {l})\n";

}  // namespace

TEST(OutputCli, ExrPfmAndPngHoldTheSameRenderedValues) {
    const TempFolder folder("caustica_output_cli");
    folder.write("scene.lua", bright_scene);
    ASSERT_EQ(caustica_in(folder.path(), "render -s --reproducible scene.lua -o x.pfm").code, 0);
    ASSERT_EQ(caustica_in(folder.path(), "render -s --reproducible scene.lua -o x.exr --exr-pixel float").code, 0);
    ASSERT_EQ(caustica_in(folder.path(), "render -s --reproducible scene.lua -o x.png").code, 0);
    ASSERT_EQ(caustica_in(folder.path(), "render -s --reproducible scene.lua -o e.pfm --exposure -1").code, 0);
    ASSERT_EQ(caustica_in(folder.path(), "render -s --reproducible scene.lua -o f.png --tonemap filmic").code, 0);
    const Image pfm = read_image_file(folder.file("x.pfm"));
    ASSERT_EQ(pfm.width, 12);
    ASSERT_EQ(pfm.height, 9);
    EXPECT_EQ(read_with_openexr(folder.file("x.exr")).pixels, pfm.pixels);
    float brightest = 0.0f;
    for (const glm::vec3& p : pfm.pixels) brightest = std::max({brightest, p.x, p.y, p.z});
    EXPECT_GT(brightest, 1.0f) << "the scene must pass 1 for this test to mean anything";
    const Png8 png = read_png(folder.file("x.png")), filmic = read_png(folder.file("f.png"));
    const Image half_exposed = read_image_file(folder.file("e.pfm"));
    for (std::size_t i = 0; i < pfm.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            const float v = pfm.pixels[i][c];
            ASSERT_EQ(png.data[i * 3 + c], encode_channel(v, PixelEncoding::clamped_linear)) << i;
            ASSERT_EQ(filmic.data[i * 3 + c],
                      encode_channel(tonemap_channel(v, Tonemap::filmic, 0.0f), PixelEncoding::clamped_linear));
            ASSERT_EQ(half_exposed.pixels[i][c], v * 0.5f);
        }
    // The parameters travel in the EXR header.
    const ImageMetadata metadata = read_exr_metadata(folder.file("x.exr"));
    auto value_of = [&](const std::string& key) {
        for (const auto& [k, v] : metadata)
            if (k == key) return v;
        return std::string("(missing)");
    };
    EXPECT_EQ(value_of("Source"), "scene.lua");
    EXPECT_EQ(value_of("caustica:camera"), "eye 0 0 5 view 0 0 -1 up 0 1 0 fovy 50");
    EXPECT_EQ(value_of("caustica:integrator"), "classic");
    EXPECT_EQ(value_of("caustica:options"), "--silent --reproducible --exr-pixel float");
    EXPECT_EQ(value_of("caustica:size"), "12x9");
    EXPECT_EQ(value_of("Software").rfind("caustica ", 0), 0u);
    EXPECT_EQ(listing(folder.path()),
              (std::vector<std::string>{"e.pfm", "f.png", "scene.lua", "x.exr", "x.pfm", "x.png"}));
}

TEST(OutputCli, UnknownExtensionIsRefusedBeforeRenderingAndMissingFoldersExit1) {
    const TempFolder folder("caustica_output_cli");
    folder.write("scene.lua", bright_scene);
    const CliRun tif = caustica_in(folder.path(), "render -v scene.lua -o x.tif");
    EXPECT_EQ(tif.code, 2);
    EXPECT_EQ(tif.output, "caustica: -o x.tif: the output must end in .png, .exr or .pfm\n");
    for (const char* name : {"nodir/x.png", "nodir/x.exr", "nodir/x.pfm"}) {
        const CliRun r = caustica_in(folder.path(), std::string("render -v scene.lua -o ") + name);
        EXPECT_EQ(r.code, 1) << name << ": " << r.output;
        EXPECT_EQ(r.output, std::string("caustica: -o: cannot write '") + name + "': folder 'nodir' does not exist\n");
    }
    const CliRun file_in_the_way = caustica_in(folder.path(), "render scene.lua -o scene.lua/x.exr");
    EXPECT_EQ(file_in_the_way.code, 1);
    EXPECT_EQ(file_in_the_way.output, "caustica: -o: cannot write 'scene.lua/x.exr': 'scene.lua' is not a folder\n");
    std::string scene = bright_scene;
    scene.replace(scene.find("'out.png'"), 9, "'nodir/out.exr'");
    folder.write("exr.lua", scene);
    const CliRun from_script = caustica_in(folder.path(), "render exr.lua");
    EXPECT_EQ(from_script.code, 1) << from_script.output;
    EXPECT_EQ(listing(folder.path()), (std::vector<std::string>{"exr.lua", "scene.lua"}));
}

TEST(OutputCli, AttachedShortValuesAndStatisticsOnce) {
    const TempFolder folder("caustica_output_cli");
    folder.write("scene.lua", bright_scene);
    const CliRun threads = caustica_in(folder.path(), "render -j2 -S -t scene.lua -o x.png");
    ASSERT_EQ(threads.code, 0) << threads.output;
    EXPECT_NE(threads.output.find("  threads                        2\n"), std::string::npos) << threads.output;
    auto count = [&](const std::string& what) {
        std::size_t n = 0;
        for (std::size_t at = threads.output.find(what); at != std::string::npos; at = threads.output.find(what, at + 1)) ++n;
        return n;
    };
    EXPECT_EQ(count("statistics:"), 1u);
    EXPECT_EQ(count("scene build"), 1u) << threads.output;  // stage times once, not under -t and -S both
    const CliRun bundled = caustica_in(folder.path(), "render -sj1 scene.lua -o y.png");
    EXPECT_EQ(bundled.code, 2);
    EXPECT_NE(bundled.output.find("'-j' is not a short flag"), std::string::npos) << bundled.output;
    EXPECT_EQ(caustica_in(folder.path(), "render -St -j 1 -s scene.lua -o z.png").code, 0);
}

TEST(OutputCli, AKilledRunsExrTemporaryIsRemovedByTheNextRun) {
    // The EXR and PFM writers share the PNG's temporaries: a run killed mid-write (SIGKILL cannot
    // be handled) leaves ".NAME.caustica-tmp-HOST-PID-N"; the next run writing there removes it.
    const TempFolder folder("caustica_output_cli");
    folder.write("scene.lua", bright_scene);
    char host[256] = {};
    ::gethostname(host, sizeof host - 1);
    std::string tag;
    for (const char* c = host; *c && tag.size() < 40; ++c)
        tag += (std::isalnum(static_cast<unsigned char>(*c)) || *c == '.' || *c == '_') ? *c : '_';
    const pid_t gone = ::fork();  // a process id that existed and no longer runs
    if (gone == 0) ::_exit(0);
    ::waitpid(gone, nullptr, 0);
    const std::string stale = ".x.exr.caustica-tmp-" + tag + "-" + std::to_string(gone) + "-0";
    folder.write(stale, "half an EXR");
    folder.write(".x.exr.caustica-tmp-elsewhere-1-0", "another host's: kept");
    ASSERT_EQ(caustica_in(folder.path(), "render -s scene.lua -o x.pfm").code, 0);
    EXPECT_EQ(listing(folder.path()),
              (std::vector<std::string>{".x.exr.caustica-tmp-elsewhere-1-0", "scene.lua", "x.pfm"}));
}
