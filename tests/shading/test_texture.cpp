// Textures and bump maps: image decoding (every PNG colour type and depth), caching, errors,
// the cube's cross and the sphere's map through a TextureSet, and end-to-end renders. The rules
// themselves (docs/TEXTURES.md) are tested one by one in test_scene_language.cpp.
#include "core/scene/camera.h"
#include "core/lua/scene_loader.h"
#include "core/io/png_io.h"
#include "core/geometry/shapes.h"
#include "core/scene/source_location.h"
#include "core/shading/texture.h"
#include "core/shading/texture_image.h"
#include "core/shading/texture_procedural.h"
#include "tests/scene_test_helpers.h"
#include "tests/test_support.h"

#include <gtest/gtest.h>
#include <png.h>

#include <cmath>
#include <csetjmp>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <unistd.h>

using namespace caustica;
using caustica::testing::JobBuilder;
namespace fs = std::filesystem;

namespace {

constexpr float pi = 3.14159265358979323846f;
const glm::vec3 kd_marker(0.123f, 0.456f, 0.789f);

/// A fresh temporary folder per test, removed afterwards.
class TextureFiles : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() / ("caustica_texture_" + std::to_string(::getpid()) + "_" +
                                            ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }

    /// Writes a w x h RGB PNG whose texel (x, y) is `texel(x, y)` (values k / 255 survive exactly).
    std::string png(const std::string& name, int w, int h, const std::function<glm::vec3(int, int)>& texel) {
        Image image(w, h);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) image.at(x, y) = texel(x, y);
        const std::string path = (dir_ / name).string();
        write_png_atomic(path, image, PixelEncoding::clamped_linear);
        return path;
    }

    fs::path dir_;
};

glm::vec3 bytes(int r, int g, int b) { return glm::vec3(r, g, b) / 255.0f; }

/// What write_raw_png puts in the file besides the samples.
struct RawPngExtras {
    std::vector<png_color> palette;
    std::vector<png_byte> transparency;  ///< tRNS alphas of the palette entries
};

/// Writes a PNG with libpng itself, in the given bit depth and colour type: `samples` are the
/// file's rows, top first, already packed as PNG stores them (16-bit samples big-endian).
void write_raw_png(const std::string& path, int w, int h, int bit_depth, int colour_type,
                   const std::vector<unsigned char>& samples, const RawPngExtras& extras = {}) {
    FILE* file = std::fopen(path.c_str(), "wb");
    ASSERT_NE(file, nullptr);
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    png_infop info = png_create_info_struct(png);
    const std::size_t stride = samples.size() / static_cast<std::size_t>(h);
    std::vector<png_bytep> rows;
    for (int y = 0; y < h; ++y) rows.push_back(const_cast<png_bytep>(samples.data() + y * stride));
    if (setjmp(png_jmpbuf(png)) == 0) {
        png_init_io(png, file);
        png_set_IHDR(png, info, w, h, bit_depth, colour_type, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
                     PNG_FILTER_TYPE_DEFAULT);
        if (!extras.palette.empty())
            png_set_PLTE(png, info, extras.palette.data(), static_cast<int>(extras.palette.size()));
        if (!extras.transparency.empty())
            png_set_tRNS(png, info, extras.transparency.data(), static_cast<int>(extras.transparency.size()), nullptr);
        png_write_info(png, info);
        png_write_image(png, rows.data());
        png_write_end(png, info);
    } else {
        ADD_FAILURE() << "libpng could not write " << path;
    }
    png_destroy_write_struct(&png, &info);
    std::fclose(file);
}

/// The 8-bit value a 16-bit sample should decode to: the nearest, v * 255 / 65535 rounded.
float from_16_bits(int v) { return static_cast<float>(std::lround(v * 255.0 / 65535.0)) / 255.0f; }

