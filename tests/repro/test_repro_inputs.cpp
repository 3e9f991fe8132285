// The reproducers of the hardening audit (tests/repro/README.md), part 3: OBJ faces (B1) and
// hostile PNG files (B2), made at run time. Each test runs `caustica render` in a child under hard
// limits (tests/repro/repro_runner.h) and asserts the outcome: the image, or exit 2 with
// "file:line: call:" naming the file, within bounded time and resident size.
#include "tests/repro/repro_runner.h"

#include "core/io/png_io.h"

#include <gtest/gtest.h>

#include <zlib.h>

#include <cmath>
#include <cstdint>
#include <cstdio>

using namespace caustica::repro;

namespace {

// ---- crafted PNG files (the generator of ../shared/repro/png/make_pngs.py, in C++) ----

/// Appends `v` big-endian, as PNG stores its numbers.
void put_u32(std::string& out, std::uint32_t v) {
    for (int shift = 24; shift >= 0; shift -= 8) out += static_cast<char>((v >> shift) & 0xff);
}

/// A chunk: length, type, body, CRC of type and body.
std::string png_chunk(const std::string& type, const std::string& body) {
    std::string out;
    put_u32(out, static_cast<std::uint32_t>(body.size()));
    const std::string typed = type + body;
    out += typed;
    put_u32(out, static_cast<std::uint32_t>(
                     crc32(0, reinterpret_cast<const Bytef*>(typed.data()), static_cast<uInt>(typed.size()))));
    return out;
}

/// The IHDR chunk of a w x h image (no interlacing).
std::string ihdr(std::uint32_t w, std::uint32_t h, int bit_depth, int colour_type) {
    std::string body;
    put_u32(body, w);
    put_u32(body, h);
    body += static_cast<char>(bit_depth);
    body += static_cast<char>(colour_type);
    body += std::string(3, '\0');  // compression, filter, interlace
    return png_chunk("IHDR", body);
}

/// The 8 bytes every PNG starts with.
const std::string png_signature("\x89PNG\r\n\x1a\n", 8);

/// zlib stream of `rows` rows of `row_bytes` zero bytes each, each after a zero filter byte.
std::string deflate_zero_rows(std::size_t rows, std::size_t row_bytes) {
    z_stream z{};
    deflateInit2(&z, 1, Z_DEFLATED, 15, 9, Z_RLE);
    const std::string row(row_bytes + 1, '\0');
    std::string out;
    char buffer[1 << 16];
    for (std::size_t r = 0; r <= rows; ++r) {
        const bool last = r == rows;
        z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(row.data()));
        z.avail_in = last ? 0 : static_cast<uInt>(row.size());
        do {
            z.next_out = reinterpret_cast<Bytef*>(buffer);
            z.avail_out = sizeof buffer;
            deflate(&z, last ? Z_FINISH : Z_NO_FLUSH);
            out.append(buffer, sizeof buffer - z.avail_out);
        } while (z.avail_out == 0);
    }
    deflateEnd(&z);
    return out;
}

/// `text` as one zlib stream (level 9).
std::string compress_text(const std::string& text) {
    uLongf size = compressBound(text.size());
    std::string out(size, '\0');
    compress2(reinterpret_cast<Bytef*>(out.data()), &size, reinterpret_cast<const Bytef*>(text.data()), text.size(), 9);
    out.resize(size);
    return out;
}

/// A PNG of w x h of colour type `ct` (8 bits) with the given IDAT data and extra chunks before it.
std::string make_png(std::uint32_t w, std::uint32_t h, int ct, const std::string& idat, const std::string& extra = "") {
    return png_signature + ihdr(w, h, 8, ct) + extra + png_chunk("IDAT", idat) + png_chunk("IEND", "");
}

/// An 8 x 8 RGB image of zeros.
std::string small_idat() { return deflate_zero_rows(8, 8 * 3); }

// ---- OBJ files made at run time ----

/// A convex polygon of `n` corners on the unit circle, as one face or fanned into triangles.
std::string polygon_obj(int n, bool fanned) {
    std::string text;
    char line[128];
    for (int i = 0; i < n; ++i) {
        const double a = 2.0 * M_PI * i / n;
        std::snprintf(line, sizeof line, "v %.17g %.17g 0\n", std::cos(a), std::sin(a));
        text += line;
    }
    if (fanned) {
        for (int i = 2; i < n; ++i) {
            std::snprintf(line, sizeof line, "f 1 %d %d\n", i, i + 1);
            text += line;
        }
    } else {
        text += "f";
        for (int i = 1; i <= n; ++i) {
            text += ' ';
            text += std::to_string(i);
        }
        text += "\n";
    }
    return text;
}

}  // namespace

// ---- B1: OBJ polygons of any size fan correctly; out-of-range indices name the OBJ line ----

