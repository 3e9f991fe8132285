// The GL-free inspection tools (ui/inspection.h): histogram, comparison metrics, heat map ramp,
// pixel readout and the zoom/pan of the image view, with values worked out by hand.
#include "ui/hover_readout.h"
#include "ui/inspection.h"
#include "ui/tooltip.h"

#include "core/render/render_session.h"
#include "tests/test_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace caustica::ui {
namespace {

Image image_of(int w, int h, std::initializer_list<glm::vec3> pixels) {
    Image image(w, h);
    std::size_t i = 0;
    for (const glm::vec3& p : pixels) image.pixels.at(i++) = p;
    return image;
}

TEST(Inspection, HistogramBinsClippedBlackAndInvalid) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    // Exposure 2 (one stop): the statistics are of what the display shows.
    const Image image = image_of(3, 2, {{0.0f, 0.0f, 0.0f},                // black, below the range
                                        {0.15f, 0.15f, 0.15f},             // 0.3: bin 34 (log10 -0.52)
                                        {0.6f, 0.0f, 0.0f},                // 1.2 red: clipped, Y 0.255: bin 34
                                        {100.0f, 100.0f, 100.0f},          // clipped, above 10^2
                                        {0.0005f, 0.001f, 0.0015f},        // black in 8 bits, Y 0.00186: bin 12
                                        {nan, 0.0f, 0.0f}});               // invalid
    const LuminanceHistogram h = luminance_histogram(image, 2.0f);
    EXPECT_EQ(h.samples, 6u);
    EXPECT_FLOAT_EQ(h.bins[34], 2.0f / 6.0f);
    EXPECT_FLOAT_EQ(h.bins[12], 1.0f / 6.0f);
    float in_bins = 0.0f;
    for (float b : h.bins) in_bins += b;
    EXPECT_FLOAT_EQ(in_bins, 3.0f / 6.0f);
    EXPECT_FLOAT_EQ(h.below, 1.0f / 6.0f);
    EXPECT_FLOAT_EQ(h.above, 1.0f / 6.0f);
    EXPECT_FLOAT_EQ(h.clipped, 2.0f / 6.0f);
    EXPECT_FLOAT_EQ(h.black, 2.0f / 6.0f);
    EXPECT_FLOAT_EQ(h.invalid, 1.0f / 6.0f);
    // At exposure 1 the red pixel (0.6) is no longer clipped and the dim one is still black.
    const LuminanceHistogram h1 = luminance_histogram(image, 1.0f);
    EXPECT_FLOAT_EQ(h1.clipped, 1.0f / 6.0f);
    EXPECT_FLOAT_EQ(h1.black, 2.0f / 6.0f);
}

TEST(Inspection, HistogramEdgesAreTenPerDecade) {
    EXPECT_FLOAT_EQ(LuminanceHistogram::edge(0), 1e-4f);
    EXPECT_FLOAT_EQ(LuminanceHistogram::edge(40), 1.0f);
    EXPECT_FLOAT_EQ(LuminanceHistogram::edge(LuminanceHistogram::bin_count), 100.0f);
    EXPECT_EQ(luminance_histogram(Image(), 1.0f).samples, 0u);
}

TEST(Inspection, StrideKeepsTheSampleBudget) {
    EXPECT_EQ(sample_stride(1280, 720), 6);  // 214 x 120 = 25680 samples; stride 5 would take 36864
    EXPECT_EQ(sample_stride(181, 181), 1);   // 32761 samples
    EXPECT_EQ(sample_stride(182, 181), 2);
    EXPECT_EQ(sample_stride(1280, 720, 65536), 4);
    EXPECT_EQ(sample_stride(0, 10), 1);
    // A stride samples every stride-th pixel of every stride-th row: 3 x 3 with stride 2 is 4 pixels.
    EXPECT_EQ(luminance_histogram(Image(3, 3), 1.0f, 2).samples, 4u);
}

