// Headless checks of what floats over the image and of the sidebar (docs/PREVIEW.md): the hover
// readout waits for the mouse to rest, the status line stays within the image area of a small
// window with the error banner under it, a copied camera is forgotten in another scene, and no
// frame shows the panels' defaults before the scene's values are there.
#include "headless_preview.h"

#include <gtest/gtest.h>

#include <chrono>
#include <functional>
#include <memory>
#include <thread>

namespace caustica::ui {
namespace {

using namespace caustica::ui::testing;

/// Runs frames of `window` with `input` (about 5 ms apart) until `done`; false after `seconds`.
bool frames_until(HeadlessWindow& window, ViewApp& app, const HeadlessInput& input, const std::function<bool()>& done,
                  double seconds = 60.0) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (!done()) {
        if (std::chrono::steady_clock::now() > end) return false;
        window.frame(app, input);
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return true;
}

TEST(SnapshotPanels, TheHoverReadoutWaitsUntilTheMouseRests) {
    HeadlessPreview p(caustic_box_text(200000));
    ASSERT_TRUE(p.settle()) << p.model->error();
    const InspectState& inspect = p.app->inspect();
    ASSERT_TRUE(inspect.readout);
    HeadlessInput input;
    input.mouse = p.app->layout().to_window({100.0f, 96.0f});
    p.frame(input);
    input.buttons[0] = true;
    p.frame(input);
    for (int i = 0; i < 8; ++i) {  // an orbit: 80 pixels to the right, the readout never in the way
        input.mouse.x += 10.0f;
        p.frame(input);
        EXPECT_FALSE(inspect.hover) << "frame " << i << " of the drag";
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    EXPECT_TRUE(p.model->orbit_camera().moved());
    input.buttons[0] = false;
    const auto released = std::chrono::steady_clock::now();
    p.frame(input);
    EXPECT_FALSE(inspect.hover) << "the view just orbited to is covered at once";
    ASSERT_TRUE(frames_until(p.window, *p.app, input, [&] { return inspect.hover.has_value(); }, 30.0));
    const double waited = std::chrono::duration<double>(std::chrono::steady_clock::now() - released).count();
    EXPECT_GE(waited, 0.9 * readout_rest_seconds);
    EXPECT_EQ(*inspect.hover, input.mouse);
    EXPECT_TRUE(inspect.pixel.valid);
    p.window.frame(*p.app, input);  // the readout drawn
    write_doc_image(p.window.pixels(), "readout_at_rest.png");
}

/// The preview in a window of 800 x 500 pixels, the size at which the status line ran under the sidebar.
struct SmallWindow {
    TempFolder folder;
    HeadlessWindow window{800, 500};  // before the model and app: destroyed last
    std::unique_ptr<ViewModel> model;
    std::unique_ptr<ViewApp> app;

    explicit SmallWindow(const std::string& scene_text) {
        ModelConfig config;
        config.option_tokens = {"--reproducible", "--threads", "2"};
        model = std::make_unique<ViewModel>(config);
        app = std::make_unique<ViewApp>(*model);
        model->open(folder.write("scene.lua", scene_text));
    }
    bool run_until(const std::function<bool()>& done) {
        if (!frames_until(window, *app, {}, done)) return false;
        for (int i = 0; i < 3; ++i) window.frame(*app);  // auto-sized windows settle
        return true;
    }
};

TEST(SnapshotPanels, TheStatusLineStaysInTheImageAreaWithTheErrorBannerUnderIt) {
    // Two progressive passes: the status has the long line of the accumulation (passes, photons,
    // samples, estimated error, radius), wider than the 430-pixel image area.
    SmallWindow w(caustic_box_text(200000, "gr.option('--integrator progressive --passes 2')\n"));
    ASSERT_TRUE(w.run_until([&] { return !w.model->changes_pending() && w.model->driver().finished(); }))
        << w.model->error();
    ASSERT_EQ(w.app->image_area().x, 800.0f - sidebar_width);
    ASSERT_TRUE(w.model->driver().accumulation().accumulating);
    ASSERT_GT(refinement_summary(w.model->driver().accumulation()).size() * 7, 430u);  // 7-pixel characters
    const PanelState& state = w.app->panels();
    const float area_right = w.app->image_area().x;
    EXPECT_GT(state.status_box.z, state.status_box.x);
    EXPECT_LE(state.status_box.z, area_right) << "the status line runs under the sidebar";
    EXPECT_EQ(state.error_box, glm::vec4(0.0f));  // no error, no banner

    w.folder.write("scene.lua", "root = gr.node('root')\nroot:no_such_method()\n");
    w.model->reload();
    ASSERT_TRUE(w.run_until([&] { return !w.model->error().empty(); }));
    EXPECT_GT(state.error_box.w, state.error_box.y);
    EXPECT_GE(state.error_box.y, state.status_box.w) << "the banner covers the status line";
    EXPECT_LE(state.error_box.z, area_right);
    EXPECT_LE(state.status_box.z, area_right);
    EXPECT_LE(state.error_box.w, w.app->image_area().y);
}

TEST(SnapshotPanels, ACopiedCameraIsForgottenInAnotherScene) {
    HeadlessPreview p(caustic_box_text(0));
    ASSERT_TRUE(p.settle()) << p.model->error();
    PanelState& state = p.app->panels();
    state.camera_text = p.model->camera_text();  // what "Copy camera" keeps
    state.camera_text_scene = p.model->scene_path();
    p.frame({});
    EXPECT_EQ(state.camera_text, p.model->camera_text());  // the same scene shows it
    const std::string other = p.folder.write("other.lua", caustic_box_text(0));
    p.model->open(other);
    ASSERT_TRUE(p.run_until([&] { return p.model->scene_path() == other && !p.model->changes_pending(); }));
    EXPECT_EQ(state.camera_text, "");
}

TEST(SnapshotPanels, NoFrameShowsThePanelsDefaultsBeforeTheScene) {
    HeadlessPreview p(caustic_box_text(0));  // the script loads in the background
    int frames_before = 0;
    while (!p.model->has_scene() && p.model->error().empty() && frames_before < 20000) {
        p.frame({});
        // A frame drawn before the scene arrived may not show knobs: they would be the defaults.
        EXPECT_EQ(p.app->panels().scene_values_shown, p.model->has_scene()) << "frame " << frames_before;
        ++frames_before;
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    ASSERT_TRUE(p.model->has_scene()) << p.model->error();
    EXPECT_GE(frames_before, 1);
    p.frame({});
    EXPECT_TRUE(p.app->panels().scene_values_shown);
}

}  // namespace
}  // namespace caustica::ui