TEST(ReproObj, B1_PolygonOf300CornersFansLikeTheFannedFile) {
    Scratch s;
    s.copy("obj/mesh.lua", "mesh.lua");
    s.write("polygon300.obj", polygon_obj(300, false));
    s.write("polygon300_fanned.obj", polygon_obj(300, true));
    caustica::Png8 images[2];
    const char* names[2] = {"polygon300.obj", "polygon300_fanned.obj"};
    for (int i = 0; i < 2; ++i) {
        const std::string out = std::string(names[i]) + ".png";
        const Outcome o = caustica_run(s.root(), {"render", "-s", "-S", "--reproducible", "mesh.lua", "-o", out}, 20.0,
                                       1 * gib, {{"OBJ", names[i]}});
        ASSERT_EQ(o.exit_code, 0) << names[i] << "\n" << o.describe();
        EXPECT_NE(o.err.find("298 triangles stored"), std::string::npos) << names[i] << "\n" << o.describe();
        images[i] = caustica::read_png((s.root() / out).string());
    }
    EXPECT_TRUE(images[0].data == images[1].data) << "the 300-gon renders differently from its fan";
}

namespace {

void expect_bad_index_located(const std::string& index) {
    Scratch s;
    s.copy("obj/mesh.lua", "mesh.lua");
    s.write("huge_index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 " + index + "\n");
    const Outcome o = caustica_run(s.root(), {"render", "-s", "mesh.lua"}, 10.0, 1 * gib, {{"OBJ", "huge_index.obj"}});
    expect_scene_error(o, "mesh.lua", 1);
    EXPECT_NE(o.err.find("gr.mesh"), std::string::npos) << o.describe();
    EXPECT_TRUE(o.err.find("line 4") != std::string::npos || o.err.find("huge_index.obj:4") != std::string::npos)
        << "the OBJ line is not named\n" << o.describe();
    EXPECT_LE(o.seconds, 2.0 * time_factor()) << o.describe();
    EXPECT_FALSE(fs::exists(s.root() / "x.png"));
}

}  // namespace

TEST(ReproObj, B1_HugeFaceIndexNamesTheObjLine) { expect_bad_index_located("99999999999999999999"); }

TEST(ReproObj, B1_HugeNegativeFaceIndexNamesTheObjLine) { expect_bad_index_located("-99999999999999999999"); }

TEST(ReproObj, B1_IndexPastTheLastVertexNamesTheObjLine) { expect_bad_index_located("4"); }

// ---- B2: hostile PNGs are refused (or read) within bounded memory ----

namespace {

/// How png/tex.lua must end with a given PNG.
enum class Read { refused, image };

/// png/tex.lua with PNG=`name` (a texture, or a bump map with `bumpmap`): a 64 x 64 image, or
/// refused at line 3 naming the file, within `resident` bytes and `seconds`.
Outcome expect_texture_handled(const Scratch& s, const std::string& name, Read read, std::size_t resident,
                               double seconds, bool bumpmap = false) {
    s.copy("png/tex.lua", "tex.lua");
    const Outcome o =
        caustica_run(s.root(), {"render", "-s", "tex.lua"}, 3.0 * seconds, 3 * gib,
                     {{"PNG", name}, {"KIND", bumpmap ? "bumpmap" : "texture"}}, roomy_address_space);
    expect_outcome(o, s.root() / "x.png", 64, 64, "tex.lua",
                   read == Read::image ? Expected::image() : Expected::error(3, bumpmap ? "gr.bumpmap" : "gr.texture"));
    if (read == Read::refused) {
        EXPECT_NE(o.err.find(name), std::string::npos) << o.describe();
    }
    EXPECT_LE(o.peak_rss, rss_bound(resident)) << o.describe();
    EXPECT_LE(o.seconds, seconds * time_factor()) << o.describe();
    return o;
}

/// A `side` x `side` RGBA PNG of zeros (16384: 1 MiB of file, 1 GiB of pixels).
std::string zero_rgba(std::uint32_t side) { return make_png(side, side, 6, deflate_zero_rows(side, side * 4)); }

}  // namespace

TEST(ReproPng, B2_ChunkClaiming2GiBIsRefusedWithoutAllocatingIt) {
    Scratch s;
    std::string file = png_signature + ihdr(8, 8, 8, 2);
    put_u32(file, 0x7ffffff0u);
    file += "tEXtabc";
    ASSERT_EQ(file.size(), 44u);
    s.write("huge_chunk_len.png", file);
    expect_texture_handled(s, "huge_chunk_len.png", Read::refused, 256 * mib, 2.0);
}

TEST(ReproPng, B2_ChunkClaiming2GiBIsRefusedAsABumpMap) {
    Scratch s;
    std::string file = png_signature + ihdr(8, 8, 8, 2);
    put_u32(file, 0x7ffffff0u);
    file += "tEXtabc";
    s.write("huge_chunk_len.png", file);
    expect_texture_handled(s, "huge_chunk_len.png", Read::refused, 256 * mib, 2.0, true);
}

