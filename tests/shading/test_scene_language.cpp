// The scene language's measured rules (docs/SCENE_LANGUAGE.md, "What a scene means", and
// docs/TEXTURES.md): primitive extents, uv layouts and bump tangents, remaps, checkers, ripples and
// PNG bump maps, the camera's field of view and the PNG output encoding. Every expected value is
// the rule's own.
#include "core/geometry/shapes.h"
#include "core/io/png_io.h"
#include "core/scene/camera.h"
#include "core/shading/texture.h"
#include "core/shading/texture_image.h"
#include "core/shading/texture_mapping.h"
#include "core/shading/texture_procedural.h"
#include "tests/scene_test_helpers.h"
#include "tests/temp_folder.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>

using namespace caustica;

namespace {

constexpr float pi = 3.14159265358979323846f;
const Shape unit_sphere{ShapeKind::sphere, glm::vec3(0.0f), glm::vec3(1.0f)};
const Shape cube{ShapeKind::box, glm::vec3(-1.0f), glm::vec3(1.0f)};
const Shape cylinder{ShapeKind::cylinder, glm::vec3(0.0f), glm::vec3(1.0f)};
const Shape cone{ShapeKind::cone, glm::vec3(0.0f), glm::vec3(1.0f)};
const glm::vec3 kd_marker(0.123f, 0.456f, 0.789f);

void expect_vec_near(const glm::vec3& got, const glm::vec3& want, float tolerance) {
    EXPECT_NEAR(got.x, want.x, tolerance);
    EXPECT_NEAR(got.y, want.y, tolerance);
    EXPECT_NEAR(got.z, want.z, tolerance);
}

void expect_uv_near(const glm::vec2& got, const glm::vec2& want, float tolerance = 1e-6f) {
    EXPECT_NEAR(got.x, want.x, tolerance);
    EXPECT_NEAR(got.y, want.y, tolerance);
}

/// The object-space tangents at a point, as a pair.
struct Tangents {
    glm::vec3 u, v;
};
Tangents tangents(const Shape& shape, const glm::vec3& p, int face) {
    Tangents t;
    shape_tangents(shape, p, face, t.u, t.v);
    return t;
}


/// A hit on the centred cube's face (0..5 = -x,+x,-y,+y,-z,+z) at p.
SurfaceHit cube_hit(int face, const glm::vec3& p) {
    glm::vec3 n(0.0f);
    n[face / 2] = face % 2 ? 1.0f : -1.0f;
    return caustica::testing::shape_hit(cube, p, face, n);
}

/// A hit carrying only uv (on a sphere, so that uv is used as it is).
SurfaceHit uv_hit(float u, float v) {
    SurfaceHit hit;
    hit.shape_kind = static_cast<int>(ShapeKind::sphere);
    hit.uv = {u, v};
    return hit;
}

/// A scene with one material (kd = kd_marker) whose texture or bump map is `source` under `remap`.
SceneDesc scene_with(const std::string& source, bool bumpmap, const std::string& remap = "",
                     std::shared_ptr<const Png8> image = nullptr) {
    SceneDesc scene;
    MaterialDesc material;
    material.kd = glm::dvec3(kd_marker);
    TextureDesc t;
    t.source = source;
    t.procedural = !image;
    t.image = std::move(image);
    t.remap = remap;
    scene.textures.push_back(t);
    (bumpmap ? material.bumpmap : material.texture) = 0;
    scene.materials.push_back(material);
    return scene;
}

/// A decoded 8-bit grey image whose pixel (x, y) (row 0 at the top) is value(x, y).
std::shared_ptr<const Png8> grey_image(int w, int h, const std::function<int(int, int)>& value) {
    auto png = std::make_shared<Png8>();
    png->width = w, png->height = h, png->channels = 1;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) png->data.push_back(static_cast<unsigned char>(value(x, y)));
    return png;
}

}  // namespace

// --- Primitives ---------------------------------------------------------------------------------