/// A scene with one material whose texture and/or bump map are the given sources.
SceneDesc textured_scene(const std::string& texture, const std::string& bumpmap = "", const std::string& remap = "") {
    SceneDesc scene;
    MaterialDesc material;
    material.kd = glm::dvec3(kd_marker);
    auto add = [&](const std::string& source) {
        TextureDesc t;
        t.source = source;
        t.procedural = !source.starts_with("/");
        t.remap = remap;
        t.where = {"scene.lua", 5};
        scene.textures.push_back(t);
        return static_cast<int>(scene.textures.size()) - 1;
    };
    if (!texture.empty()) material.texture = add(texture);
    if (!bumpmap.empty()) material.bumpmap = add(bumpmap);
    scene.materials.push_back(material);
    return scene;
}

using caustica::testing::shape_hit;

const Shape unit_box{ShapeKind::box, glm::vec3(-1.0f), glm::vec3(1.0f)};

/// A hit on the centred cube's face (0..5 = -x,+x,-y,+y,-z,+z) at point p.
SurfaceHit box_hit(int face, const glm::vec3& p) {
    glm::vec3 n(0.0f);
    n[face / 2] = face % 2 ? 1.0f : -1.0f;
    return shape_hit(unit_box, p, face, n);
}

void expect_vec_near(const glm::vec3& got, const glm::vec3& want, float tolerance) {
    EXPECT_NEAR(got.x, want.x, tolerance);
    EXPECT_NEAR(got.y, want.y, tolerance);
    EXPECT_NEAR(got.z, want.z, tolerance);
}

/// A 4 x 3 image, one texel per cell of the cube's cross: red = 20 column, green = 80 row
/// (row 0 at the top of the image).
glm::vec3 cell_texel(int x, int y) { return bytes(20 * x, 80 * y, 128); }

}  // namespace

// --- Image decoding -------------------------------------------------------------------------

using TextureDecoding = TextureFiles;

TEST_F(TextureDecoding, EightBitRgbValuesAreLinearWithoutGamma) {
    const std::string path = png("rgb.png", 1, 1, [](int, int) { return bytes(128, 64, 32); });
    expect_vec_near(load_texture_image(path)->colour({0.5f, 0.5f}), glm::vec3(128, 64, 32) / 255.0f, 0.0f);
}

TEST_F(TextureDecoding, GreyAndGreyAlphaGiveEqualChannelsAndIgnoreAlpha) {
    const std::string grey = (dir_ / "grey.png").string(), grey_alpha = (dir_ / "ga.png").string();
    write_raw_png(grey, 3, 1, 8, PNG_COLOR_TYPE_GRAY, {0, 77, 255});
    write_raw_png(grey_alpha, 2, 1, 8, PNG_COLOR_TYPE_GRAY_ALPHA, {50, 255, 180, 0});
    const auto g = load_texture_image(grey), ga = load_texture_image(grey_alpha);
    EXPECT_EQ(g->texel(0, 0), glm::vec3(0.0f));
    EXPECT_EQ(g->texel(1, 0), glm::vec3(77.0f / 255.0f));
    EXPECT_EQ(g->texel(2, 0), glm::vec3(1.0f));
    EXPECT_EQ(ga->texel(0, 0), glm::vec3(50.0f / 255.0f));
    EXPECT_EQ(ga->texel(1, 0), glm::vec3(180.0f / 255.0f));  // fully transparent: still its grey
    // Low-bit grey is scaled to the full range: 1-bit 1 is white, 4-bit 5 is 5 * 17.
    const std::string one_bit = (dir_ / "g1.png").string(), four_bit = (dir_ / "g4.png").string();
    write_raw_png(one_bit, 2, 1, 1, PNG_COLOR_TYPE_GRAY, {0x40});  // pixels 0, 1
    write_raw_png(four_bit, 2, 1, 4, PNG_COLOR_TYPE_GRAY, {0x5F});  // pixels 5, 15
    EXPECT_EQ(load_texture_image(one_bit)->texel(0, 0), glm::vec3(0.0f));
    EXPECT_EQ(load_texture_image(one_bit)->texel(1, 0), glm::vec3(1.0f));
    EXPECT_EQ(load_texture_image(four_bit)->texel(0, 0), glm::vec3(85.0f / 255.0f));
    EXPECT_EQ(load_texture_image(four_bit)->texel(1, 0), glm::vec3(1.0f));
}

