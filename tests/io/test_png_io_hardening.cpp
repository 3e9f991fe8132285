// PNG reading and writing against hostile files and signals: a declared size, a chunk length or
// a decompression bomb is refused before libpng allocates (checked in a child process under an
// address-space limit, with its peak memory measured); a cancelled or signalled write leaves no
// temporary; temporaries of killed runs are removed by the next write, and only those.
#include "core/io/png_io.h"
#include "core/util/sanitized.h"
#include "tests/time_bounds.h"

#include <gtest/gtest.h>
#include <zlib.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

namespace fs = std::filesystem;
using caustica::Image;
using caustica::Png8;
using caustica::PngReadLimits;

namespace {

constexpr bool sanitized = caustica::sanitized_build;

/// Sanitized builds carry shadow memory: memory bounds widen for them, never otherwise (time
/// bounds: time_bounds.h).
constexpr long kib_bound(long mib) { return (sanitized ? 2 * mib + 64 : mib) * 1024; }

using Bytes = std::string;  // PNG bytes built by hand

void put_32(Bytes& out, std::uint32_t v) {
    for (int shift = 24; shift >= 0; shift -= 8) out += static_cast<char>((v >> shift) & 0xff);
}

/// One chunk with a correct CRC; `declared` overrides the length field (a lying chunk).
Bytes chunk(const std::string& type, const Bytes& body, long long declared = -1) {
    Bytes out;
    put_32(out, declared >= 0 ? static_cast<std::uint32_t>(declared) : static_cast<std::uint32_t>(body.size()));
    const Bytes typed = type + body;
    out += typed;
    put_32(out, static_cast<std::uint32_t>(::crc32(0, reinterpret_cast<const Bytef*>(typed.data()), typed.size())));
    return out;
}

Bytes ihdr(std::uint32_t width, std::uint32_t height, int depth, int colour_type, int interlace = 0) {
    Bytes body;
    put_32(body, width);
    put_32(body, height);
    body += static_cast<char>(depth);
    body += static_cast<char>(colour_type);
    body += '\0';
    body += '\0';
    body += static_cast<char>(interlace);
    return chunk("IHDR", body);
}

const Bytes signature("\x89PNG\r\n\x1a\n", 8);

Bytes zlib_compress(const Bytes& raw) {
    uLongf size = ::compressBound(raw.size());
    Bytes out(size, '\0');
    EXPECT_EQ(::compress2(reinterpret_cast<Bytef*>(out.data()), &size, reinterpret_cast<const Bytef*>(raw.data()),
                          raw.size(), 9),
              Z_OK);
    out.resize(size);
    return out;
}

/// A PNG of `height` rows of `row_bytes` zero bytes (plus the filter byte of each row), as a
/// real zlib stream made without inflating memory: each row is deflated after a full flush, so
/// every row after the first compresses to the same bytes, repeated; the Adler-32 of n zero
/// bytes is (n mod 65521) << 16 | 1. A 16384 x 16384 RGBA image is about 1 MB.
Bytes zero_png(std::uint32_t width, std::uint32_t height, int colour_type, std::size_t row_bytes) {
    z_stream z{};
    EXPECT_EQ(::deflateInit(&z, 9), Z_OK);
    const Bytes row(row_bytes + 1, '\0');
    auto deflate_row = [&](int flush) {
        Bytes out(::deflateBound(&z, row.size()) + 64, '\0');
        z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(row.data()));
        z.avail_in = flush == Z_FINISH ? 0 : static_cast<uInt>(row.size());
        z.next_out = reinterpret_cast<Bytef*>(out.data());
        z.avail_out = static_cast<uInt>(out.size());
        ::deflate(&z, flush);
        out.resize(out.size() - z.avail_out);
        return out;
    };
    const Bytes first = deflate_row(Z_FULL_FLUSH);
    const Bytes repeated = deflate_row(Z_FULL_FLUSH);
    Bytes end = deflate_row(Z_FINISH);
    ::deflateEnd(&z);
    end.resize(end.size() - 4);  // the Adler-32 of two rows: replaced by that of all of them
    const std::uint64_t total = std::uint64_t(height) * row.size();
    Bytes idat = first;
    idat.reserve(first.size() + repeated.size() * height + end.size() + 4);
    for (std::uint32_t y = 1; y < height; ++y) idat += repeated;
    idat += end;
    put_32(idat, static_cast<std::uint32_t>((total % 65521) << 16 | 1));
    return signature + ihdr(width, height, 8, colour_type) + chunk("IDAT", idat) + chunk("IEND", "");
}