TEST(SceneLanguagePrimitives, ConeHasHeightOneApexAtHalfAndBaseRadiusOne) {
    ShapeInterval iv;
    // Down the axis: in at the apex y = +1/2, out through the base y = -1/2 (face 2).
    ASSERT_TRUE(intersect_shape_interval(cone, {0, 5, 0}, {0, -1, 0}, iv));
    EXPECT_NEAR(iv.entry.t, 4.5f, 1e-4f);
    EXPECT_NEAR(iv.exit.t, 5.5f, 1e-5f);
    EXPECT_EQ(iv.exit.face, 2);
    // Radius 1/2 - y: horizontal rays at several heights cross a chord of 2 (1/2 - y).
    for (const float y : {-0.45f, -0.25f, 0.0f, 0.2f, 0.4f}) {
        SCOPED_TRACE(y);
        ASSERT_TRUE(intersect_shape_interval(cone, {-5, y, 0}, {1, 0, 0}, iv));
        EXPECT_NEAR(iv.entry.t, 5.0f - (0.5f - y), 1e-5f);
        EXPECT_NEAR(iv.exit.t, 5.0f + (0.5f - y), 1e-5f);
        // The side's slope is 45 degrees: the outward normal makes 45 degrees with the axis.
        EXPECT_NEAR(glm::normalize(iv.entry.normal).y, std::sqrt(0.5f), 1e-5f);
    }
    // The base disc has radius 1: a vertical ray at r = 0.99 enters through it at y = -1/2.
    ASSERT_TRUE(intersect_shape_interval(cone, {0.99f, -5, 0}, {0, 1, 0}, iv));
    EXPECT_NEAR(iv.entry.t, 4.5f, 1e-5f);
    EXPECT_EQ(iv.entry.face, 2);
    EXPECT_NEAR(iv.exit.t, 5.0f - 0.49f, 1e-4f);  // leaves where 1/2 - y = 0.99
    EXPECT_FALSE(intersect_shape_interval(cone, {1.01f, -5, 0}, {0, 1, 0}, iv));
    // Nothing above the apex or below the base.
    EXPECT_FALSE(intersect_shape_interval(cone, {-5, 0.55f, 0}, {1, 0, 0}, iv));
    EXPECT_FALSE(intersect_shape_interval(cone, {-5, 1.0f, 0}, {1, 0, 0}, iv));
    EXPECT_FALSE(intersect_shape_interval(cone, {-5, -0.55f, 0}, {1, 0, 0}, iv));
    glm::vec3 lo, hi;
    shape_bounds(cone, lo, hi);
    expect_vec_near(lo, {-1, -0.5f, -1}, 0.0f);
    expect_vec_near(hi, {1, 0.5f, 1}, 0.0f);
}

TEST(SceneLanguagePrimitives, CubeFacesSitInTheirCellsOfTheFourByThreeCross) {
    struct FaceCase {
        int face;
        glm::vec3 centre;
        glm::vec2 cell;            // the cell's lower-left corner (u, v)
        glm::vec3 tangent_u, tangent_v;
    };
    const FaceCase cases[] = {
        {1, {1, 0, 0}, {0.5f, 1.0f / 3}, {0, -1, 0}, {0, 0, -1}},    // +x
        {0, {-1, 0, 0}, {0.0f, 1.0f / 3}, {0, 1, 0}, {0, 0, -1}},    // -x
        {3, {0, 1, 0}, {0.25f, 1.0f / 3}, {1, 0, 0}, {0, 0, -1}},    // +y
        {2, {0, -1, 0}, {0.75f, 1.0f / 3}, {-1, 0, 0}, {0, 0, -1}},  // -y
        {5, {0, 0, 1}, {0.25f, 0.0f}, {1, 0, 0}, {0, 1, 0}},         // +z
        {4, {0, 0, -1}, {0.25f, 2.0f / 3}, {1, 0, 0}, {0, -1, 0}},   // -z
    };
    const glm::vec2 cell_size(0.25f, 1.0f / 3.0f);
    for (const FaceCase& c : cases) {
        SCOPED_TRACE(c.face);
        expect_uv_near(shape_uv(cube, c.centre, c.face), c.cell + 0.5f * cell_size);
        const Tangents t = tangents(cube, c.centre, c.face);
        EXPECT_EQ(t.u, c.tangent_u);
        EXPECT_EQ(t.v, c.tangent_v);
        // The tangents point along increasing u and v: a step along U moves u only, and so on.
        const float step = 0.1f;
        const glm::vec2 du = shape_uv(cube, c.centre + step * t.u, c.face) - shape_uv(cube, c.centre, c.face);
        const glm::vec2 dv = shape_uv(cube, c.centre + step * t.v, c.face) - shape_uv(cube, c.centre, c.face);
        expect_uv_near(du, {step / 2 * cell_size.x, 0.0f});
        expect_uv_near(dv, {0.0f, step / 2 * cell_size.y});
    }
    // Corners: +x at (1, 1, 1) has s = (1, 1, 1): u = (3 - 1)/4, v = (2 - 1)/3.
    expect_uv_near(shape_uv(cube, {1, 1, 1}, 1), {0.5f, 1.0f / 3});
    expect_uv_near(shape_uv(cube, {1, -1, -1}, 1), {0.75f, 2.0f / 3});
    expect_uv_near(shape_uv(cube, {-1, -1, 1}, 5), {0.25f, 0.0f});
    expect_uv_near(shape_uv(cube, {1, 1, -1}, 4), {0.5f, 2.0f / 3});
    expect_uv_near(shape_uv(cube, {-1, -1, -1}, 4), {0.25f, 1.0f});
    // nh_box(c, L): s = (p - c) / L, the same layout.
    const Shape nh_box{ShapeKind::box, glm::vec3(2, 0, 0), glm::vec3(5, 3, 3)};
    expect_uv_near(shape_uv(nh_box, {3.5f, 1.5f, 3}, 5), {0.375f, 1.0f / 6});
    expect_uv_near(shape_uv(nh_box, {5, 3, 0}, 1), {0.5f, 2.0f / 3});
}