TEST(Inspection, ComparisonMetrics) {
    const Image a = image_of(2, 1, {{1.0f, 2.0f, 3.0f}, {0.0f, 0.0f, 0.0f}});
    const Image b = image_of(2, 1, {{1.0f, 2.0f, 2.0f}, {0.0f, 0.0f, 0.0005f}});
    const std::optional<ImageComparison> c = compare_images(a, b, 1e-3f);
    ASSERT_TRUE(c);
    EXPECT_EQ(c->samples, 2u);
    EXPECT_NEAR(c->rmse, std::sqrt((1.0 + 0.0005 * 0.0005) / 6.0), 1e-9);
    EXPECT_DOUBLE_EQ(c->max_abs, 1.0);
    EXPECT_EQ(c->relative_samples, 1u);        // |b|_1 = 0.0005 is under epsilon
    EXPECT_NEAR(c->mean_relative, 0.2, 1e-7);  // |(0,0,1)|_1 / |(1,2,2)|_1
    const std::optional<ImageComparison> same = compare_images(a, a);
    ASSERT_TRUE(same);
    EXPECT_EQ(same->rmse, 0.0);
    EXPECT_EQ(same->mean_relative, 0.0);
    EXPECT_EQ(same->max_abs, 0.0);
    EXPECT_FALSE(compare_images(a, Image(1, 2)));
    EXPECT_FALSE(compare_images(Image(), Image()));
    EXPECT_EQ(c->non_finite, 0u);
}

TEST(Inspection, NonFinitePixelsAreCountedNotTakenForAMatch) {
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    const Image broken = image_of(2, 1, {{nan, nan, nan}, {nan, 0.0f, 0.0f}});
    const Image fine = image_of(2, 1, {{1.0f, 1.0f, 1.0f}, {0.0f, 0.0f, 0.0f}});
    const std::optional<ImageComparison> none = compare_images(broken, fine);
    ASSERT_TRUE(none);
    EXPECT_EQ(none->samples, 0u);  // the panel says "no finite pixels to compare", not "RMSE 0"
    EXPECT_EQ(none->non_finite, 2u);
    const Image half = image_of(2, 1, {{1.0f, 1.0f, 1.0f}, {0.0f, inf, 0.0f}});
    const std::optional<ImageComparison> some = compare_images(fine, half);
    ASSERT_TRUE(some);
    EXPECT_EQ(some->samples, 1u);
    EXPECT_EQ(some->non_finite, 1u);
    EXPECT_EQ(some->rmse, 0.0);
}

TEST(Inspection, RelativeErrorAndHeatRamp) {
    EXPECT_FLOAT_EQ(relative_error({1, 1, 1}, {0, 0, 0}, 1e-3f), 3000.0f);
    EXPECT_FLOAT_EQ(relative_error({1, 2, 2}, {1, 2, 3}, 1e-3f), 1.0f / 6.0f);
    EXPECT_FLOAT_EQ(heat_position(1e-4f), 0.0f);
    EXPECT_FLOAT_EQ(heat_position(1e-2f), 1.0f / 3.0f);
    EXPECT_FLOAT_EQ(heat_position(0.1f), 2.0f / 3.0f);
    EXPECT_FLOAT_EQ(heat_position(1.0f), 1.0f);
    EXPECT_FLOAT_EQ(heat_position(50.0f), 1.0f);
    EXPECT_FLOAT_EQ(heat_position(std::numeric_limits<float>::quiet_NaN()), 0.0f);
    EXPECT_EQ(heat_colour(0.0f), glm::vec3(0.0f, 0.0f, 0.25f));
    EXPECT_EQ(heat_colour(0.5f), glm::vec3(0.0f, 0.8f, 0.3f));
    EXPECT_EQ(heat_colour(1.0f), glm::vec3(1.0f, 0.0f, 0.0f));
    EXPECT_EQ(heat_colour(7.0f), glm::vec3(1.0f, 0.0f, 0.0f));
    const glm::vec3 mid = heat_colour(0.125f);  // half way between the first two stops
    EXPECT_FLOAT_EQ(mid.g, 0.175f);
    EXPECT_FLOAT_EQ(mid.b, 0.625f);
}

