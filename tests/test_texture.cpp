// Textures and bump maps: filtering, caching, procedurals, the cube unwrap, remaps, Blinn bump
// mapping, and an end-to-end textured render. Expected values follow docs/TEXTURES.md.
#include "core/scene/camera.h"
#include "core/lua/scene_loader.h"
#include "core/io/png_io.h"
#include "core/geometry/shapes.h"
#include "core/scene/source_location.h"
#include "core/shading/texture.h"
#include "core/shading/texture_image.h"
#include "core/shading/texture_procedural.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <unistd.h>

using namespace caustica;
using caustica::testing::JobBuilder;
namespace fs = std::filesystem;

namespace {

constexpr float pi = 3.14159265358979323846f;
/// The documented height of a white bump-map texel, in texture units.
constexpr float bump_depth = 1.0f / 32.0f;
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

    /// Writes a w x h PNG whose texel (x, y) is `texel(x, y)` (values k / 255 survive exactly).
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

/// A hit on an analytic shape placed with object space = world space, as RenderScene fills it.
SurfaceHit shape_hit(const Shape& shape, const glm::vec3& p, int face, const glm::vec3& outward) {
    SurfaceHit hit;
    hit.position = hit.object_position = p;
    hit.normal = glm::normalize(outward);
    hit.face = face;
    hit.material = 0;
    hit.shape_kind = static_cast<int>(shape.kind);
    hit.uv = shape_uv(shape, p, face);
    shape_tangents(shape, p, face, hit.dpdu, hit.dpdv);
    return hit;
}

const Shape unit_box{ShapeKind::box, glm::vec3(-1.0f), glm::vec3(1.0f)};

/// A hit on the centred cube's face (0..5 = -x,+x,-y,+y,-z,+z) at point p.
SurfaceHit box_hit(int face, const glm::vec3& p) {
    glm::vec3 n(0.0f);
    n[face / 2] = face % 2 ? 1.0f : -1.0f;
    return shape_hit(unit_box, p, face, n);
}

/// A hit on the unit cylinder's side (face 0) or caps (1 top, 2 bottom).
SurfaceHit cylinder_hit(int face, const glm::vec3& p) {
    const glm::vec3 n = face == 0 ? glm::vec3(p.x, 0.0f, p.z) : glm::vec3(0.0f, face == 1 ? 1.0f : -1.0f, 0.0f);
    return shape_hit(Shape{ShapeKind::cylinder}, p, face, n);
}

/// A hit on the cone's side at (x, z) (y follows from the surface) or its base cap (face 2).
SurfaceHit cone_side_hit(float x, float z) {
    const float r = std::sqrt(x * x + z * z);
    const glm::vec3 p(x, 1.0f - 2.0f * r, z);
    return shape_hit(Shape{ShapeKind::cone}, p, 0, {2.0f * p.x, 0.5f * (1.0f - p.y), 2.0f * p.z});
}

void expect_vec_near(const glm::vec3& got, const glm::vec3& want, float tolerance) {
    EXPECT_NEAR(got.x, want.x, tolerance);
    EXPECT_NEAR(got.y, want.y, tolerance);
    EXPECT_NEAR(got.z, want.z, tolerance);
}

/// A 12 x 16 image: the 3 x 4 unwrap cells are 4 x 4 texels, each cell split into 2 x 2 quadrants
/// of uniform colour. Red encodes the cell (row * 3 + column), green the quadrant (qy * 2 + qx).
glm::vec3 cell_quadrant_texel(int x, int y) {
    const int cell = (y / 4) * 3 + x / 4, quadrant = ((y % 4) / 2) * 2 + (x % 4) / 2;
    return bytes(20 * cell, 60 * quadrant, 128);
}
glm::vec3 cell_quadrant_colour(int column, int row, int quadrant) { return bytes(20 * (row * 3 + column), 60 * quadrant, 128); }

/// A 4 x 4 image of four 2 x 2 quadrants: top-left red, top-right green, bottom-left blue, bottom-right white.
glm::vec3 quadrant_texel(int x, int y) {
    static const glm::vec3 colours[4] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}};
    return colours[(y / 2) * 2 + x / 2];
}
const glm::vec3 top_left_red(1, 0, 0), top_right_green(0, 1, 0), bottom_left_blue(0, 0, 1);

}  // namespace