TEST(SceneLanguagePrimitives, CylinderSideAndCaps) {
    // Side: u = 1/2 + atan2(z, x) / 2 pi, v = (1 - y) / 4 in [0, 1/2].
    expect_uv_near(shape_uv(cylinder, {1, 1, 0}, 0), {0.5f, 0.0f});
    expect_uv_near(shape_uv(cylinder, {0, -1, 1}, 0), {0.75f, 0.5f});
    expect_uv_near(shape_uv(cylinder, {0, 0, -1}, 0), {0.25f, 0.25f});
    // Caps: top u = (3 + x)/4, v = (3 + z)/4; bottom u = (1 + x)/4, v = (3 + z)/4.
    expect_uv_near(shape_uv(cylinder, {1, 1, -1}, 1), {1.0f, 0.5f});
    expect_uv_near(shape_uv(cylinder, {-1, 1, 1}, 1), {0.5f, 1.0f});
    expect_uv_near(shape_uv(cylinder, {0, -1, 0}, 2), {0.25f, 0.75f});
    expect_uv_near(shape_uv(cylinder, {1, -1, 1}, 2), {0.5f, 1.0f});
    // Tangents: side U along increasing u, V = -y; caps U = +x, V = +z.
    Tangents t = tangents(cylinder, {1, 0.3f, 0}, 0);
    expect_vec_near(t.u, {0, 0, 1}, 1e-6f);
    EXPECT_EQ(t.v, glm::vec3(0, -1, 0));
    t = tangents(cylinder, {0, 0.3f, 1}, 0);
    expect_vec_near(t.u, {-1, 0, 0}, 1e-6f);
    EXPECT_GT(shape_uv(cylinder, glm::normalize(glm::vec3(-0.01f, 0.3f, 1)), 0).x, shape_uv(cylinder, {0, 0.3f, 1}, 0).x);
    for (const int face : {1, 2}) {
        t = tangents(cylinder, {0.2f, face == 1 ? 1.0f : -1.0f, 0.3f}, face);
        EXPECT_EQ(t.u, glm::vec3(1, 0, 0));
        EXPECT_EQ(t.v, glm::vec3(0, 0, 1));
    }
}

TEST(SceneLanguagePrimitives, ConeSideAndBase) {
    // Side: u as the cylinder, v = (1/2 - y) / 2 in [0, 1/2]; at y = 0 the radius is 1/2.
    expect_uv_near(shape_uv(cone, {0.5f, 0, 0}, 0), {0.5f, 0.25f});
    expect_uv_near(shape_uv(cone, {0, -0.5f, 1}, 0), {0.75f, 0.5f});
    EXPECT_NEAR(shape_uv(cone, {0, 0.5f, 0}, 0).y, 0.0f, 1e-6f);  // the apex: v = 0
    // Base cap: u = (1 + x)/2, v = (3 + z)/4.
    expect_uv_near(shape_uv(cone, {0, -0.5f, 0}, 2), {0.5f, 0.75f});
    expect_uv_near(shape_uv(cone, {-1, -0.5f, 1}, 2), {0.0f, 1.0f});
    // Side tangents: V = unit vector towards the apex, U = V x N.
    const glm::vec3 p(0.5f, 0.0f, 0.0f);
    const Tangents t = tangents(cone, p, 0);
    expect_vec_near(t.v, glm::normalize(glm::vec3(-0.5f, 0.5f, 0.0f)), 1e-6f);
    const glm::vec3 n = glm::normalize(glm::vec3(1, 1, 0));
    expect_vec_near(t.u, glm::cross(t.v, n), 1e-6f);
    expect_vec_near(t.u, {0, 0, -1}, 1e-6f);
    const Tangents apex = tangents(cone, {0, 0.5f, 0}, 0);
    EXPECT_EQ(apex.u, glm::vec3(0.0f));
    EXPECT_EQ(apex.v, glm::vec3(0.0f));
    const Tangents base = tangents(cone, {0.3f, -0.5f, 0.2f}, 2);
    EXPECT_EQ(base.u, glm::vec3(1, 0, 0));
    EXPECT_EQ(base.v, glm::vec3(0, 0, 1));
}