/// A small valid image: `width` x `height`, the given colour type, 8-bit, rows of zeros.
Bytes small_png(std::uint32_t width, std::uint32_t height, int colour_type, int depth = 8, const Bytes& extra = "") {
    const int channels = colour_type == 0 || colour_type == 3 ? 1 : colour_type == 4 ? 2 : colour_type == 2 ? 3 : 4;
    const std::size_t row = (std::size_t(width) * channels * depth + 7) / 8;
    Bytes raw;
    for (std::uint32_t y = 0; y < height; ++y) raw += Bytes(1, '\0') + Bytes(row, static_cast<char>(y * 16));
    return signature + ihdr(width, height, depth, colour_type) + extra + chunk("IDAT", zlib_compress(raw)) +
           chunk("IEND", "");
}

std::span<const unsigned char> as_span(const Bytes& b) {
    return {reinterpret_cast<const unsigned char*>(b.data()), b.size()};
}

/// What a read in a child process did.
struct Outcome {
    enum Kind { refused, decoded, out_of_memory, crashed } kind = crashed;
    std::string message;       ///< the error message, or "W x H x C" when decoded
    long peak_kib = -1;        ///< growth of the child's resident set above its size at the start
    double seconds = 0.0;
};

long status_kib(const char* field) {
    std::ifstream in("/proc/self/status");
    std::string line;
    while (std::getline(in, line))
        if (line.rfind(field, 0) == 0) return std::stol(line.substr(std::strlen(field)));
    return -1;
}

/// Runs `read` in a forked child under an address-space limit of its current size plus
/// `headroom_mib` (not under sanitizers, whose shadow memory cannot live with one), with a
/// 20-second alarm, and reports how it ended and its peak memory growth.
Outcome run_bounded(const std::function<Png8()>& read, long headroom_mib = 256) {
    int pipe_fds[2];
    EXPECT_EQ(::pipe(pipe_fds), 0);
    const auto t0 = std::chrono::steady_clock::now();
    const pid_t pid = ::fork();
    if (pid == 0) {
        ::close(pipe_fds[0]);
        std::ofstream("/proc/self/clear_refs") << "5";  // resets the peak (VmHWM) to the current size
        const long start = status_kib("VmRSS:");
        if (!sanitized) {
            const rlim_t limit = rlim_t(status_kib("VmSize:") + headroom_mib * 1024) * 1024;
            const rlimit as{limit, limit};
            ::setrlimit(RLIMIT_AS, &as);
        }
        ::alarm(20);
        char kind = 'c';
        std::string message;
        try {
            const Png8 png = read();
            kind = 'd';
            message = std::to_string(png.width) + " x " + std::to_string(png.height) + " x " + std::to_string(png.channels);
        } catch (const std::bad_alloc&) {
            kind = 'm';
        } catch (const std::exception& e) {
            kind = 'r';
            message = e.what();
        }
        const std::string report = kind + std::to_string(status_kib("VmHWM:") - start) + "\n" + message;
        (void)!::write(pipe_fds[1], report.data(), report.size());
        ::_exit(0);
    }
    ::close(pipe_fds[1]);
    std::string report;
    char buffer[4096];
    for (ssize_t n; (n = ::read(pipe_fds[0], buffer, sizeof buffer)) > 0;) report.append(buffer, std::size_t(n));
    ::close(pipe_fds[0]);
    int status = 0;
    ::waitpid(pid, &status, 0);
    Outcome out;
    out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (!WIFEXITED(status) || report.empty()) return out;
    const std::size_t newline = report.find('\n');
    out.kind = report[0] == 'r' ? Outcome::refused : report[0] == 'd' ? Outcome::decoded : Outcome::out_of_memory;
    out.peak_kib = std::stol(report.substr(1, newline - 1));
    out.message = report.substr(newline + 1);
    return out;
}