// --- Image textures -------------------------------------------------------------------------

using TextureFiltering = TextureFiles;

TEST_F(TextureFiltering, BilinearMatchesHandComputedValues) {
    // Red channel: top row 0, 255; bottom row 51, 153.
    const std::string path = png("two.png", 2, 2, [](int x, int y) {
        const int red[2][2] = {{0, 255}, {51, 153}};
        return bytes(red[y][x], 0, 0);
    });
    const auto image = load_texture_image(path);
    ASSERT_EQ(image->width(), 2);
    // Texel centres give the texels; v = 0 is the top row.
    EXPECT_NEAR(image->colour({0.25f, 0.25f}).r, 0.0f, 1e-6f);
    EXPECT_NEAR(image->colour({0.75f, 0.25f}).r, 1.0f, 1e-6f);
    EXPECT_NEAR(image->colour({0.25f, 0.75f}).r, 0.2f, 1e-6f);
    EXPECT_NEAR(image->colour({0.75f, 0.75f}).r, 0.6f, 1e-6f);
    // The centre blends all four equally; a quarter of the way blends with weights 3/4, 1/4.
    EXPECT_NEAR(image->colour({0.5f, 0.5f}).r, (0.0f + 1.0f + 0.2f + 0.6f) / 4.0f, 1e-6f);
    EXPECT_NEAR(image->colour({0.375f, 0.25f}).r, 0.75f * 0.0f + 0.25f * 1.0f, 1e-6f);
    EXPECT_NEAR(image->colour({0.75f, 0.375f}).r, 0.75f * 1.0f + 0.25f * 0.6f, 1e-6f);
    EXPECT_NEAR(image->colour({0.75f, 0.625f}).r, 0.25f * 1.0f + 0.75f * 0.6f, 1e-6f);
    // Luminance of a pure red texel: the Rec. 709 red weight.
    EXPECT_NEAR(image->height({0.75f, 0.25f}), 0.2126f, 1e-6f);
}

TEST_F(TextureFiltering, UWrapsAroundAndVClamps) {
    const std::string path = png("two.png", 2, 2, [](int x, int y) {
        const int red[2][2] = {{0, 255}, {51, 153}};
        return bytes(red[y][x], 0, 0);
    });
    const auto image = load_texture_image(path);
    // u = 0 lies halfway between the last column's centre (wrapped) and the first's.
    EXPECT_NEAR(image->colour({0.0f, 0.25f}).r, 0.5f, 1e-6f);
    EXPECT_NEAR(image->colour({1.0f, 0.25f}).r, 0.5f, 1e-6f);
    EXPECT_NEAR(image->colour({-0.75f, 0.25f}).r, 0.0f, 1e-6f);  // same as u = 0.25
    EXPECT_NEAR(image->colour({3.75f, 0.75f}).r, 0.6f, 1e-6f);   // same as u = 0.75
    // v = 0 and below stay on the top row (no blend with the bottom row); v >= 1 on the bottom row.
    EXPECT_NEAR(image->colour({0.25f, 0.0f}).r, 0.0f, 1e-6f);
    EXPECT_NEAR(image->colour({0.25f, -2.0f}).r, 0.0f, 1e-6f);
    EXPECT_NEAR(image->colour({0.25f, 1.0f}).r, 0.2f, 1e-6f);
    EXPECT_NEAR(image->colour({0.75f, 7.0f}).r, 0.6f, 1e-6f);
}