TEST(SceneLanguagePrimitives, SphereSeamPolesAndFront) {
    // u = 1/2 + atan2(-z, x) / 2 pi, v = (1 + y) / 2.
    expect_uv_near(shape_uv(unit_sphere, {1, 0, 0}, 0), {0.5f, 0.5f});    // image centre at +x
    expect_uv_near(shape_uv(unit_sphere, {0, 0, 1}, 0), {0.25f, 0.5f});   // facing +z: u = 1/4
    expect_uv_near(shape_uv(unit_sphere, {0, 0, -1}, 0), {0.75f, 0.5f});
    EXPECT_NEAR(shape_uv(unit_sphere, glm::normalize(glm::vec3(-1, 0, 1e-3f)), 0).x, 0.0f, 1e-3f);  // the seam at -x
    EXPECT_NEAR(shape_uv(unit_sphere, glm::normalize(glm::vec3(-1, 0, -1e-3f)), 0).x, 1.0f, 1e-3f);
    EXPECT_NEAR(shape_uv(unit_sphere, {0, 1, 0}, 0).y, 1.0f, 1e-6f);    // north pole: the top row
    EXPECT_NEAR(shape_uv(unit_sphere, {0, -1, 0}, 0).y, 0.0f, 1e-6f);
    const float c = std::sqrt(0.75f);
    EXPECT_NEAR(shape_uv(unit_sphere, {c, 0.5f, 0}, 0).y, 0.75f, 1e-6f);  // linear in height, not latitude
    // nh_sphere(c, r): the same, scaled by r and moved to c.
    const Shape nh_sphere{ShapeKind::sphere, glm::vec3(3, 1, 0), glm::vec3(2)};
    expect_uv_near(shape_uv(nh_sphere, {3, 1, 2}, 0), {0.25f, 0.5f});
    EXPECT_NEAR(shape_uv(nh_sphere, {3, 2, 0}, 0).y, 0.75f, 1e-6f);
    // Tangents: U = normalise(y, 0, -x), V = N x U (normalised, as the bump uses them); zero at
    // (0, 0, +-1).
    Tangents t = tangents(unit_sphere, {1, 0, 0}, 0);
    expect_vec_near(t.u, {0, 0, -1}, 1e-6f);
    expect_vec_near(t.v, {0, 1, 0}, 1e-6f);
    const glm::vec3 q = glm::normalize(glm::vec3(0.3f, 0.5f, 0.6f));
    t = tangents(nh_sphere, glm::vec3(3, 1, 0) + 2.0f * q, 0);
    expect_vec_near(t.u, glm::normalize(glm::vec3(q.y, 0, -q.x)), 1e-6f);
    expect_vec_near(t.v, glm::normalize(glm::cross(q, t.u)), 1e-6f);  // U is not tangent off the equator
    t = tangents(unit_sphere, {0, 0, 1}, 0);
    EXPECT_EQ(t.u, glm::vec3(0.0f));
    EXPECT_EQ(t.v, glm::vec3(0.0f));
}

// --- Remaps -------------------------------------------------------------------------------------