TEST(Inspection, PixelReadout) {
    const Image image = image_of(3, 2, {{1, 0, 0}, {2, 0, 0}, {3, 0, 0}, {4, 0, 0}, {5, 0, 0}, {6, 0, 0}});
    const PixelReadout r = read_pixel(image, {2.9f, 1.0f});
    ASSERT_TRUE(r.valid);
    EXPECT_EQ(r.x, 2);
    EXPECT_EQ(r.y, 1);
    EXPECT_EQ(r.rgb, glm::vec3(6, 0, 0));
    EXPECT_FALSE(r.reference);
    EXPECT_FALSE(read_pixel(image, {3.0f, 0.0f}).valid);
    EXPECT_FALSE(read_pixel(image, {-0.1f, 0.0f}).valid);
    EXPECT_FALSE(read_pixel(image, {0.0f, std::numeric_limits<float>::quiet_NaN()}).valid);
    const Image reference = image_of(3, 2, {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}, {0, 0, 0}, {0, 7, 0}, {0, 0, 0}});
    const PixelReadout with = read_pixel(image, {1.5f, 1.5f}, &reference);
    ASSERT_TRUE(with.reference);
    EXPECT_EQ(*with.reference, glm::vec3(0, 7, 0));
    const Image other(2, 2);
    EXPECT_FALSE(read_pixel(image, {1.5f, 1.5f}, &other).reference);  // another size: no reference
    EXPECT_EQ(format_rgb({0.5f, 1234.5f, 0.000123f}), "0.5 1.23e+03 0.000123");
}

// A 200 x 100 image in an 800 x 600 area: fitted at 4x, origin (0, 100).
constexpr glm::vec2 area_origin(0.0f), area_size(800.0f, 600.0f);

TEST(Inspection, ZoomKeepsThePointUnderTheCursor) {
    ImageZoom zoom;
    const ImageLayout fitted = zoom.layout(area_origin, area_size, 200, 100);
    EXPECT_EQ(fitted.scale, 4.0f);
    EXPECT_EQ(fitted.origin, glm::vec2(0.0f, 100.0f));
    const glm::vec2 cursor(100.0f, 150.0f);  // image point (25, 12.5)
    zoom.zoom_at(fitted, area_origin, area_size, cursor, 1);
    EXPECT_FALSE(zoom.fit);
    EXPECT_EQ(zoom.scale, 6.0f);
    const ImageLayout zoomed = zoom.layout(area_origin, area_size, 200, 100);
    EXPECT_EQ(zoomed.origin, glm::vec2(-50.0f, 75.0f));
    EXPECT_EQ(zoomed.to_image(cursor), glm::vec2(25.0f, 12.5f));
    zoom.zoom_at(zoomed, area_origin, area_size, cursor, -2);
    EXPECT_EQ(zoom.scale, 3.0f);
    // The origin is rounded to whole window pixels: the point moves by less than one window pixel
    // (1/3 of an image pixel here) and stays in the same image pixel.
    const glm::vec2 p = zoom.layout(area_origin, area_size, 200, 100).to_image(cursor);
    EXPECT_NEAR(p.x, 25.0f, 1.0f / 3.0f);
    EXPECT_NEAR(p.y, 12.5f, 1.0f / 3.0f);
    EXPECT_EQ(glm::floor(p), glm::vec2(25.0f, 12.0f));
    zoom.fit_area();
    EXPECT_EQ(zoom.layout(area_origin, area_size, 200, 100).origin, fitted.origin);
}

TEST(Inspection, ZoomStepsAreWholeAboveOneAndBounded) {
    ImageZoom zoom;
    ImageLayout l = zoom.layout(area_origin, area_size, 200, 100);
    for (int i = 0; i < 30; ++i) {
        zoom.zoom_at(l, area_origin, area_size, {400.0f, 300.0f}, 1);
        l = zoom.layout(area_origin, area_size, 200, 100);
        EXPECT_EQ(l.scale, std::floor(l.scale));
    }
    EXPECT_EQ(zoom.scale, ImageZoom::max_scale);
    for (int i = 0; i < 30; ++i) {
        zoom.zoom_at(l, area_origin, area_size, {400.0f, 300.0f}, -1);
        l = zoom.layout(area_origin, area_size, 200, 100);
    }
    EXPECT_EQ(zoom.scale, ImageZoom::min_scale);
    zoom.set_scale(l, area_origin, area_size, {400.0f, 300.0f}, 1.0f);  // 1:1
    EXPECT_EQ(zoom.layout(area_origin, area_size, 200, 100).scale, 1.0f);
}