std::string describe(const Outcome& o) {
    static const char* kinds[] = {"refused", "decoded", "out of memory", "crashed or timed out"};
    return std::string(kinds[o.kind]) + ": '" + o.message + "', peak +" + std::to_string(o.peak_kib) + " KiB, " +
           std::to_string(o.seconds) + " s";
}

/// Expects a refusal naming `fragment`, in under 2 s and `max_mib` of memory growth.
void expect_refused_cheaply(const Bytes& png, const std::string& fragment, long max_mib = 32) {
    const Outcome o = run_bounded([&] { return caustica::read_png_memory(as_span(png), "tex.png", {}); });
    EXPECT_EQ(o.kind, Outcome::refused) << describe(o);
    EXPECT_NE(o.message.find("tex.png: " + fragment), std::string::npos) << describe(o);
    EXPECT_LT(o.peak_kib, kib_bound(max_mib)) << describe(o);
    EXPECT_LT(o.seconds, caustica::testing::time_bound(2.0)) << describe(o);
}

}  // namespace

// --- reading ------------------------------------------------------------------------------------

TEST(PngReadHardening, HugeDeclaredSizeIsRefusedBeforeAnyPixelIsAllocated) {
    // 100000 x 100000 RGB would be 30 GB; the IDAT is a few bytes.
    const Bytes png = signature + ihdr(100000, 100000, 8, 2) + chunk("IDAT", zlib_compress(Bytes(1000, '\0'))) +
                      chunk("IEND", "");
    expect_refused_cheaply(png, "100000 x 100000 pixels is more than the 67108864-pixel image budget");
    // Within the pixel budget, a row longer than the width limit: libpng's row buffers stay small.
    expect_refused_cheaply(signature + ihdr(70000, 1, 8, 2) + chunk("IDAT", zlib_compress(Bytes(1, '\0'))) +
                               chunk("IEND", ""),
                           "70000 x 1 pixels: the width is more than the 65536 allowed");
    // The largest size PNG can declare.
    expect_refused_cheaply(signature + ihdr(0x7fffffff, 1, 8, 2) + chunk("IEND", ""),
                           "2147483647 x 1 pixels is more than the 67108864-pixel image budget");
}

TEST(PngReadHardening, AChunkLongerThanTheFileIsRefusedWithoutAllocatingIt) {
    // The 44-byte file of the audit: a tEXt chunk declaring 2 GiB made libpng allocate 2 GB.
    const Bytes png = signature + ihdr(8, 8, 8, 2) + chunk("tEXt", "abc", 0x7ffffff0).substr(0, 11);
    ASSERT_EQ(png.size(), 44u);
    expect_refused_cheaply(png, "chunk 'tEXt' at byte 33 declares 2147483632 bytes but only 3 remain in the file");
    // The same lie on IDAT, with the whole chunk present otherwise.
    expect_refused_cheaply(signature + ihdr(8, 8, 8, 2) + chunk("IDAT", "xyz", 0x40000000) + chunk("IEND", ""),
                           "chunk 'IDAT' at byte 33 declares 1073741824 bytes but only 19 remain in the file");
}

TEST(PngReadHardening, DecompressionBombIsRefusedByTheBudget) {
    // 16384 x 16384 RGBA zeros: about 1 MB on disk, 1 GiB decoded.
    const Bytes bomb = zero_png(16384, 16384, 6, 16384 * 4);
    EXPECT_LT(bomb.size(), 2u << 20);
    expect_refused_cheaply(bomb, "16384 x 16384 pixels is more than the 67108864-pixel image budget");
    PngReadLimits texture;
    texture.budget_name = "texture";
    EXPECT_THROW(
        {
            try {
                caustica::read_png_header(as_span(bomb), "bomb.png", texture);
            } catch (const std::runtime_error& e) {
                EXPECT_STREQ(e.what(), "bomb.png: 16384 x 16384 pixels is more than the 67108864-pixel texture budget");
                throw;
            }
        },
        std::runtime_error);
}