TEST_F(TextureFiltering, EightBitValuesAreLinearWithoutGamma) {
    const std::string path = png("grey.png", 1, 1, [](int, int) { return bytes(128, 64, 32); });
    const glm::vec3 c = load_texture_image(path)->colour({0.5f, 0.5f});
    expect_vec_near(c, glm::vec3(128, 64, 32) / 255.0f, 1e-6f);
}

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

TEST(TextureProcedural, CheckerIsEightByEightColourAndBlack) {
    const TextureSet set(textured_scene("redcheck"));
    auto at = [&](float u, float v) {
        SurfaceHit hit;
        hit.shape_kind = static_cast<int>(ShapeKind::sphere);  // the default mapping: uv as given
        hit.uv = {u, v};
        return set.diffuse(0, hit, kd_marker);
    };
    const glm::vec3 red(1, 0, 0), black(0.0f);
    EXPECT_EQ(at(0.01f, 0.01f), red);    // square (0, 0)
    EXPECT_EQ(at(0.13f, 0.01f), black);  // square (1, 0)
    EXPECT_EQ(at(0.01f, 0.13f), black);  // square (0, 1)
    EXPECT_EQ(at(0.13f, 0.13f), red);    // square (1, 1)
    EXPECT_EQ(at(0.99f, 0.99f), red);    // square (7, 7)
    EXPECT_EQ(at(0.99f, 0.01f), black);  // square (7, 0)
    EXPECT_EQ(at(-0.01f, 0.01f), black); // square (-1, 0): the pattern continues
    EXPECT_EQ(checker(*checker_colour("greencheck"), {0.3f, 0.3f}), glm::vec3(0, 1, 0));
    EXPECT_EQ(checker(*checker_colour("bluecheck"), {0.3f, 0.3f}), glm::vec3(0, 0, 1));
    EXPECT_EQ(checker(*checker_colour("whitecheck"), {0.3f, 0.3f}), glm::vec3(1, 1, 1));
    EXPECT_EQ(checker(*checker_colour("whitecheck"), {0.3f, 0.2f}), black);
    EXPECT_FALSE(checker_colour("purplecheck"));
}

TEST(TextureProcedural, UnknownProceduralNameIsAnInputError) {
    SceneDesc scene = textured_scene("purplecheck");
    EXPECT_THROW(TextureSet{scene}, InputError);
    scene = textured_scene("", "redcheck");  // a checkerboard is not a bump map
    EXPECT_THROW(TextureSet{scene}, InputError);
}

// --- Parametrisations -------------------------------------------------------------------------

using TextureUnwrap = TextureFiles;

TEST_F(TextureUnwrap, EachCubeFaceShowsItsCellUnmirrored) {
    const TextureSet set(textured_scene(png("cells.png", 12, 16, cell_quadrant_texel)));
    struct FaceCase {
        const char* name;
        int face, column, row;
        glm::vec3 centre, top_left;  // the face centre and the centre of its cell's top-left quadrant
    };
    const FaceCase cases[] = {
        {"top +y", 3, 1, 0, {0, 1, 0}, {-0.5f, 1, -0.5f}},       // image top edge at the back
        {"-x", 0, 0, 1, {-1, 0, 0}, {-1, 0.5f, -0.5f}},          // seen from -x: back is on the left
        {"front +z", 5, 1, 1, {0, 0, 1}, {-0.5f, 0.5f, 1}},
        {"+x", 1, 2, 1, {1, 0, 0}, {1, 0.5f, 0.5f}},             // seen from +x: front is on the left
        {"bottom -y", 2, 1, 2, {0, -1, 0}, {-0.5f, -1, 0.5f}},   // image top edge at the front
        {"back -z", 4, 1, 3, {0, 0, -1}, {-0.5f, -0.5f, -1}},    // image top edge at the bottom
    };
    for (const FaceCase& c : cases) {
        SCOPED_TRACE(c.name);
        // The face centre is the cell centre: the cell's red, the mean of its quadrants' green.
        const glm::vec3 centre = set.diffuse(0, box_hit(c.face, c.centre), kd_marker);
        EXPECT_NEAR(centre.r, cell_quadrant_colour(c.column, c.row, 0).r, 1e-6f);
        EXPECT_NEAR(centre.g, (0 + 60 + 120 + 180) / 4.0f / 255.0f, 1e-6f);
        expect_vec_near(set.diffuse(0, box_hit(c.face, c.top_left), kd_marker),
                        cell_quadrant_colour(c.column, c.row, 0), 1e-6f);
    }
}

