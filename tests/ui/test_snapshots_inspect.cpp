// Headless snapshots of the inspection tools (docs/INSPECTION.md): the A/B comparison modes show
// the current image and the reference where they should, and the hidden sidebar, the image zoom
// with sharp pixels and the hover readout with the surface under the cursor. With
// CAUSTICA_DOC_IMAGES=folder set they also write the README's screenshots (inspect_*.png) there.
#include "headless_preview.h"
#include "ui/keys.h"

#include "core/io/png_io.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <functional>
#include <memory>

namespace caustica::ui {
namespace {

using namespace caustica::ui::testing;

constexpr int key_b = 66;

/// The fixture with the test scene: few photons for speed; the README's screenshots show the
/// scene's own 2 million.
struct Preview : HeadlessPreview {
    Preview() : HeadlessPreview(caustic_box_text(std::getenv("CAUSTICA_DOC_IMAGES") ? 2000000 : 200000)) {}
    /// One more frame, then the window's pixels.
    std::vector<unsigned char> shot() {
        window.frame(*app);
        return window.pixels();
    }
};

TEST(SnapshotInspect, ComparisonModesShowCurrentAndReference) {
    Preview p;
    ASSERT_TRUE(p.settle()) << p.model->error();
    const std::vector<unsigned char> before = p.shot();
    p.window.frame(*p.app, HeadlessInput{.keys = {key_b}, .alt = true});  // Alt+B: the image becomes the reference
    InspectState& inspect = p.app->inspect();
    ASSERT_EQ(inspect.reference.width, p.model->driver().image().width);
    EXPECT_EQ(inspect.mode, CompareMode::split);  // a first reference shows the split at once

    // Identical images: the relative error is zero everywhere, the bottom of the ramp.
    inspect.mode = CompareMode::heat;
    const std::vector<unsigned char> heat = p.shot();
    const ImageLayout layout = p.app->layout();
    const glm::vec3 bottom = heat_colour(0.0f) * 255.0f;
    const Rgb expected{static_cast<int>(std::lround(bottom.r)), static_cast<int>(std::lround(bottom.g)),
                       static_cast<int>(std::lround(bottom.b))};
    const glm::ivec2 lo(layout.origin), hi(layout.origin + layout.size());
    int off_colour = 0;
    for (int y = lo.y + 1; y < hi.y - 1; y += 3)
        for (int x = lo.x + 1; x < hi.x - 1; x += 3) {
            const Rgb q = pixel(heat, x, y);
            off_colour += std::abs(q.r - expected.r) > 1 || std::abs(q.g - expected.g) > 1 || std::abs(q.b - expected.b) > 1;
        }
    EXPECT_EQ(off_colour, 0);
    inspect.mode = CompareMode::difference;  // and |A - B| is black, whatever the gain
    inspect.difference_stops = 10.0f;
    const std::vector<unsigned char> difference = p.shot();
    int not_black = 0;
    for (int y = lo.y + 1; y < hi.y - 1; y += 3)
        for (int x = lo.x + 1; x < hi.x - 1; x += 3) not_black += !(pixel(difference, x, y) == Rgb{0, 0, 0});
    EXPECT_EQ(not_black, 0);
    inspect.difference_stops = 0.0f;

    // Another image (photons only): split shows it left of the line and the reference right of it.
    p.window.frame(*p.app, HeadlessInput{.keys = {keys::p}, .alt = true});
    ASSERT_TRUE(p.settle());
    inspect.mode = CompareMode::off;
    const std::vector<unsigned char> after = p.shot();
    inspect.mode = CompareMode::split;
    inspect.split = 0.5f;
    const std::vector<unsigned char> split = p.shot();
    const int line = static_cast<int>(layout.origin.x + 0.5f * layout.size().x);
    int left_wrong = 0, right_wrong = 0, changed = 0;
    for (int y = lo.y + 24; y < hi.y; y += 2) {  // under the A and B labels
        for (int x = lo.x; x < line - 1; x += 2) {
            left_wrong += !(pixel(split, x, y) == pixel(after, x, y));
            changed += !(pixel(after, x, y) == pixel(before, x, y));
        }
        for (int x = line + 2; x < hi.x; x += 2) right_wrong += !(pixel(split, x, y) == pixel(before, x, y));
    }
    EXPECT_GT(changed, 1000);  // the two images do differ
    EXPECT_EQ(left_wrong, 0);
    EXPECT_EQ(right_wrong, 0);

    // The metrics follow (refreshed within a quarter of a second).
    ASSERT_TRUE(p.run_until([&] { return inspect.metrics && inspect.metrics->rmse > 0.0; }, 5.0));
    EXPECT_GT(inspect.metrics->mean_relative, 0.0);
    if (std::getenv("CAUSTICA_DOC_IMAGES")) {
        inspect.open_header = true;
        p.shot();
        write_doc_image(p.shot(), "inspect_split.png");
    }

    // A file that cannot be read is named with the reason; one of another size is loaded but
    // not compared (the image stays as it is, no metrics).
    const std::string missing = p.folder.file("missing.png");
    std::snprintf(inspect.reference_path.data(), inspect.reference_path.size(), "%s", missing.c_str());
    inspect.load_requested = true;
    p.shot();
    EXPECT_NE(inspect.reference_problem.find(missing), std::string::npos) << inspect.reference_problem;
    EXPECT_EQ(inspect.reference.width, p.model->driver().image().width);  // the snapshot stays
    const std::string small = p.folder.file("small.png");
    write_png_atomic(small, Image(4, 3), PixelEncoding::clamped_linear);
    std::snprintf(inspect.reference_path.data(), inspect.reference_path.size(), "%s", small.c_str());
    inspect.load_requested = true;
    p.shot();
    EXPECT_TRUE(inspect.reference_problem.empty()) << inspect.reference_problem;
    EXPECT_EQ(inspect.reference.width, 4);
    EXPECT_EQ(inspect.reference_name, "small.png");
    inspect.stats_due = true;
    ASSERT_TRUE(p.run_until([&] { return !inspect.stats_due; }, 5.0));
    EXPECT_FALSE(inspect.metrics);
    const std::vector<unsigned char> mismatched = p.shot();  // split asked for, A shown
    EXPECT_TRUE(pixel(mismatched, line + 20, hi.y - 10) == pixel(after, line + 20, hi.y - 10));


    if (!std::getenv("CAUSTICA_DOC_IMAGES")) return;
    // For the README: the relative error of N = 5 against N = 60 photons per estimate.
    CausticKnobs knobs = p.model->knobs();
    knobs.photons_only = false;
    p.model->set_knobs(knobs);
    ASSERT_TRUE(p.settle());
    p.window.frame(*p.app, HeadlessInput{.keys = {key_b}, .alt = true});
    knobs.num_neighbours = 60;
    p.model->set_knobs(knobs);
    ASSERT_TRUE(p.settle());
    inspect.mode = CompareMode::heat;
    inspect.stats_due = true;
    p.run_until([&] { return !inspect.stats_due; }, 5.0);
    inspect.open_header = true;
    p.shot();
    write_doc_image(p.shot(), "inspect_heat.png");
}

TEST(SnapshotInspect, HiddenSidebarZoomAndReadout) {
    Preview p;
    ASSERT_TRUE(p.settle()) << p.model->error();
    p.window.frame(*p.app, HeadlessInput{.keys = {keys::tab}});  // Tab: the image takes the window
    std::vector<unsigned char> shot = p.shot();
    EXPECT_EQ(p.app->image_area(), glm::vec2(window_width, window_height));
    ImageLayout layout = p.app->layout();
    ASSERT_EQ(layout.scale, 3.0f);  // 256 x 192 in 1280 x 720
    EXPECT_EQ(layout.origin.x, 256.0f);
    EXPECT_EQ(pixel(shot, 1270, 700), (Rgb{26, 26, 28}));  // the clear colour where the sidebar was

    // Ctrl+wheel on the ball: 3x -> 4x -> 6x about the cursor; the pixel under it stays.
    const glm::vec2 ball = layout.to_window({100.5f, 106.5f});
    for (int i = 0; i < 2; ++i) p.window.frame(*p.app, HeadlessInput{.mouse = ball, .wheel = 1.0f, .keys = {}, .ctrl = true});
    shot = p.shot();
    layout = p.app->layout();
    ASSERT_EQ(layout.scale, 6.0f) << layout.origin.x << " " << layout.origin.y;
    EXPECT_EQ(glm::floor(layout.to_image(ball)), glm::vec2(100.0f, 106.0f));
    // Nearest-neighbour magnification: every 6 x 6 block of window pixels is one image pixel
    // (below the status line).
    int blurred = 0, blocks = 0;
    for (int by = 40; by < 190; by += 3)
        for (int bx = 40; bx < 250; bx += 3) {
            const glm::ivec2 corner(layout.to_window({static_cast<float>(bx), static_cast<float>(by)}));
            if (corner.x < 0 || corner.y < 50 || corner.x + 6 > window_width || corner.y + 6 > window_height) continue;
            ++blocks;
            const Rgb first = pixel(shot, corner.x, corner.y);
            for (int k = 0; k < 36; ++k) blurred += !(pixel(shot, corner.x + k % 6, corner.y + k / 6) == first);
        }
    EXPECT_GT(blocks, 1000);
    EXPECT_EQ(blurred, 0);

    // The readout: the ball (glass, material 2 of the script), then the floor under it.
    p.app->force_hover(ball);
    p.shot();
    const InspectState& inspect = p.app->inspect();
    ASSERT_TRUE(inspect.pixel.valid);
    EXPECT_EQ(inspect.pixel.x, 100);
    EXPECT_EQ(inspect.pixel.y, 106);
    ASSERT_TRUE(inspect.surface);
    EXPECT_EQ(inspect.surface->object, "ball");
    EXPECT_EQ(inspect.surface->material, 2);
    EXPECT_TRUE(inspect.surface->transparent);
    EXPECT_TRUE(inspect.surface->caustic);  // the classic estimate, with the map there
    const glm::vec2 floor = layout.to_window({100.5f, 150.5f});
    p.app->force_hover(floor);
    p.window.frame(*p.app, HeadlessInput{.mouse = floor, .keys = {}});
    ASSERT_TRUE(inspect.surface);
    EXPECT_EQ(inspect.surface->object, "floor");
    EXPECT_EQ(inspect.surface->material, 0);
    EXPECT_GT(inspect.surface->map_photons, 0u);
    if (std::getenv("CAUSTICA_DOC_IMAGES")) {  // the README's: on the post's caustic
        p.app->force_hover(layout.to_window({160.5f, 129.5f}));
        p.shot();
        write_doc_image(p.shot(), "inspect_zoom_readout.png");
    }

    p.window.frame(*p.app, HeadlessInput{.keys = {keys::tab}});  // back
    p.shot();
    EXPECT_EQ(p.app->image_area(), glm::vec2(window_width - sidebar_width, window_height));
}

}  // namespace
}  // namespace caustica::ui