TEST(PngReadHardening, TheBombGeneratorMakesRealImagesAndTheBudgetIsWhatDecides) {
    // The same construction at 2048 x 2048 decodes (so the bomb above is a real image), costs
    // its decoded size, and is refused once the budget is smaller than it.
    const Bytes png = zero_png(2048, 2048, 6, 2048 * 4);
    const Outcome ok = run_bounded([&] { return caustica::read_png_memory(as_span(png), "z.png", {}); });
    EXPECT_EQ(ok.kind, Outcome::decoded) << describe(ok);
    EXPECT_EQ(ok.message, "2048 x 2048 x 4");
    EXPECT_LT(ok.peak_kib, kib_bound(16 + 8)) << describe(ok);  // 16 MiB of pixels, little else
    PngReadLimits small;
    small.max_pixels = 1 << 20;
    try {
        caustica::read_png_memory(as_span(png), "z.png", small);
        ADD_FAILURE() << "decoded over budget";
    } catch (const std::runtime_error& e) {
        EXPECT_STREQ(e.what(), "z.png: 2048 x 2048 pixels is more than the 1048576-pixel image budget");
    }
}

TEST(PngReadHardening, CompressedTextCannotInflateAcrossManyChunks) {
    // 1000 zTXt chunks of 1 MiB of 'A' each: 1 GiB of text from a 1 MB file. Compressed text is
    // skipped (chunk_malloc_max alone bounds one chunk, not the sum); plain tEXt is kept.
    const Bytes text = chunk("zTXt", Bytes("k\0\0", 3) + zlib_compress(Bytes(1 << 20, 'A')));
    Bytes many;
    for (int i = 0; i < 1000; ++i) many += text;
    const Bytes png = small_png(8, 8, 2, 8, chunk("tEXt", Bytes("Software\0caustica", 17)) + many);
    const Outcome o = run_bounded([&] { return caustica::read_png_memory(as_span(png), "t.png", {}); });
    EXPECT_EQ(o.kind, Outcome::decoded) << describe(o);
    EXPECT_LT(o.peak_kib, kib_bound(32)) << describe(o);
    const Png8 decoded = caustica::read_png_memory(as_span(png), "t.png");
    ASSERT_EQ(decoded.text.size(), 1u);
    EXPECT_EQ(decoded.text[0].first, "Software");
    EXPECT_EQ(decoded.text[0].second, "caustica");
}

TEST(PngReadHardening, ManyChunksAreBoundedByTheChunkCache) {
    Bytes many;
    for (int i = 0; i < 100000; ++i) many += chunk("tEXt", Bytes("k\0v", 3));
    const Bytes png = small_png(8, 8, 2, 8, many);
    const Outcome o = run_bounded([&] { return caustica::read_png_memory(as_span(png), "t.png", {}); });
    EXPECT_EQ(o.kind, Outcome::decoded) << describe(o);
    EXPECT_LT(o.peak_kib, kib_bound(32)) << describe(o);
    EXPECT_LT(o.seconds, caustica::testing::time_bound(2.0)) << describe(o);
    EXPECT_LE(caustica::read_png_memory(as_span(png), "t.png").text.size(), 1000u);
}