TEST_F(TextureDecoding, PaletteImagesGiveThePaletteColours) {
    const RawPngExtras palette{{{10, 20, 30}, {200, 100, 50}, {255, 255, 0}}, {}};
    const std::string eight = (dir_ / "p8.png").string(), two = (dir_ / "p2.png").string();
    const std::string transparent = (dir_ / "pt.png").string();
    write_raw_png(eight, 3, 1, 8, PNG_COLOR_TYPE_PALETTE, {1, 0, 2}, palette);
    write_raw_png(two, 3, 1, 2, PNG_COLOR_TYPE_PALETTE, {0x24}, palette);  // 2-bit indices 0, 2, 1
    write_raw_png(transparent, 2, 1, 8, PNG_COLOR_TYPE_PALETTE, {1, 2}, {palette.palette, {0, 128, 255}});
    const auto p8 = load_texture_image(eight), p2 = load_texture_image(two), pt = load_texture_image(transparent);
    EXPECT_EQ(p8->texel(0, 0), bytes(200, 100, 50));
    EXPECT_EQ(p8->texel(1, 0), bytes(10, 20, 30));
    EXPECT_EQ(p8->texel(2, 0), bytes(255, 255, 0));
    EXPECT_EQ(p2->texel(0, 0), bytes(10, 20, 30));
    EXPECT_EQ(p2->texel(1, 0), bytes(255, 255, 0));
    EXPECT_EQ(p2->texel(2, 0), bytes(200, 100, 50));
    EXPECT_EQ(pt->texel(0, 0), bytes(200, 100, 50));  // tRNS adds alpha: the colours stay
    EXPECT_EQ(pt->texel(1, 0), bytes(255, 255, 0));
}

TEST_F(TextureDecoding, SixteenBitSamplesBecomeTheNearestEightBitValue) {
    // 0x00C0 = 192 is 0.75 / 255: the nearest 8-bit value is 1 (dropping the low byte gives 0).
    const int values[] = {0xFFFF, 0x8080, 0x00C0, 0x01F0, 0x7FFF, 0x0000};
    std::vector<unsigned char> rgb, grey, grey_alpha;
    for (int v : values) {
        const unsigned char hi = static_cast<unsigned char>(v >> 8), lo = static_cast<unsigned char>(v & 0xFF);
        grey.insert(grey.end(), {hi, lo});
        grey_alpha.insert(grey_alpha.end(), {hi, lo, 0xFF, 0xFF});
        rgb.insert(rgb.end(), {hi, lo, 0x00, 0xC0, 0xFF, 0xFF});  // (v, 192, 65535)
    }
    const int n = static_cast<int>(std::size(values));
    const std::string rgb_path = (dir_ / "rgb16.png").string(), grey_path = (dir_ / "g16.png").string();
    const std::string ga_path = (dir_ / "ga16.png").string();
    write_raw_png(rgb_path, n, 1, 16, PNG_COLOR_TYPE_RGB, rgb);
    write_raw_png(grey_path, n, 1, 16, PNG_COLOR_TYPE_GRAY, grey);
    write_raw_png(ga_path, n, 1, 16, PNG_COLOR_TYPE_GRAY_ALPHA, grey_alpha);
    const auto rgb_image = load_texture_image(rgb_path), grey_image = load_texture_image(grey_path);
    const auto ga_image = load_texture_image(ga_path);
    for (int i = 0; i < n; ++i) {
        SCOPED_TRACE(values[i]);
        EXPECT_EQ(rgb_image->texel(i, 0), glm::vec3(from_16_bits(values[i]), 1.0f / 255.0f, 1.0f));
        EXPECT_EQ(grey_image->texel(i, 0), glm::vec3(from_16_bits(values[i])));
        EXPECT_EQ(ga_image->texel(i, 0), glm::vec3(from_16_bits(values[i])));
    }
}

// --- Cache, errors, procedurals ---------------------------------------------------------------

using TextureCache = TextureFiles;