TEST(SceneLanguageRemaps, WindowsStretchToTheWholeImageBoundsIncluded) {
    struct WindowCase {
        const char* mode;
        glm::vec2 lo, hi;
    };
    const WindowCase cases[] = {{"cubetop", {0.25f, 1.0f / 3}, {0.5f, 2.0f / 3}},
                                {"cubefront", {0.25f, 0.0f}, {0.5f, 1.0f / 3}},
                                {"cubebot", {0.75f, 1.0f / 3}, {1.0f, 2.0f / 3}},
                                {"cyltop", {0.5f, 0.5f}, {1.0f, 1.0f}},
                                {"conetop", {0.0f, 0.5f}, {1.0f, 1.0f}}};
    for (const WindowCase& c : cases) {
        SCOPED_TRACE(c.mode);
        const TextureRemap remap = *parse_texture_remap(c.mode);
        auto at = [&](float fu, float fv) { return remap_uv(c.lo + glm::vec2(fu, fv) * (c.hi - c.lo), remap); };
        for (const glm::vec2 f : {glm::vec2(0, 0), glm::vec2(1, 1), glm::vec2(0, 1), glm::vec2(0.3f, 0.6f)}) {
            const TextureLookup l = at(f.x, f.y);
            ASSERT_TRUE(l.covered);  // the corners are inside: bounds inclusive
            expect_uv_near(l.uv, f, 1e-5f);
        }
        // Just outside each bound of v (and of u, where the window does not span it all).
        EXPECT_FALSE(remap_uv({0.5f * (c.lo.x + c.hi.x), c.lo.y - 1e-4f}, remap).covered);
        EXPECT_FALSE(remap_uv({0.5f * (c.lo.x + c.hi.x), c.hi.y + 1e-4f}, remap).covered);
        if (c.lo.x > 0.0f) {
            EXPECT_FALSE(remap_uv({c.lo.x - 1e-4f, 0.5f * (c.lo.y + c.hi.y)}, remap).covered);
        }
        if (c.hi.x < 1.0f) {
            EXPECT_FALSE(remap_uv({c.hi.x + 1e-4f, 0.5f * (c.lo.y + c.hi.y)}, remap).covered);
        }
    }
    // The windows are the faces they name: the +y face's corners are the cubetop window's.
    EXPECT_TRUE(texture_lookup(cube_hit(3, {1, 1, -1}), TextureRemap::cube_top).covered);
    expect_uv_near(texture_lookup(cube_hit(3, {1, 1, -1}), TextureRemap::cube_top).uv, {1, 1});
    expect_uv_near(texture_lookup(cube_hit(5, {-1, 1, 1}), TextureRemap::cube_front).uv, {0, 1});
    expect_uv_near(texture_lookup(cube_hit(2, {-1, -1, 1}), TextureRemap::cube_bottom).uv, {1, 0});
    expect_uv_near(texture_lookup(caustica::testing::shape_hit(cylinder, {1, 1, 1}, 1, {0, 1, 0}), TextureRemap::cylinder_top).uv, {1, 1});
    expect_uv_near(texture_lookup(caustica::testing::shape_hit(cone, {-1, -0.5f, -1}, 2, {0, -1, 0}), TextureRemap::cone_top).uv, {0, 0});
    EXPECT_FALSE(texture_lookup(caustica::testing::shape_hit(cone, {0.5f, 0, 0}, 0, {1, 1, 0}), TextureRemap::cone_top).covered);
}

TEST(SceneLanguageRemaps, OutsideTheWindowATextureIsBlackAndABumpDoesNothing) {
    const TextureSet white(scene_with("whitecheck", false, "cubefront"));
    const TextureSet ripple(scene_with("sinewaves", true, "cubefront"));
    // +x face: outside the cubefront window. Black replaces kd; the normal stays.
    const SurfaceHit side = cube_hit(1, {1, 0.2f, 0.3f});
    EXPECT_EQ(white.diffuse(0, side, kd_marker), glm::vec3(0.0f));
    EXPECT_EQ(ripple.shading_normal(0, side, {1, 0, 0}), glm::vec3(1, 0, 0));
    // Inside the window (+z face) both act: u' = s_x, v' = s_y.
    const SurfaceHit front = cube_hit(5, {2.0f * (0.5f / 24) - 1, 2.0f * (1.5f / 24) - 1, 1});  // square (0, 1)
    EXPECT_EQ(white.diffuse(0, front, kd_marker), glm::vec3(1.0f));
    EXPECT_NE(ripple.shading_normal(0, front, {0, 0, 1}), glm::vec3(0, 0, 1));
}

// --- Procedural textures and bump maps ----------------------------------------------------------