TEST(PngReadHardening, MalformedFilesAreRefusedWithTheReason) {
    const Bytes good = small_png(64, 64, 2);
    const auto reason = [](const Bytes& png) -> std::string {
        try {
            caustica::read_png_memory(as_span(png), "m.png");
            return "decoded";
        } catch (const std::runtime_error& e) {
            return e.what();
        }
    };
    EXPECT_EQ(reason(""), "m.png: not a PNG file");
    EXPECT_EQ(reason("GIF89a........"), "m.png: not a PNG file");
    EXPECT_EQ(reason(signature), "m.png: truncated: no IHDR header");
    EXPECT_EQ(reason(good.substr(0, 20)), "m.png: chunk 'IHDR' at byte 8 declares 13 bytes but only 4 remain in the file");
    EXPECT_EQ(reason(good.substr(0, 12)), "m.png: truncated: a chunk is cut off at byte 8");
    EXPECT_EQ(reason(good.substr(0, 31)), "m.png: truncated: the CRC of chunk 'IHDR' is cut off");
    EXPECT_EQ(reason(good.substr(0, good.size() - 12)), "m.png: truncated: no IEND chunk");
    EXPECT_EQ(reason(signature + chunk("IDAT", "x") + chunk("IEND", "")), "m.png: the first chunk is not a valid IHDR header");
    EXPECT_EQ(reason(signature + ihdr(0, 0, 8, 2) + chunk("IEND", "")),
              "m.png: the header declares an empty image (0 x 0 pixels)");
    EXPECT_EQ(reason(signature + ihdr(8, 8, 8, 5) + chunk("IEND", "")), "m.png: the header declares an unknown colour type 5");
    EXPECT_EQ(reason(signature + ihdr(8, 8, 7, 2) + chunk("IEND", "")),
              "m.png: the header declares bit depth 7, which colour type 2 does not allow");
    EXPECT_EQ(reason(signature + ihdr(8, 8, 8, 2, 2) + chunk("IEND", "")),
              "m.png: the header declares an unknown compression, filter or interlace method");
    // Errors libpng finds: bad CRCs of critical chunks, missing palette, too little image data.
    Bytes bad_crc = good;
    bad_crc[29] ^= 1;  // the last CRC byte of IHDR
    EXPECT_EQ(reason(bad_crc).rfind("m.png: ", 0), 0u);
    EXPECT_NE(reason(bad_crc), "decoded");
    EXPECT_NE(reason(small_png(8, 8, 3)), "decoded");  // palette image without PLTE
    const Bytes short_data = signature + ihdr(64, 64, 8, 2) + chunk("IDAT", zlib_compress(Bytes(100, '\0'))) +
                             chunk("IEND", "");
    EXPECT_NE(reason(short_data), "decoded");
    EXPECT_EQ(reason(short_data).rfind("m.png: ", 0), 0u);
}

TEST(PngReadHardening, EveryColourTypeStillDecodesTo8Bits) {
    struct Case {
        int colour_type, depth, channels;
    };
    for (const Case c : {Case{0, 1, 1}, Case{0, 8, 1}, Case{0, 16, 1}, Case{2, 8, 3}, Case{2, 16, 3}, Case{4, 8, 2},
                         Case{6, 16, 4}}) {
        const Bytes png = small_png(8, 8, c.colour_type, c.depth);
        const caustica::PngHeader h = caustica::read_png_header(as_span(png), "c.png");
        EXPECT_EQ(h.channels, c.channels) << c.colour_type << "/" << c.depth;
        EXPECT_EQ(h.decoded_bytes(), 64u * c.channels);
        const Png8 decoded = caustica::read_png_memory(as_span(png), "c.png");
        EXPECT_EQ(decoded.width, 8);
        EXPECT_EQ(decoded.channels, c.channels) << c.colour_type << "/" << c.depth;
        EXPECT_EQ(decoded.data.size(), 64u * c.channels);
        EXPECT_EQ(decoded.data[8 * c.channels * 2], c.depth == 1 ? 0 : 32) << c.colour_type << "/" << c.depth;  // row 2
    }
    // A palette with transparency becomes RGBA; the header says so before decoding.
    const Bytes palette = signature + ihdr(4, 4, 8, 3) + chunk("PLTE", Bytes("\xff\x00\x00\x00\xff\x00", 6)) +
                          chunk("tRNS", Bytes("\x80", 1)) + chunk("IDAT", zlib_compress(Bytes(4 * 5, '\0'))) +
                          chunk("IEND", "");
    EXPECT_EQ(caustica::read_png_header(as_span(palette), "p.png").channels, 4);
    const Png8 rgba = caustica::read_png_memory(as_span(palette), "p.png");
    ASSERT_EQ(rgba.channels, 4);
    EXPECT_EQ(rgba.data[0], 255);  // index 0: red, alpha 0x80
    EXPECT_EQ(rgba.data[3], 128);
}