TEST_F(TextureCache, SamePathGivesTheSameImageUntilTheFileChanges) {
    const std::string path = png("a.png", 2, 2, [](int, int) { return bytes(255, 0, 0); });
    const auto first = load_texture_image(path);
    EXPECT_EQ(load_texture_image(path).get(), first.get());
    // A second scene (another render) shares the cached image too.
    const TextureSet one(textured_scene(path)), two(textured_scene(path));
    EXPECT_EQ(load_texture_image(path).get(), first.get());
    // Rewriting the file (different size on disk) makes the next load read the new pixels.
    png("a.png", 4, 4, [](int, int) { return bytes(0, 255, 0); });
    const auto second = load_texture_image(path);
    EXPECT_NE(second.get(), first.get());
    EXPECT_EQ(second->width(), 4);
    EXPECT_NEAR(second->colour({0.5f, 0.5f}).g, 1.0f, 1e-6f);
}

using TextureErrors = TextureFiles;

TEST_F(TextureErrors, UnreadablePngNamesTheScriptLineAndThePath) {
    const std::string path = (dir_ / "missing.png").string();
    try {
        TextureSet set(textured_scene(path));
        FAIL() << "expected InputError";
    } catch (const InputError& e) {
        const std::string message = e.what();
        EXPECT_EQ(message.rfind("scene.lua:5: gr.texture: cannot read '" + path + "': ", 0), 0u) << message;
        EXPECT_EQ(message.find(path), message.rfind(path)) << "path repeated: " << message;
    }
    std::ofstream(dir_ / "fake.png") << "not a png";
    try {
        TextureSet set(textured_scene("", (dir_ / "fake.png").string()));
        FAIL() << "expected InputError";
    } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()),
                  "scene.lua:5: gr.bumpmap: cannot read '" + (dir_ / "fake.png").string() + "': not a PNG file");
    }
}

TEST(TextureSetBasics, UntexturedMaterialsKeepKdAndNormal) {
    SceneDesc scene;
    scene.materials.push_back(MaterialDesc{});
    const TextureSet set(scene);
    EXPECT_TRUE(set.empty());
    const SurfaceHit hit = box_hit(5, {0, 0, 1});
    EXPECT_EQ(set.diffuse(0, hit, kd_marker), kd_marker);
    EXPECT_EQ(set.diffuse(7, hit, kd_marker), kd_marker);  // the renderer's default material
    EXPECT_EQ(set.shading_normal(0, hit, {0, 0, 1}), glm::vec3(0, 0, 1));
    EXPECT_FALSE(TextureSet(textured_scene("redcheck")).empty());
}

// --- Procedural textures ----------------------------------------------------------------------

TEST(TextureProcedural, CheckerColoursAndPhase) {
    // 24 squares per unit (docs/TEXTURES.md, "Procedural textures"): n = floor(24u) + floor(24v),
    // the colour where n is odd. test_scene_language.cpp counts the squares.
    const glm::vec3 black(0.0f);
    EXPECT_EQ(checker(*checker_colour("greencheck"), {0.3f, 0.3f}), black);       // (7, 7)
    EXPECT_EQ(checker(*checker_colour("greencheck"), {0.3f, 0.34f}), glm::vec3(0, 1, 0));  // (7, 8)
    EXPECT_EQ(checker(*checker_colour("bluecheck"), {0.3f, 0.34f}), glm::vec3(0, 0.8f, 1));
    EXPECT_EQ(checker(*checker_colour("whitecheck"), {0.3f, 0.34f}), glm::vec3(1, 1, 1));
    EXPECT_EQ(checker(*checker_colour("whitecheck"), {0.3f, 0.2f}), glm::vec3(1, 1, 1));  // (7, 4)
    EXPECT_FALSE(checker_colour("purplecheck"));
}

TEST(TextureProcedural, UnknownProceduralNameIsAnInputError) {
    SceneDesc scene = textured_scene("purplecheck");
    EXPECT_THROW(TextureSet{scene}, InputError);
    scene = textured_scene("", "redcheck");  // a checkerboard is not a bump map
    EXPECT_THROW(TextureSet{scene}, InputError);
}


// --- Layouts through a TextureSet -----------------------------------------------------------