TEST_F(TextureUnwrap, FilteringStaysInsideTheCell) {
    const TextureSet set(textured_scene(png("cells.png", 12, 16, cell_quadrant_texel)));
    // At the very edges of the front face the lookup only blends texels of cell (1, 1).
    for (const glm::vec3 p : {glm::vec3(0.999f, 0.999f, 1), glm::vec3(-0.999f, -0.999f, 1)}) {
        const glm::vec3 c = set.diffuse(0, box_hit(5, p), kd_marker);
        EXPECT_NEAR(c.r, cell_quadrant_colour(1, 1, 0).r, 1e-6f);
    }
    const glm::vec3 corner = set.diffuse(0, box_hit(5, {0.999f, -0.999f, 1}), kd_marker);
    expect_vec_near(corner, cell_quadrant_colour(1, 1, 3), 1e-6f);  // bottom-right quadrant
}

TEST_F(TextureUnwrap, NonCentredBoxesUseTheSameLayout) {
    const TextureSet set(textured_scene(png("cells.png", 12, 16, cell_quadrant_texel)));
    // An nh_box (corner (2, 0, 0), side 3): its front face's top-left quadrant.
    const Shape box{ShapeKind::box, glm::vec3(2, 0, 0), glm::vec3(5, 3, 3)};
    const SurfaceHit hit = shape_hit(box, {2.75f, 2.25f, 3}, 5, {0, 0, 1});
    expect_vec_near(set.diffuse(0, hit, kd_marker), cell_quadrant_colour(1, 1, 0), 1e-6f);
}

TEST_F(TextureUnwrap, SphereAndCylinderUseLongitudeAndHeight) {
    const TextureSet set(textured_scene(png("quad.png", 4, 4, quadrant_texel)));
    const Shape sphere{ShapeKind::sphere, glm::vec3(0.0f), glm::vec3(1.0f)};
    // u = 0.5 + atan2(x, z) / 2 pi, v = acos(y) / pi: front-left upper octant -> top-left quadrant.
    const glm::vec3 p = glm::normalize(glm::vec3(-0.5f, 0.7071f, 0.5f));
    expect_vec_near(set.diffuse(0, shape_hit(sphere, p, 0, p), kd_marker), top_left_red, 1e-6f);
    // Front-right lower -> bottom-right (white); cylinder side the same way, v = (1 - y) / 2.
    const glm::vec3 q = glm::normalize(glm::vec3(0.5f, -0.7071f, 0.5f));
    expect_vec_near(set.diffuse(0, shape_hit(sphere, q, 0, q), kd_marker), glm::vec3(1.0f), 1e-6f);
    const float s = std::sqrt(0.5f);
    expect_vec_near(set.diffuse(0, cylinder_hit(0, {-s, 0.5f, s}), kd_marker), top_left_red, 1e-6f);
    expect_vec_near(set.diffuse(0, cylinder_hit(0, {s, 0.5f, s}), kd_marker), top_right_green, 1e-6f);
}

TEST_F(TextureUnwrap, MeshTexcoordsHaveVUpAsInObjFiles) {
    const TextureSet set(textured_scene(png("quad.png", 4, 4, quadrant_texel)));
    SurfaceHit hit;
    hit.shape_kind = -1;
    hit.uv = {0.25f, 0.25f};  // vt near the bottom-left corner of the image
    expect_vec_near(set.diffuse(0, hit, kd_marker), bottom_left_blue, 1e-6f);
    hit.uv = {0.75f, 0.75f};
    expect_vec_near(set.diffuse(0, hit, kd_marker), top_right_green, 1e-6f);
}