TEST(PngReadHardening, ReadPngReadsOnlyRegularFilesOfBoundedSize) {
    const fs::path dir = fs::temp_directory_path() / ("caustica_png_read_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    const std::string fifo = (dir / "fifo.png").string();
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    const auto t0 = std::chrono::steady_clock::now();
    try {
        caustica::read_png(fifo);
        ADD_FAILURE() << "read a FIFO";
    } catch (const std::runtime_error& e) {
        EXPECT_EQ(std::string(e.what()), "cannot open '" + fifo + "': not a regular file");
    }
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), caustica::testing::time_bound(1.0));
    EXPECT_THROW(caustica::read_png(dir.string()), std::runtime_error);

    const std::string file = (dir / "a.png").string();
    std::ofstream(file, std::ios::binary) << small_png(8, 8, 2);
    EXPECT_EQ(caustica::read_png(file).width, 8);
    PngReadLimits tiny;
    tiny.max_file_bytes = 50;
    try {
        caustica::read_png(file, tiny);
        ADD_FAILURE() << "read past the size cap";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("more than the 50 allowed"), std::string::npos) << e.what();
    }
    std::ofstream(file, std::ios::binary) << "not a png";
    EXPECT_THROW(
        {
            try {
                caustica::read_png(file);
            } catch (const std::runtime_error& e) {
                EXPECT_EQ(std::string(e.what()), "'" + file + "' is not a PNG file");
                throw;
            }
        },
        std::runtime_error);
    fs::remove_all(dir);
}

// --- writing ------------------------------------------------------------------------------------

namespace {

class PngWrite : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() / ("caustica_png_write_" + std::to_string(::getpid()) + "_" +
                                            ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }

    /// Names in the folder, hidden ones included.
    std::vector<std::string> files() const {
        std::vector<std::string> names;
        for (const auto& e : fs::directory_iterator(dir_)) names.push_back(e.path().filename().string());
        std::sort(names.begin(), names.end());
        return names;
    }

    /// The temporary of a write in progress, or "" when there is none.
    std::string temporary() const {
        for (const std::string& n : files())
            if (n.find(".caustica-tmp-") != std::string::npos) return n;
        return {};
    }

    /// A noisy image, so that deflate works for its time (about a second for 4000 x 4000).
    static Image noisy(int size) {
        Image image(size, size);
        std::uint32_t state = 12345;
        for (glm::vec3& p : image.pixels)
            for (int c = 0; c < 3; ++c) {
                state = state * 1664525u + 1013904223u;
                p[c] = float(state >> 8) / float(1 << 24);
            }
        return image;
    }

    fs::path dir_;
};

}  // namespace

TEST_F(PngWrite, ARaisedCancelFlagWritesNothingAndKeepsTheOldFile) {
    const std::string out = (dir_ / "out.png").string();
    std::ofstream(out) << "OLD";
    std::atomic<bool> cancel{true};
    EXPECT_THROW(caustica::write_png_atomic(out, noisy(64), caustica::PixelEncoding::clamped_linear, {}, &cancel),
                 caustica::ImageWriteCancelled);
    EXPECT_EQ(files(), std::vector<std::string>{"out.png"});
    std::ifstream in(out);
    std::string content;
    in >> content;
    EXPECT_EQ(content, "OLD");
}