using TextureLayouts = TextureFiles;

TEST_F(TextureLayouts, EachCubeFaceShowsItsCellOfTheCross) {
    const TextureSet set(textured_scene(png("cells.png", 4, 3, cell_texel)));
    struct FaceCase {
        int face, column, row;  // the cell's column from the left, row from the top of the image
        glm::vec3 centre;
    };
    const FaceCase cases[] = {{0, 0, 1, {-1, 0, 0}}, {3, 1, 1, {0, 1, 0}}, {1, 2, 1, {1, 0, 0}},
                              {2, 3, 1, {0, -1, 0}}, {5, 1, 2, {0, 0, 1}}, {4, 1, 0, {0, 0, -1}}};
    for (const FaceCase& c : cases) {
        SCOPED_TRACE(c.face);
        EXPECT_EQ(set.diffuse(0, box_hit(c.face, c.centre), kd_marker), cell_texel(c.column, c.row));
    }
    // An nh_box (corner (2, 0, 0), side 3) uses the same cross.
    const Shape box{ShapeKind::box, glm::vec3(2, 0, 0), glm::vec3(5, 3, 3)};
    EXPECT_EQ(set.diffuse(0, shape_hit(box, {3.5f, 1.5f, 3}, 5, {0, 0, 1}), kd_marker), cell_texel(1, 2));
}

TEST_F(TextureLayouts, SphereMapsLongitudeFromTheSeamAtMinusXAndHeightUp) {
    // 4 x 2 texels: column c covers u in [c/4, (c+1)/4], row 0 (top) v in [1/2, 1].
    const TextureSet set(textured_scene(png("map.png", 4, 2, [](int x, int y) { return bytes(60 * x, 200 * y, 0); })));
    const Shape sphere{ShapeKind::sphere, glm::vec3(0.0f), glm::vec3(1.0f)};
    auto at = [&](glm::vec3 p) { p = glm::normalize(p); return set.diffuse(0, shape_hit(sphere, p, 0, p), kd_marker); };
    EXPECT_EQ(at({-1, 0.5f, 0.2f}), bytes(0, 0, 0));      // just after the seam (-x), towards +z, north
    EXPECT_EQ(at({0.3f, 0.5f, 1}), bytes(60, 0, 0));      // facing +z (u = 1/4), slightly right: column 1
    EXPECT_EQ(at({-0.3f, -0.5f, 1}), bytes(0, 200, 0));   // facing +z, slightly left, south: column 0, row 1
    EXPECT_EQ(at({1, 0.5f, -0.1f}), bytes(120, 0, 0));    // just past +x (u = 1/2)
    EXPECT_EQ(at({-1, 0.5f, -0.2f}), bytes(180, 0, 0));   // just before the seam
}

// --- End to end -------------------------------------------------------------------------------

using TextureRender = TextureFiles;

TEST_F(TextureRender, SphereShowsTheTextureWhereItProjects) {
    // 16 x 8 texels in 4 x 2 blocks of 4 x 4, each block its own colour.
    const glm::vec3 block_colours[2][4] = {{bytes(255, 0, 0), bytes(0, 255, 0), bytes(0, 0, 255), bytes(255, 255, 0)},
                                           {bytes(0, 255, 255), bytes(255, 0, 255), bytes(255, 255, 255), bytes(51, 102, 153)}};
    const std::string path = png("blocks.png", 16, 8, [&](int x, int y) { return block_colours[y / 4][x / 4]; });
    JobBuilder b(129, 129);
    const int material = b.material({0.5, 0.5, 0.5});
    b.add(NodeKind::sphere, material);
    TextureDesc texture;
    texture.source = path;
    b.scene->textures.push_back(texture);
    b.scene->materials[material].texture = 0;
    b.camera({0, 0, 5}, {0, 0, -1}, 30);
    b.job.ambient = {1, 1, 1};  // no lights: each pixel is ambient * kd = the texture colour
    b.job.options.disable_aa = true;
    const RenderJob job = b.build();
    const Image image = caustica::testing::render(job);
    const Camera camera(job.camera, job.width, job.height);
    // u = 1/2 + atan2(-z, x) / 2 pi, v = (1 + y) / 2: the half facing +z has u in (0, 1/2), so
    // block columns 0 and 1; image row 0 (the top) is the northern half.
    for (int row = 0; row < 2; ++row) {
        for (int column = 0; column <= 1; ++column) {
            const float u = (column + 0.5f) / 4.0f, v = 1.0f - (row + 0.5f) / 2.0f;
            const float phi = 2.0f * pi * (u - 0.5f), y = 2.0f * v - 1.0f, r = std::sqrt(1.0f - y * y);
            const glm::vec3 p(r * std::cos(phi), y, -r * std::sin(phi));
            glm::vec2 pixel;
            ASSERT_TRUE(camera.project(p, pixel));
            const glm::vec3 c = image.at(static_cast<int>(pixel.x), static_cast<int>(pixel.y));
            SCOPED_TRACE(::testing::Message() << "block " << column << "," << row);
            expect_vec_near(c, block_colours[row][column], 1e-4f);
        }
    }
}