using TextureRemaps = TextureFiles;

TEST_F(TextureRemaps, CubeRemapsPutTheWholeImageOnOneFace) {
    const std::string path = png("quad.png", 4, 4, quadrant_texel);
    const TextureSet top(textured_scene(path, "", "cubetop"));
    const TextureSet front(textured_scene(path, "", "cubefront"));
    const TextureSet bottom(textured_scene(path, "", "cubebot"));
    // Top: image top edge at the back (-z), left at -x.
    expect_vec_near(top.diffuse(0, box_hit(3, {-0.5f, 1, -0.5f}), kd_marker), top_left_red, 1e-6f);
    expect_vec_near(top.diffuse(0, box_hit(3, {0.5f, 1, -0.5f}), kd_marker), top_right_green, 1e-6f);
    expect_vec_near(top.diffuse(0, box_hit(3, {-0.5f, 1, 0.5f}), kd_marker), bottom_left_blue, 1e-6f);
    // Front: image top edge up, left at -x. Bottom: seen from below, image top edge at the front.
    expect_vec_near(front.diffuse(0, box_hit(5, {-0.5f, 0.5f, 1}), kd_marker), top_left_red, 1e-6f);
    expect_vec_near(front.diffuse(0, box_hit(5, {-0.5f, -0.5f, 1}), kd_marker), bottom_left_blue, 1e-6f);
    expect_vec_near(bottom.diffuse(0, box_hit(2, {-0.5f, -1, 0.5f}), kd_marker), top_left_red, 1e-6f);
    expect_vec_near(bottom.diffuse(0, box_hit(2, {0.5f, -1, 0.5f}), kd_marker), top_right_green, 1e-6f);
    // Every other face keeps the material's kd.
    for (int face = 0; face < 6; ++face) {
        glm::vec3 p(0.0f);
        p[face / 2] = face % 2 ? 1.0f : -1.0f;
        const SurfaceHit hit = box_hit(face, p);
        if (face != 3) {
            EXPECT_EQ(top.diffuse(0, hit, kd_marker), kd_marker) << face;
        }
        if (face != 5) {
            EXPECT_EQ(front.diffuse(0, hit, kd_marker), kd_marker) << face;
        }
        if (face != 2) {
            EXPECT_EQ(bottom.diffuse(0, hit, kd_marker), kd_marker) << face;
        }
    }
}

TEST_F(TextureRemaps, CylinderTopIsAPlanarProjectionOnTheTopCap) {
    const TextureSet set(textured_scene(png("quad.png", 4, 4, quadrant_texel), "", "cyltop"));
    expect_vec_near(set.diffuse(0, cylinder_hit(1, {-0.5f, 1, -0.5f}), kd_marker), top_left_red, 1e-6f);
    expect_vec_near(set.diffuse(0, cylinder_hit(1, {0.5f, 1, -0.5f}), kd_marker), top_right_green, 1e-6f);
    expect_vec_near(set.diffuse(0, cylinder_hit(1, {-0.5f, 1, 0.5f}), kd_marker), bottom_left_blue, 1e-6f);
    EXPECT_EQ(set.diffuse(0, cylinder_hit(0, {1, 0, 0}), kd_marker), kd_marker);
    EXPECT_EQ(set.diffuse(0, cylinder_hit(2, {0, -1, 0}), kd_marker), kd_marker);
}