TEST(SceneLanguageTextures, CheckersAre24PerUnitWithTheSquareAtTheOriginBlack) {
    const TextureSet set(scene_with("redcheck", false));
    auto at = [&](float u, float v) { return set.diffuse(0, uv_hit(u, v), kd_marker); };
    const glm::vec3 red(1, 0, 0), black(0.0f);
    const float w = 1.0f / 24.0f;
    EXPECT_EQ(at(0.5f * w, 0.5f * w), black);  // square (0, 0)
    EXPECT_EQ(at(1.5f * w, 0.5f * w), red);    // (1, 0)
    EXPECT_EQ(at(0.5f * w, 1.5f * w), red);    // (0, 1)
    EXPECT_EQ(at(1.5f * w, 1.5f * w), black);  // (1, 1)
    EXPECT_EQ(at(23.5f * w, 0.5f * w), red);   // (23, 0): 24 squares along u
    EXPECT_EQ(at(0.99f, 0.99f), black);        // (23, 23)
    EXPECT_EQ(at(-0.5f * w, 0.5f * w), red);   // (-1, 0): the pattern continues
    // Count the colour changes along u over one unit: 23 inside, 24 squares.
    int changes = 0;
    for (int i = 1; i < 2400; ++i)
        changes += at((i - 0.5f) / 2400.0f, 0.3f * w) != at((i + 0.5f) / 2400.0f, 0.3f * w);
    EXPECT_EQ(changes, 23);
    EXPECT_EQ(*checker_colour("bluecheck"), glm::vec3(0.0f, 0.8f, 1.0f));
    EXPECT_EQ(*checker_colour("greencheck"), glm::vec3(0, 1, 0));
    EXPECT_EQ(*checker_colour("whitecheck"), glm::vec3(1, 1, 1));
    EXPECT_EQ(checker(*checker_colour("bluecheck"), {1.5f * w, 0.5f * w}), glm::vec3(0.0f, 0.8f, 1.0f));
}

TEST(SceneLanguageTextures, RippleHas15CrestsPerUnitAndTiltsUpTo45Degrees) {
    // p = cos(30 pi rho) r_hat around (1/2, 1/2).
    for (int k = 1; k <= 7; ++k) {
        SCOPED_TRACE(k);
        const float rho = k / 15.0f;  // crests every 1/15: 15 per uv unit
        expect_uv_near(ripple_perturbation({0.5f + rho, 0.5f}), {1, 0}, 1e-4f);
        expect_uv_near(ripple_perturbation({0.5f, 0.5f + rho - 0.5f / 15}), {0, -1}, 1e-4f);  // troughs between
        expect_uv_near(ripple_perturbation({0.5f + rho - 0.25f / 15, 0.5f}), {0, 0}, 1e-4f);
    }
    expect_uv_near(ripple_perturbation({0.5f, 0.5f}), {0, 0}, 0.0f);
    const glm::vec2 diagonal = ripple_perturbation(glm::vec2(0.5f) + glm::vec2(std::sqrt(0.5f) / 15.0f));
    expect_uv_near(diagonal, glm::vec2(std::sqrt(0.5f)), 1e-4f);
    // On the +z face under cubefront (u' = s_x, v' = s_y, U = +x, V = +y): at the first crest
    // outward along +x the normal tilts by 45 degrees towards +x.
    const TextureSet set(scene_with("ripple", true, "cubefront"));
    const glm::vec3 n = set.shading_normal(0, cube_hit(5, {2.0f / 15.0f, 0, 1}), {0, 0, 1});
    expect_vec_near(n, glm::normalize(glm::vec3(1, 0, 1)), 1e-4f);
    EXPECT_NEAR(std::acos(n.z) * 180.0f / pi, 45.0f, 1e-2f);
    // Seen from inside the result is the outward one flipped.
    expect_vec_near(set.shading_normal(0, cube_hit(5, {2.0f / 15.0f, 0, 1}), {0, 0, -1}), -n, 1e-6f);
}

