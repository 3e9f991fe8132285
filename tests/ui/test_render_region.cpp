// The render region through the preview's model (docs/PREVIEW.md, "Render region"): set and
// cleared by its API, the accumulation going on in it without a restart while the other pixels
// keep the image, a classic render redoing the region alone, the region clamped to the image and
// cleared by a camera move; and the pixels a dragged box covers.
#include "ui/render_region_tool.h"
#include "ui/view_model.h"
#include "ui_test_support.h"

#include <gtest/gtest.h>

namespace caustica::ui {
namespace {

using namespace caustica::ui::testing;

ModelConfig region_config(const std::vector<std::string>& extra = {}) {
    ModelConfig config;
    config.option_tokens = {"--reproducible", "--threads", "2"};
    config.option_tokens.insert(config.option_tokens.end(), extra.begin(), extra.end());
    return config;
}

/// Pixels outside `region` that differ between two images of one size, and pixels inside.
struct Differences {
    int outside = 0, inside = 0;
};
Differences differences(const Image& a, const Image& b, const RenderRegion& region) {
    Differences d;
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x)
            if (a.at(x, y) != b.at(x, y)) ++(region.renders(x, y) ? d.inside : d.outside);
    return d;
}

TEST(ViewModelRegion, ADraggedBoxCoversThePixelsItTouches) {
    EXPECT_EQ(region_from_drag({10.5f, 20.2f}, {3.2f, 5.9f}, 256, 192), (RenderRegion{3, 5, 11, 21}));
    EXPECT_EQ(region_from_drag({-4.0f, 180.0f}, {30.0f, 250.0f}, 256, 192), (RenderRegion{0, 180, 30, 192}));
    EXPECT_TRUE(region_from_drag({10.0f, 10.0f}, {10.4f, 30.0f}, 256, 192).empty());  // a click, not a box
    EXPECT_TRUE(region_from_drag({300.0f, 10.0f}, {320.0f, 30.0f}, 256, 192).empty());  // off the image
    EXPECT_EQ(region_status({}), "");
    EXPECT_NE(region_status({3, 5, 11, 21}).find("3,5 - 11,21 (8 x 16)"), std::string::npos);
}

// A finished three-pass accumulation given a region and a pass limit of 5 continues (no restart)
// to 5 passes in the region: the pixels outside stay as they were. Cleared, the region gives way
// to the whole image, still the same accumulation, to 7 passes: pixels outside change then.
TEST(ViewModelRegion, TheAccumulationGoesOnInTheRegionAndTheRestKeepsItsImage) {
    TempFolder folder;
    ViewModel model(region_config({"--passes", "3"}));
    model.open(folder.write("scene.lua", caustic_box_text(20000, "gr.option('--integrator progressive')\n")));
    ASSERT_TRUE(run_until_finished(model, 20.0)) << model.error();
    const PreviewDriver& driver = model.driver();
    ASSERT_EQ(driver.accumulation().passes_done, 3);
    const Image three_passes = driver.image();
    const std::uint64_t restarts = driver.restarts();

    const RenderRegion region{96, 64, 160, 128};
    model.set_render_region(region);
    model.set_stop_rules({5, 0.0, 0.0});
    EXPECT_EQ(model.render_region(), region);
    int lowest = 3;
    ASSERT_TRUE(run_until(model, [&] {
        lowest = std::min(lowest, driver.accumulation().passes_done);
        return driver.finished() && driver.accumulation().passes_done == 5;
    }, 20.0));
    EXPECT_EQ(lowest, 3) << "the region restarted the accumulation";
    EXPECT_EQ(driver.restarts(), restarts);
    const Differences in_region = differences(driver.image(), three_passes, region);
    EXPECT_EQ(in_region.outside, 0);
    EXPECT_GT(in_region.inside, 0);

    const Image five_passes = driver.image();
    model.clear_render_region();
    EXPECT_TRUE(model.render_region().empty());
    model.set_stop_rules({7, 0.0, 0.0});
    ASSERT_TRUE(run_until(model, [&] { return driver.finished() && driver.accumulation().passes_done == 7; }, 20.0));
    EXPECT_EQ(driver.restarts(), restarts);
    EXPECT_GT(differences(driver.image(), five_passes, region).outside, 0);
}

// The classic integrator renders the region again alone; the region is clamped to the image, one
// wholly off it is none, and a camera move clears it (it marks pixels of the view it was drawn on).
TEST(ViewModelRegion, ClassicRendersTheRegionAgainAndACameraMoveClearsIt) {
    TempFolder folder;
    ViewModel model(region_config());
    model.open(folder.write("scene.lua", caustic_box_text(20000)));
    ASSERT_TRUE(run_until_finished(model)) << model.error();
    const PreviewDriver& driver = model.driver();
    ASSERT_EQ(driver.image().width, 256);
    const std::uint64_t restarts = driver.restarts();

    model.set_render_region({-10, -10, 20, 16});
    EXPECT_EQ(model.render_region(), (RenderRegion{0, 0, 20, 16}));
    model.set_render_region({300, 10, 400, 20});
    EXPECT_TRUE(model.render_region().empty());

    // The photons-only view changes every lit pixel; the region alone is rendered with it.
    const Image before = driver.image();
    const RenderRegion region{100, 120, 180, 180};
    model.set_render_region(region);
    CausticKnobs k = model.knobs();
    k.photons_only = true;
    model.set_knobs(k);
    ASSERT_TRUE(run_until(model, [&] { return driver.restarts() > restarts; }, 5.0));
    ASSERT_TRUE(run_until_finished(model)) << model.error();
    EXPECT_EQ(model.render_region(), region);
    const Differences d = differences(driver.image(), before, region);
    EXPECT_EQ(d.outside, 0);
    EXPECT_GT(d.inside, 0);

    model.orbit(10.0, 0.0);
    ASSERT_TRUE(run_until_finished(model));
    EXPECT_TRUE(model.render_region().empty());
    EXPECT_GT(differences(driver.image(), before, region).outside, 0);
}

}  // namespace
}  // namespace caustica::ui