TEST_F(TextureRemaps, ConeTopProjectsFromAboveWithTheCentreAtTheApex) {
    const std::string path = png("quad.png", 4, 4, quadrant_texel);
    const TextureSet set(textured_scene(path, "", "conetop"));
    expect_vec_near(set.diffuse(0, cone_side_hit(-0.5f, -0.5f), kd_marker), top_left_red, 1e-6f);
    expect_vec_near(set.diffuse(0, cone_side_hit(0.5f, -0.5f), kd_marker), top_right_green, 1e-6f);
    expect_vec_near(set.diffuse(0, cone_side_hit(-0.5f, 0.5f), kd_marker), bottom_left_blue, 1e-6f);
    // The apex sees the image centre: the mean of the four quadrants.
    expect_vec_near(set.diffuse(0, cone_side_hit(0.0f, 0.0f), kd_marker), glm::vec3(0.5f, 0.5f, 0.5f), 1e-6f);
    const SurfaceHit base = shape_hit(Shape{ShapeKind::cone}, {0, -1, 0}, 2, {0, -1, 0});
    EXPECT_EQ(set.diffuse(0, base, kd_marker), kd_marker);
}

TEST_F(TextureRemaps, RemapForAnotherShapeKindIsIgnored) {
    const std::string path = png("quad.png", 4, 4, quadrant_texel);
    const TextureSet plain(textured_scene(path)), remapped(textured_scene(path, "", "cubetop"));
    const Shape sphere{ShapeKind::sphere, glm::vec3(0.0f), glm::vec3(1.0f)};
    const glm::vec3 p = glm::normalize(glm::vec3(0.3f, 0.4f, 0.8f));
    EXPECT_EQ(remapped.diffuse(0, shape_hit(sphere, p, 0, p), kd_marker),
              plain.diffuse(0, shape_hit(sphere, p, 0, p), kd_marker));
}

// --- Bump maps --------------------------------------------------------------------------------

using BumpMapping = TextureFiles;

TEST_F(BumpMapping, LinearRampTiltsTheNormalDownhill) {
    // Luminance rises by 16/255 per texel to the right (u): dh/du = 16/255 * 16 texels per unit.
    const std::string ramp_u = png("ramp_u.png", 16, 16, [](int x, int) { return bytes(16 * x, 16 * x, 16 * x); });
    const std::string ramp_v = png("ramp_v.png", 16, 16, [](int, int y) { return bytes(16 * y, 16 * y, 16 * y); });
    const float slope = bump_depth * 16.0f / 255.0f * 16.0f;
    const TextureSet along_u(textured_scene("", ramp_u, "cubefront")), along_v(textured_scene("", ramp_v, "cubefront"));
    const SurfaceHit hit = box_hit(5, {0.1f, 0.2f, 1});
    const glm::vec3 n(0, 0, 1);
    // Height grows towards +x: the raised side is to the right, so the normal leans to -x.
    expect_vec_near(along_u.shading_normal(0, hit, n), glm::normalize(glm::vec3(-slope, 0, 1)), 1e-5f);
    // Height grows down the image (v), i.e. towards -y on the front face: the normal leans to +y.
    expect_vec_near(along_v.shading_normal(0, hit, n), glm::normalize(glm::vec3(0, slope, 1)), 1e-5f);
    // The tilt angle itself.
    const float angle = std::acos(glm::dot(along_u.shading_normal(0, hit, n), n));
    EXPECT_NEAR(angle, std::atan(slope), 1e-4f);
    // Seen from inside, the result is the same normal, flipped.
    expect_vec_near(along_u.shading_normal(0, hit, -n), -glm::normalize(glm::vec3(-slope, 0, 1)), 1e-5f);
}

TEST_F(BumpMapping, TiltDoesNotDependOnTheObjectsScale) {
    const std::string ramp = png("ramp.png", 16, 16, [](int x, int) { return bytes(16 * x, 16 * x, 16 * x); });
    const TextureSet set(textured_scene("", ramp, "cubefront"));
    SurfaceHit hit = box_hit(5, {0.1f, 0.2f, 1});
    const glm::vec3 unit = set.shading_normal(0, hit, {0, 0, 1});
    hit.dpdu *= 7.0f;
    hit.dpdv *= 7.0f;
    expect_vec_near(set.shading_normal(0, hit, {0, 0, 1}), unit, 1e-6f);
}