TEST(SceneLanguageTextures, PngBumpTiltsTowardsBrighterWithStrengthFive) {
    // Intensity rises by 10/255 per column to the right, or per row upwards.
    const TextureSet along_u(scene_with("u.png", true, "cubefront", grey_image(8, 8, [](int x, int) { return 10 * x; })));
    const TextureSet along_v(scene_with("v.png", true, "cubefront", grey_image(8, 8, [](int, int y) { return 70 - 10 * y; })));
    const float g = 10.0f / 255.0f;
    const glm::vec3 n(0, 0, 1);
    // +z face under cubefront: U = +x, V = +y; column 3, row 4 of 8 at s = (3.5/8, 1 - 4.5/8).
    const SurfaceHit inner = cube_hit(5, {2.0f * 3.5f / 8 - 1, 2.0f * (1 - 4.5f / 8) - 1, 1});
    expect_vec_near(along_u.shading_normal(0, inner, n), glm::normalize(glm::vec3(5 * g, 0, 1)), 1e-5f);
    expect_vec_near(along_v.shading_normal(0, inner, n), glm::normalize(glm::vec3(0, 5 * g, 1)), 1e-5f);
    // At the borders the difference is one-sided: I(next) - I(here), not halved.
    const SurfaceHit corner = cube_hit(5, {-1, 1, 1});  // column 0, row 0
    expect_vec_near(along_u.shading_normal(0, corner, n), glm::normalize(glm::vec3(5 * g, 0, 1)), 1e-5f);
    expect_vec_near(along_v.shading_normal(0, corner, n), glm::normalize(glm::vec3(0, 5 * g, 1)), 1e-5f);
    // A single bright texel: its right neighbour tilts left (towards it), central difference 1/2.
    const TextureSet spot(scene_with("s.png", true, "cubefront", grey_image(8, 8, [](int x, int y) {
        return x == 3 && y == 4 ? 255 : 0;
    })));
    const SurfaceHit right = cube_hit(5, {2.0f * 4.5f / 8 - 1, 2.0f * (1 - 4.5f / 8) - 1, 1});
    expect_vec_near(spot.shading_normal(0, right, n), glm::normalize(glm::vec3(-2.5f, 0, 1)), 1e-5f);
    const SurfaceHit below = cube_hit(5, {2.0f * 3.5f / 8 - 1, 2.0f * (1 - 5.5f / 8) - 1, 1});
    expect_vec_near(spot.shading_normal(0, below, n), glm::normalize(glm::vec3(0, 2.5f, 1)), 1e-5f);
    EXPECT_EQ(spot.shading_normal(0, inner, n), n);  // the bright texel itself: both sides dark
}

TEST(SceneLanguageTextures, PngLookupIsTheNearestTexelClamped) {
    // A 4 x 3 RGB image whose texel (x, y) has red 30 x and green 60 y (bytes).
    auto png = std::make_shared<Png8>();
    png->width = 4, png->height = 3, png->channels = 3;
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 4; ++x) png->data.insert(png->data.end(), {static_cast<unsigned char>(30 * x),
                                                                      static_cast<unsigned char>(60 * y), 0});
    const TextureImage image = TextureImage::from_png(*png);
    auto at = [&](float u, float v) {
        const glm::vec3 c = image.colour({u, v});
        return glm::ivec2(static_cast<int>(std::lround(c.r * 255 / 30)), static_cast<int>(std::lround(c.g * 255 / 60)));
    };
    EXPECT_EQ(at(1.0f, 0.0f), glm::ivec2(3, 2));   // last column, bottom row
    EXPECT_EQ(at(0.0f, 1.0f), glm::ivec2(0, 0));   // v = 1: the top row
    EXPECT_EQ(at(0.2499f, 0.5f), glm::ivec2(0, 1));
    EXPECT_EQ(at(0.25f, 0.5f), glm::ivec2(1, 1));  // floor(u W): no rounding to the nearest centre
    EXPECT_EQ(at(0.74f, 0.34f), glm::ivec2(2, 1));
    EXPECT_EQ(at(0.74f, 0.333f), glm::ivec2(2, 2));  // (1 - v) H = 2.001
    EXPECT_EQ(at(-3.0f, 7.0f), glm::ivec2(0, 0));  // clamped, no wrap
    EXPECT_EQ(at(5.5f, -2.0f), glm::ivec2(3, 2));
    EXPECT_NEAR(image.colour({0.6f, 0.6f}).r, 60.0f / 255.0f, 0.0f);  // c / 255, no filtering
    // Through a TextureSet: a texture replaces kd (the nearest texel on the +z face's cell).
    const TextureSet set(scene_with("t.png", false, "cubefront", png));
    EXPECT_EQ(set.diffuse(0, cube_hit(5, {1, -1, 1}), kd_marker), glm::vec3(90, 120, 0) / 255.0f);
}