TEST(ReproPng, B2_DeclaredSizesAreCheckedBeforeDecoding) {
    const std::pair<std::uint32_t, std::uint32_t> sizes[] = {{100000, 100000}, {0x7fffffffu, 1}, {65536, 4096}};
    for (const auto& [w, h] : sizes) {
        SCOPED_TRACE(std::to_string(w) + " x " + std::to_string(h));
        Scratch s;
        s.write("dims.png", make_png(w, h, 2, compress_text(std::string(1000, '\0'))));
        expect_texture_handled(s, "dims.png", Read::refused, 256 * mib, 2.0);
    }
}

TEST(ReproPng, B2_OverThePixelLimitIsRefusedBeforeDecoding) {
    Scratch s;
    s.write("over_limit_gray.png", make_png(16385, 16384, 0, deflate_zero_rows(16384, 16385)));
    expect_texture_handled(s, "over_limit_gray.png", Read::refused, 256 * mib, 3.0);
}

TEST(ReproPng, B2_CompressedTextBombIsNotInflated) {
    Scratch s;
    const std::string ztxt = std::string("k\0\0", 3) + compress_text(std::string(50'000'000, 'A'));
    s.write("ztxt_bomb.png", make_png(8, 8, 2, small_idat(), png_chunk("zTXt", ztxt)));
    expect_texture_handled(s, "ztxt_bomb.png", Read::image, 256 * mib, 3.0);
}

TEST(ReproPng, B2_ManyChunksAreBounded) {
    Scratch s;
    std::string chunks;
    const std::string one = png_chunk("tEXt", std::string("k\0v", 3));
    for (int i = 0; i < 100000; ++i) chunks += one;
    s.write("many_chunks.png", make_png(8, 8, 2, small_idat(), chunks));
    expect_texture_handled(s, "many_chunks.png", Read::image, 256 * mib, 3.0);
}

TEST(ReproPng, B2_DecompressionBombStaysWithinTheBudget) {
    Scratch s;
    s.write("bomb_16384_rgba.png", zero_rgba(16384));
    expect_texture_handled(s, "bomb_16384_rgba.png", Read::refused, 256 * mib, 2.0);
}

TEST(ReproPng, B2_DecompressionBombUnderThreeNamesStaysWithinTheBudget) {
    Scratch s;
    s.write("bomb_16384_rgba.png", zero_rgba(16384));
    fs::create_symlink("bomb_16384_rgba.png", s.root() / "b2.png");
    fs::create_symlink("bomb_16384_rgba.png", s.root() / "b3.png");
    s.copy("png/tex3.lua", "tex3.lua");
    const Outcome o = caustica_run(s.root(), {"render", "-s", "tex3.lua"}, 45.0, 3 * gib, {}, roomy_address_space);
    expect_outcome(o, s.root() / "x.png", 64, 64, "tex3.lua", Expected::error(5, "gr.texture"));
    EXPECT_LE(o.peak_rss, rss_bound(256 * mib)) << o.describe();
    EXPECT_LE(o.seconds, 2.0 * time_factor()) << o.describe();
}

TEST(ReproPng, B2_OneFileUnderThreeNamesIsDecodedOnce) {
    // A 4096 x 4096 RGBA texture (64 MiB as 8-bit pixels) is read; under three names it must cost
    // no more than under one.
    Scratch s;
    s.write("mid.png", zero_rgba(4096));
    fs::create_symlink("mid.png", s.root() / "m2.png");
    fs::create_symlink("mid.png", s.root() / "m3.png");
    const Outcome once = expect_texture_handled(s, "mid.png", Read::image, 1 * gib, 5.0);
    ASSERT_EQ(once.exit_code, 0) << once.describe();
    std::string scene = read_text(repro_source("png/tex3.lua"));
    for (const auto& [from, to] : {std::pair<std::string, std::string>{"bomb_16384_rgba.png", "mid.png"},
                                   {"'b2.png'", "'m2.png'"},
                                   {"'b3.png'", "'m3.png'"}}) {
        const std::size_t at = scene.find(from);
        ASSERT_NE(at, std::string::npos) << from;
        scene.replace(at, from.size(), to);
    }
    s.write("mid3.lua", scene);
    fs::remove(s.root() / "x.png");
    const Outcome o = caustica_run(s.root(), {"render", "-s", "mid3.lua"}, 15.0, 3 * gib, {}, roomy_address_space);
    ASSERT_EQ(o.exit_code, 0) << o.describe();
    EXPECT_LE(o.peak_rss, once.peak_rss + 64 * mib) << "decoded more than once (one name: " << once.peak_rss / mib
                                                     << " MiB)\n" << o.describe();
    EXPECT_LE(o.seconds, 5.0 * time_factor()) << o.describe();
}