TEST_F(BumpMapping, UnwrapCellsScaleHeightsByTheTextureUnitSize) {
    // Default cube mapping: the front face is one 1/3 x 1/4 cell. One texture unit spans
    // |dp/du'| = 3 * 2 = 6 along x and 4 * 2 = 8 along y: L = sqrt(48), slope = L / 6 * depth * dh/du'.
    const std::string ramp = png("ramp.png", 48, 64, [](int x, int) { return bytes(4 * x, 4 * x, 4 * x); });
    const TextureSet set(textured_scene("", ramp));
    const float slope = std::sqrt(48.0f) / 6.0f * bump_depth * (4.0f / 255.0f * 48.0f);
    expect_vec_near(set.shading_normal(0, box_hit(5, {0.1f, 0.2f, 1}), {0, 0, 1}),
                    glm::normalize(glm::vec3(-slope, 0, 1)), 1e-5f);
}

TEST_F(BumpMapping, ConstantHeightLeavesTheNormalUnchanged) {
    const std::string flat = png("flat.png", 8, 8, [](int, int) { return bytes(200, 200, 200); });
    const TextureSet set(textured_scene("", flat));
    const glm::vec3 n = glm::normalize(glm::vec3(0.3f, 0.4f, 0.8f));
    const Shape sphere{ShapeKind::sphere, glm::vec3(0.0f), glm::vec3(1.0f)};
    expect_vec_near(set.shading_normal(0, shape_hit(sphere, n, 0, n), n), n, 1e-6f);
    expect_vec_near(set.shading_normal(0, box_hit(3, {0.2f, 1, 0.3f}), {0, 1, 0}), glm::vec3(0, 1, 0), 1e-6f);
}

TEST(BumpSinewaves, FlatWhereTheGradientVanishesSteepestBetween) {
    const TextureSet set(textured_scene("", "sinewaves", "cubetop"));
    const glm::vec3 up(0, 1, 0);
    // Top face: u' = (x + 1) / 2, v' = (z + 1) / 2. Zero gradient at the centre and wherever
    // r = |uv - (0.5, 0.5)| is a multiple of 1/16 (crests and troughs).
    for (const glm::vec3 p : {glm::vec3(0, 1, 0), glm::vec3(0.125f, 1, 0), glm::vec3(0, 1, -0.25f),
                              glm::vec3(0.375f * std::sqrt(0.5f), 1, 0.375f * std::sqrt(0.5f))})
        expect_vec_near(set.shading_normal(0, box_hit(3, p), up), up, 1e-5f);
    // r = 1/32 (x = 1/16): just past the central crest, slope 1/2 going down outward, so the normal
    // leans outward (+x) by atan(1/2).
    expect_vec_near(set.shading_normal(0, box_hit(3, {0.0625f, 1, 0}), up), glm::normalize(glm::vec3(0.5f, 1, 0)),
                    1e-5f);
    EXPECT_NEAR(ripple_gradient({0.5f + 1.0f / 32.0f, 0.5f}).x, -0.5f, 1e-5f);
    // Outside the top face the remap leaves the normal alone.
    expect_vec_near(set.shading_normal(0, box_hit(5, {0.0625f, 0, 1}), {0, 0, 1}), glm::vec3(0, 0, 1), 1e-6f);
    // "ripple" is the same map.
    const TextureSet ripple(textured_scene("", "ripple", "cubetop"));
    expect_vec_near(ripple.shading_normal(0, box_hit(3, {0.0625f, 1, 0}), up), glm::normalize(glm::vec3(0.5f, 1, 0)),
                    1e-5f);
}

TEST(BumpSinewaves, SingularFrameLeavesTheNormalUnchanged) {
    const TextureSet set(textured_scene("", "sinewaves"));
    const Shape sphere{ShapeKind::sphere, glm::vec3(0.0f), glm::vec3(1.0f)};
    const SurfaceHit pole = shape_hit(sphere, {0, 1, 0}, 0, {0, 1, 0});  // dp/du = dp/dv = 0 at the pole
    ASSERT_EQ(pole.dpdu, glm::vec3(0.0f));
    const glm::vec3 n(0, 1, 0);
    EXPECT_EQ(set.shading_normal(0, pole, n), n);
    EXPECT_EQ(set.shading_normal(0, pole, -n), -n);
}