TEST_F(PngWrite, CancellingDuringTheWriteStopsAtOnceAndRemovesTheTemporary) {
    const Image image = noisy(4000);
    const std::string out = (dir_ / "out.png").string();
    std::atomic<bool> cancel{false};
    std::string seen;
    std::chrono::steady_clock::time_point cancelled_at;
    std::thread canceller([&] {
        const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(20);
        while ((seen = temporary()).empty() && std::chrono::steady_clock::now() < give_up)
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
        std::this_thread::sleep_for(std::chrono::milliseconds(50));  // well into the rows
        cancelled_at = std::chrono::steady_clock::now();
        cancel = true;
    });
    bool threw = false;
    try {
        caustica::write_png_atomic(out, image, caustica::PixelEncoding::clamped_linear, {}, &cancel);
    } catch (const caustica::ImageWriteCancelled& e) {
        threw = true;
        EXPECT_EQ(std::string(e.what()), "writing '" + out + "' was interrupted; nothing written");
    }
    const auto stopped_at = std::chrono::steady_clock::now();
    canceller.join();
    ASSERT_TRUE(threw) << "the write finished before the cancel (temporary seen: '" << seen << "')";
    EXPECT_LT(std::chrono::duration<double>(stopped_at - cancelled_at).count(), caustica::testing::time_bound(0.25));
    EXPECT_TRUE(files().empty());
    // Hidden, named after the output, this host and this process.
    EXPECT_EQ(seen.rfind(".out.png.caustica-tmp-", 0), 0u) << seen;
    EXPECT_NE(seen.find("-" + std::to_string(::getpid()) + "-"), std::string::npos) << seen;
}

TEST_F(PngWrite, ASignalHandlerRemovesTheTemporaryOfAWriteInProgress) {
    // In a child: a handler like caustica's second Ctrl-C (remove the temporaries, _exit).
    const std::string out = (dir_ / "out.png").string();
    const pid_t pid = ::fork();
    if (pid == 0) {
        std::signal(SIGINT, [](int) {
            caustica::remove_output_temporaries_from_signal_handler();
            ::_exit(130);
        });
        caustica::write_png_atomic(out, noisy(4000), caustica::PixelEncoding::clamped_linear);
        ::_exit(0);
    }
    const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    while (temporary().empty() && std::chrono::steady_clock::now() < give_up)
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    ::kill(pid, SIGINT);
    int status = 0;
    ::waitpid(pid, &status, 0);
    ASSERT_TRUE(WIFEXITED(status));
    ASSERT_EQ(WEXITSTATUS(status), 130) << "the write finished before the signal";
    EXPECT_TRUE(files().empty());
}

TEST_F(PngWrite, TheNextWriteRemovesTemporariesOfKilledRunsAndNothingElse) {
    // A real stale temporary: a child killed while writing.
    const std::string out = (dir_ / "out.png").string();
    const pid_t pid = ::fork();
    if (pid == 0) {
        caustica::write_png_atomic(out, noisy(4000), caustica::PixelEncoding::clamped_linear);
        ::_exit(0);
    }
    const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    std::string stale;
    while ((stale = temporary()).empty() && std::chrono::steady_clock::now() < give_up)
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    ::kill(pid, SIGKILL);
    ::waitpid(pid, nullptr, 0);
    ASSERT_FALSE(stale.empty());
    ASSERT_EQ(files(), std::vector<std::string>{stale});

    // Look-alikes that must stay: a live process's (ours), another host's, other names, a link.
    const std::string dead = "-" + std::to_string(pid) + "-";
    const std::size_t at = stale.rfind(dead);
    ASSERT_NE(at, std::string::npos) << stale;
    const std::string live = stale.substr(0, at) + "-" + std::to_string(::getpid()) + "-" + stale.substr(at + dead.size());
    const std::string other_host = ".out.png.caustica-tmp-elsewhere" + dead + "0";
    const std::vector<std::string> kept = {live, other_host, "out.png.tmp-" + std::to_string(pid) + "-1",
                                           ".out.png.caustica-tmp-" + std::to_string(pid), "notes.txt"};
    for (const std::string& name : kept) std::ofstream(dir_ / name) << "x";
    const std::string link = stale.substr(0, at) + dead + "99";
    fs::create_symlink(dir_ / "notes.txt", dir_ / link);

    caustica::write_png_atomic(out, noisy(8), caustica::PixelEncoding::clamped_linear);
    std::vector<std::string> expected = kept;
    expected.push_back(link);
    expected.push_back("out.png");
    std::sort(expected.begin(), expected.end());
    EXPECT_EQ(files(), expected);
    EXPECT_EQ(caustica::read_png(out).width, 8);
}