TEST(SceneLanguageTextures, MeshesHaveNoUvAndNoTangents) {
    const TextureSet checker_set(scene_with("whitecheck", false));
    const TextureSet image_set(scene_with("i.png", false, "", grey_image(2, 2, [](int x, int y) { return 100 * y + 10 * x; })));
    const TextureSet ripple(scene_with("ripple", true));
    SurfaceHit mesh;
    mesh.shape_kind = -1;
    mesh.normal = {0, 0, 1};
    mesh.uv = {0.5f + 1.5f / 24, 0.3f};  // whatever the mesh code fills in, the lookup is at (0, 0)
    mesh.dpdu = {1, 0, 0};
    mesh.dpdv = {0, 1, 0};
    EXPECT_EQ(checker_set.diffuse(0, mesh, kd_marker), glm::vec3(0.0f));                  // square (0, 0)
    EXPECT_EQ(image_set.diffuse(0, mesh, kd_marker), glm::vec3(100.0f / 255.0f));         // bottom-left texel
    EXPECT_EQ(ripple.shading_normal(0, mesh, mesh.normal), mesh.normal);                  // no tangents
}

// --- Camera and output --------------------------------------------------------------------------

TEST(SceneLanguageCamera, GrRenderAngleIsHorizontalWithVerticalAngleFovOverAspect) {
    const CameraDesc desc{{0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 60.0};
    auto angle = [](const Ray& r, int axis) {
        return std::atan2(std::fabs(r.direction[axis]), -r.direction.z) * 180.0f / pi;
    };
    // 200 x 100: aspect 2, fov_y = 60 / 2 = 30 degrees; the image plane is aspect times wider.
    EXPECT_DOUBLE_EQ(vertical_fov_degrees(desc, 200, 100), 30.0);
    const Camera wide(desc, 200, 100);
    EXPECT_NEAR(angle(wide.generate(100, 0), 1), 15.0f, 1e-3f);
    EXPECT_NEAR(std::tan(angle(wide.generate(200, 50), 0) * pi / 180.0f), 2.0f * std::tan(15.0f * pi / 180.0f), 1e-5f);
    // 100 x 200: fov_y = 60 * 2 = 120 degrees.
    const Camera tall(desc, 100, 200);
    EXPECT_NEAR(angle(tall.generate(50, 0), 1), 60.0f, 1e-3f);
    // 100 x 300 at 120 degrees would be 360 degrees tall: kept just below 180, upright and finite.
    const Camera very_tall(CameraDesc{{0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 120.0}, 100, 300);
    EXPECT_GT(very_tall.generate(50, 0).direction.y, 0.99f);
    EXPECT_LT(very_tall.generate(50, 300).direction.y, -0.99f);
    // Square images: the angle both ways.
    const Camera square(desc, 100, 100);
    EXPECT_NEAR(angle(square.generate(50, 0), 1), 30.0f, 1e-3f);
    EXPECT_NEAR(angle(square.generate(100, 50), 0), 30.0f, 1e-3f);
    // Up only fixes the roll: a tilted up gives the same rays as its part orthogonal to the view.
    const Camera tilted(CameraDesc{{0, 0, 0}, {0, 0, -1}, {0, 1, -3}, 60.0}, 200, 100);
    expect_vec_near(tilted.generate(37, 81).direction, wide.generate(37, 81).direction, 1e-6f);
}

TEST(SceneLanguageOutput, PngValuesAreTruncatedNotRounded) {
    EXPECT_EQ(encode_channel(0.999f, PixelEncoding::clamped_linear), 254);
    EXPECT_EQ(encode_channel(0.5f, PixelEncoding::clamped_linear), 127);
    EXPECT_EQ(encode_channel(0.7f / 255.0f, PixelEncoding::clamped_linear), 0);
    EXPECT_EQ(encode_channel(1.0f, PixelEncoding::clamped_linear), 255);
    EXPECT_EQ(encode_channel(1.7f, PixelEncoding::clamped_linear), 255);
    EXPECT_EQ(encode_channel(-0.2f, PixelEncoding::clamped_linear), 0);
    for (int k = 0; k <= 255; ++k) EXPECT_EQ(encode_channel(k / 255.0f, PixelEncoding::clamped_linear), k);
    // Through a written file.
    caustica::testing::TempFolder folder("scene_language_png");
    Image image(2, 1);
    image.at(0, 0) = {0.999f, 0.5f, 0.2f};
    image.at(1, 0) = {1.5f, -1.0f, 0.99f};
    const std::string path = folder.file("out.png");
    write_png_atomic(path, image, PixelEncoding::clamped_linear);
    const Png8 png = read_png(path);
    ASSERT_EQ(png.channels, 3);
    EXPECT_EQ(std::vector<int>(png.data.begin(), png.data.end()), (std::vector<int>{254, 127, 51, 255, 0, 252}));
}