TEST(Inspection, PanMovesTheImageAndStaysOnIt) {
    ImageZoom zoom;
    const ImageLayout fitted = zoom.layout(area_origin, area_size, 200, 100);
    zoom.pan(fitted, area_origin, area_size, {10.0f, -20.0f});
    EXPECT_EQ(zoom.scale, 4.0f);  // panning a fitted image keeps its magnification
    EXPECT_EQ(zoom.layout(area_origin, area_size, 200, 100).origin, fitted.origin + glm::vec2(10.0f, -20.0f));
    zoom.pan(fitted, area_origin, area_size, {1e6f, -1e6f});
    EXPECT_EQ(zoom.centre, glm::vec2(0.0f, 100.0f));  // clamped: the image's corner at the middle
}

}  // namespace
}  // namespace caustica::ui

namespace caustica::ui {
namespace {

// RenderSession::inspect: the node is told apart from another of the same material by where the
// ray crosses it; CSG objects are named by their CSG node; no photon map, no caustic estimate.
TEST(Inspection, SessionInspectNamesTheNodeAndMaterial) {
    caustica::testing::JobBuilder b(32, 32);
    const int grey = b.material({0.8, 0.8, 0.8});
    const int red = b.material({0.9, 0.1, 0.1});
    const int left = b.add(NodeKind::sphere, grey);
    b.translate(left, {-1.5, 0.0, 0.0});
    const int right = b.add(NodeKind::sphere, grey);
    b.translate(right, {1.5, 0.0, 0.0});
    // A CSG union below them, its operands not children of anything.
    const int csg = b.add(NodeKind::csg_union, red);
    b.translate(csg, {0.0, -3.0, 0.0});
    for (int side = 0; side < 2; ++side) {
        NodeDesc operand;
        operand.kind = NodeKind::sphere;
        operand.name = side ? "lobe b" : "lobe a";
        operand.transforms.push_back({});
        operand.transforms.back().kind = TransformOp::Kind::translate;
        operand.transforms.back().amount = glm::dvec3(side ? 0.4 : -0.4, 0.0, 0.0);
        b.scene->nodes.push_back(operand);
        (side ? b.scene->nodes[csg].csg_right : b.scene->nodes[csg].csg_left) =
            static_cast<int>(b.scene->nodes.size()) - 1;
    }
    b.scene->materials[grey].where = {"scene.lua", 3};
    b.scene->nodes[right].where = {"scene.lua", 9};
    b.camera({0.0, 0.0, 10.0}, {0.0, 0.0, -1.0});
    RenderSession session;
    Options options;
    EXPECT_FALSE(session.inspect(Ray{{0, 0, 10}, {0, 0, -1}}, options));  // nothing built yet
    session.set_job(b.build());
    session.start();  // builds the scene (and renders the 32 x 32 image)
    ASSERT_TRUE(session.wait());
    auto look_at = [&](glm::vec3 target) {
        const glm::vec3 eye(0.0f, 0.0f, 10.0f);
        return session.inspect(Ray{eye, glm::normalize(target - eye)}, options);
    };
    const std::optional<SurfaceInspection> l = look_at({-1.5f, 0.0f, 0.0f});
    ASSERT_TRUE(l);
    EXPECT_EQ(l->object, b.scene->nodes[left].name);
    EXPECT_EQ(l->material, grey);
    EXPECT_EQ(l->material_where, "scene.lua:3");
    EXPECT_NEAR(glm::length(l->point - glm::vec3(-1.5f, 0.0f, 0.0f)), 1.0f, 1e-4f);  // on the unit sphere
    EXPECT_NEAR(l->distance, glm::length(l->point - glm::vec3(0.0f, 0.0f, 10.0f)), 1e-4f);
    EXPECT_EQ(l->kd, glm::vec3(0.8f));
    EXPECT_FALSE(l->caustic);  // no light, no photon map
    EXPECT_EQ(l->map_photons, 0u);
    const std::optional<SurfaceInspection> r = look_at({1.5f, 0.0f, 0.0f});
    ASSERT_TRUE(r);
    EXPECT_EQ(r->object, b.scene->nodes[right].name);
    EXPECT_EQ(r->object_where, "scene.lua:9");
    const std::optional<SurfaceInspection> c = look_at({0.0f, -3.0f, 0.0f});
    ASSERT_TRUE(c);
    EXPECT_EQ(c->object, b.scene->nodes[csg].name);
    EXPECT_EQ(c->material, red);
    EXPECT_FALSE(look_at({0.0f, 6.0f, 0.0f}));  // the sky
}

TEST(Inspection, HistogramAxisLabelsAreEverySecondDecade) {
    // The plot spans log10 luminance -4 .. 2: labels at its left edge, a third, two thirds, the right edge.
    const std::array<std::string, 4> labels = histogram_axis_labels();
    EXPECT_EQ(labels[0], "1e-4");
    EXPECT_EQ(labels[1], "0.01");
    EXPECT_EQ(labels[2], "1");
    EXPECT_EQ(labels[3], "100");
}

TEST(Inspection, APngReferenceIsSaidToBeClampedEightBit) {
    EXPECT_NE(reference_range_note("render.png").find("8-bit PNG"), std::string::npos);
    EXPECT_NE(reference_range_note("/some/folder/RENDER.PNG").find("clamped to 0..1"), std::string::npos);
    EXPECT_EQ(reference_range_note("render.exr"), "");
    EXPECT_EQ(reference_range_note("render.pfm"), "");
    EXPECT_EQ(reference_range_note("snapshot"), "");  // the preview's own image: HDR too
}

TEST(HoverReadout, ShowsOnlyOnceTheMouseAndTheCameraRest) {
    HoverRest rest;
    rest.update(10.0, false);  // the first frame counts as activity: nothing before a rest
    EXPECT_FALSE(rest.resting(10.0));
    EXPECT_FALSE(rest.resting(10.0 + 0.9 * readout_rest_seconds));
    EXPECT_TRUE(rest.resting(10.0 + readout_rest_seconds));
    rest.update(11.0, true);  // a drag, a move or an orbit: hidden again
    rest.update(11.2, false);
    EXPECT_FALSE(rest.resting(11.2));
    EXPECT_TRUE(rest.resting(11.0 + readout_rest_seconds));
}

TEST(HoverReadout, TheBoxKeepsClearOfTheCursorAndInsideTheArea) {
    const glm::vec2 area(910.0f, 720.0f), box(300.0f, 180.0f);
    for (const glm::vec2 cursor : {glm::vec2(5.0f, 5.0f), glm::vec2(900.0f, 5.0f), glm::vec2(5.0f, 715.0f),
                                   glm::vec2(900.0f, 715.0f), glm::vec2(455.0f, 360.0f), glm::vec2(620.0f, 600.0f)}) {
        const glm::vec2 at = readout_position(cursor, box, area);
        EXPECT_GE(at.x, readout_margin) << cursor.x << " " << cursor.y;
        EXPECT_GE(at.y, readout_margin) << cursor.x << " " << cursor.y;
        EXPECT_LE(at.x + box.x, area.x - readout_margin) << cursor.x << " " << cursor.y;
        EXPECT_LE(at.y + box.y, area.y - readout_margin) << cursor.x << " " << cursor.y;
        // The cursor and the gap around it stay uncovered.
        const bool clear_x = cursor.x + readout_cursor_gap <= at.x || at.x + box.x <= cursor.x - readout_cursor_gap;
        const bool clear_y = cursor.y + readout_cursor_gap <= at.y || at.y + box.y <= cursor.y - readout_cursor_gap;
        EXPECT_TRUE(clear_x && clear_y) << cursor.x << " " << cursor.y << " -> " << at.x << " " << at.y;
    }
    // Below and right of the cursor where there is room.
    EXPECT_EQ(readout_position({100.0f, 100.0f}, box, area), glm::vec2(124.0f, 124.0f));
    // A box larger than the area starts at its margin.
    EXPECT_EQ(readout_position({100.0f, 100.0f}, {2000.0f, 50.0f}, area).x, readout_margin);
}

TEST(Tooltip, WrapsWithinTheWindow) {
    // 13-pixel font: 32 font sizes (416 pixels) in a wide window, the window less its margins in a narrow one.
    EXPECT_EQ(tooltip_wrap_width(1280.0f, 13.0f), 416.0f);
    EXPECT_EQ(tooltip_wrap_width(400.0f, 13.0f), 400.0f - 2.0f * tooltip_margin);
    EXPECT_LE(tooltip_wrap_width(400.0f, 13.0f) + 2.0f * tooltip_margin, 400.0f);
    EXPECT_EQ(tooltip_wrap_width(50.0f, 13.0f), 104.0f);  // never narrower than 8 font sizes
}

}  // namespace
}  // namespace caustica::ui