TEST_F(PngWrite, AVeryLongNameStillGetsATemporaryAndAFailedWriteLeavesNothing) {
    const std::string long_name = std::string(250, 'n') + ".png";
    const std::string out = (dir_ / long_name).string();
    caustica::write_png_atomic(out, noisy(8), caustica::PixelEncoding::clamped_linear);
    EXPECT_EQ(files(), std::vector<std::string>{long_name});

    fs::create_directory(dir_ / "taken.png");  // the output is a folder: rename fails
    try {
        caustica::write_png_atomic((dir_ / "taken.png").string(), noisy(8), caustica::PixelEncoding::clamped_linear);
        ADD_FAILURE() << "wrote over a folder";
    } catch (const std::runtime_error& e) {
        EXPECT_EQ(std::string(e.what()).rfind("cannot write '" + (dir_ / "taken.png").string() + "': ", 0), 0u) << e.what();
    }
    EXPECT_EQ(files(), (std::vector<std::string>{long_name, "taken.png"}));
}

TEST(PngEncoding, LinearTruncatesSrgbRounds) {
    // "PNG bytes" (docs/SCENE_LANGUAGE.md): linear output is clamp to [0, 1], x255, truncated (no
    // rounding); only --srgb (ours) rounds to the nearest value.
    using caustica::PixelEncoding;
    for (int k = 0; k <= 255; ++k) {
        EXPECT_EQ(caustica::encode_channel(k / 255.0f, PixelEncoding::clamped_linear), k) << k;
        if (k < 255) {
            EXPECT_EQ(caustica::encode_channel((k + 0.99f) / 255.0f, PixelEncoding::clamped_linear), k) << k;
        }
    }
    EXPECT_EQ(caustica::encode_channel(0.5f / 255.0f, PixelEncoding::clamped_linear), 0);     // lround: 1
    EXPECT_EQ(caustica::encode_channel(254.99f / 255.0f, PixelEncoding::clamped_linear), 254);  // lround: 255
    EXPECT_EQ(caustica::encode_channel(0.999f, PixelEncoding::clamped_linear), 254);
    EXPECT_EQ(caustica::encode_channel(0.5f, PixelEncoding::clamped_linear), 127);  // 127.5
    EXPECT_EQ(caustica::encode_channel(1.0f, PixelEncoding::clamped_linear), 255);
    EXPECT_EQ(caustica::encode_channel(-1.0f, PixelEncoding::clamped_linear), 0);
    EXPECT_EQ(caustica::encode_channel(2.0f, PixelEncoding::clamped_linear), 255);
    EXPECT_EQ(caustica::encode_channel(std::nanf(""), PixelEncoding::clamped_linear), 0);
    // --srgb rounds: 0.5 -> 1.055 * 0.5^(1/2.4) - 0.055 = 0.73536, x255 = 187.52 -> 188 (truncated: 187).
    EXPECT_EQ(caustica::encode_channel(0.5f, PixelEncoding::srgb), 188);
    // On the linear segment (12.92 v): 0.6 of a step rounds up to 1, 0.4 down to 0.
    EXPECT_EQ(caustica::encode_channel(0.6f / (12.92f * 255.0f), PixelEncoding::srgb), 1);
    EXPECT_EQ(caustica::encode_channel(0.4f / (12.92f * 255.0f), PixelEncoding::srgb), 0);
    EXPECT_EQ(caustica::encode_channel(0.0f, PixelEncoding::srgb), 0);
    EXPECT_EQ(caustica::encode_channel(1.0f, PixelEncoding::srgb), 255);
    EXPECT_EQ(caustica::encode_channel(2.0f, PixelEncoding::srgb), 255);
}