TEST_F(TextureRender, BumpMapChangesLambertShadingAsPredicted) {
    // A cube's front face with a ramp bump (cubefront), lit by a distant-ish light straight ahead:
    // the Lambert factor becomes the cosine of the tilt, n' = normalise(n + 5 g_x U), g_x = 16/255.
    const std::string ramp = png("ramp.png", 16, 16, [](int x, int) { return bytes(16 * x, 16 * x, 16 * x); });
    JobBuilder b(65, 65);
    const int material = b.material({1, 1, 1});
    b.add(NodeKind::cube, material);
    TextureDesc bump;
    bump.source = ramp;
    bump.remap = "cubefront";
    b.scene->textures.push_back(bump);
    b.scene->materials[material].bumpmap = 0;
    b.camera({0, 0, 5}, {0, 0, -1}, 20);
    b.light({0, 0, 1000}, {1, 1, 1});
    b.job.options.disable_aa = true;
    const Image image = caustica::testing::render(b.build());
    const float slope = 5.0f * 16.0f / 255.0f;
    const float expected = 1.0f / std::sqrt(1.0f + slope * slope);
    EXPECT_NEAR(image.at(32, 32).r, expected, 2e-4f);
    EXPECT_LT(image.at(32, 32).r, 1.0f - 1e-4f);
}
TEST(TextureScene, DemoSceneShowsTheDiesYellowTop) {
    const SceneScript script = load_scene_script(CAUSTICA_SOURCE_DIR "/scenes/textures.lua");
    ASSERT_EQ(script.renders.size(), 1u);
    RenderJob job = script.renders[0];
    job.width = 320;
    job.height = 200;
    job.options.disable_aa = true;
    job.options.silent = true;
    const Image image = caustica::testing::render(job);
    // The die (translate(-3.3, 0, 1.6) rotate('y', 35)) wears the cube's own uv, the 4 x 3 cross
    // (docs/TEXTURES.md): its top face at local (-0.5, 1, 0) has s = (0.25, 1, 0.5), so
    // u = (1 + s_x)/4 = 0.3125 and v = (2 - s_z)/3 = 0.5: the +y cell (column 1 of the middle row)
    // at (0.25, 0.5) within the cell, in its yellow between the pip and the border.
    const float c = std::cos(glm::radians(35.0f)), s = std::sin(glm::radians(35.0f));
    const glm::vec3 p(-3.3f - 0.5f * c, 1.0f, 1.6f + 0.5f * s);
    glm::vec2 pixel;
    ASSERT_TRUE(Camera(job.camera, job.width, job.height).project(p, pixel));
    const glm::vec3 top = image.at(static_cast<int>(pixel.x), static_cast<int>(pixel.y));
    // Yellow (0.95, 0.85, 0.30) under white light: red and green well above blue.
    EXPECT_GT(top.r, 2.0f * top.b) << top.r << " " << top.g << " " << top.b;
    EXPECT_GT(top.g, 2.0f * top.b) << top.r << " " << top.g << " " << top.b;
}