TEST(BumpSinewaves, WorksOnEveryPrimitiveAndFacesTheInputSide) {
    const TextureSet set(textured_scene("", "sinewaves"));
    const Shape sphere{ShapeKind::sphere, glm::vec3(0.0f), glm::vec3(1.0f)};
    const glm::vec3 p = glm::normalize(glm::vec3(0.3f, 0.2f, 0.9f));
    SurfaceHit mesh;  // a triangle in the plane z = 0 with texcoords (x, y): dpdu = +x, dpdv = +y
    mesh.shape_kind = -1;
    mesh.normal = {0, 0, 1};
    mesh.uv = {0.5f + 1.0f / 32.0f, 0.5f};
    mesh.dpdu = {1, 0, 0};
    mesh.dpdv = {0, 1, 0};
    const SurfaceHit hits[] = {shape_hit(sphere, p, 0, p), box_hit(1, {1, 0.3f, 0.1f}), cylinder_hit(0, {0.6f, 0.3f, 0.8f}),
                               cylinder_hit(1, {0.3f, 1, 0.2f}), cone_side_hit(0.2f, 0.3f), mesh};
    for (const SurfaceHit& hit : hits) {
        SCOPED_TRACE(hit.shape_kind);
        const glm::vec3 front = set.shading_normal(0, hit, hit.normal);
        const glm::vec3 back = set.shading_normal(0, hit, -hit.normal);
        EXPECT_NEAR(glm::length(front), 1.0f, 1e-5f);
        EXPECT_GT(glm::dot(front, hit.normal), 0.0f);
        expect_vec_near(back, -front, 1e-6f);
        EXPECT_GT(1.0f - glm::dot(front, hit.normal), 1e-6f);  // actually perturbed
    }
    // The mesh sits on the steepest ring, just outside the centre: the normal leans to +x.
    expect_vec_near(set.shading_normal(0, mesh, mesh.normal), glm::normalize(glm::vec3(0.5f, 0, 1)), 1e-5f);
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
    // Block centres on the visible half: u in (0.25, 0.75) -> columns 1 and 2, both rows.
    for (int row = 0; row < 2; ++row) {
        for (int column = 1; column <= 2; ++column) {
            const float u = (column + 0.5f) / 4.0f, v = (row + 0.5f) / 2.0f;
            const float phi = 2.0f * pi * (u - 0.5f), theta = pi * v;
            const glm::vec3 p(std::sin(theta) * std::sin(phi), std::cos(theta), std::sin(theta) * std::cos(phi));
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
    // the Lambert factor becomes the cosine of the tilt.
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
    const float slope = bump_depth * 16.0f / 255.0f * 16.0f;
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
    // The die (translate(-3.3, 0, 1.6) rotate('y', 35)): its top face at local (-0.5, 1, 0) is in
    // the top cell's yellow, between the pip and the border.
    const float c = std::cos(glm::radians(35.0f)), s = std::sin(glm::radians(35.0f));
    const glm::vec3 p(-3.3f - 0.5f * c, 1.0f, 1.6f + 0.5f * s);
    glm::vec2 pixel;
    ASSERT_TRUE(Camera(job.camera, job.width, job.height).project(p, pixel));
    const glm::vec3 top = image.at(static_cast<int>(pixel.x), static_cast<int>(pixel.y));
    // Yellow (0.95, 0.85, 0.30) under white light: red and green well above blue.
    EXPECT_GT(top.r, 2.0f * top.b) << top.r << " " << top.g << " " << top.b;
    EXPECT_GT(top.g, 2.0f * top.b) << top.r << " " << top.g << " " << top.b;
}
