// Headless UI tests: the whole window rendered with OSMesa, as a person would see it. Panels are
// where they belong, the image region equals a batch render of the same view, the overlay shows
// where the outline is, mouse and keys drive the camera, and the command line picks the right
// executable.
#include "headless_preview.h"
#include "ui/keys.h"

#include "core/io/png_io.h"

#include <gtest/gtest.h>
#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <sstream>
#include <sys/wait.h>

namespace caustica::ui {
namespace {

using namespace caustica::ui::testing;

/// The fixture with the preview test scene by default.
struct Preview : HeadlessPreview {
    explicit Preview(const std::string& scene_text = caustic_box_text()) : HeadlessPreview(scene_text) {}
};

bool near(Rgb a, Rgb b, int tolerance) {
    return std::abs(a.r - b.r) <= tolerance && std::abs(a.g - b.g) <= tolerance && std::abs(a.b - b.b) <= tolerance;
}

/// An ImGui style colour drawn over the window's clear colour, as 8-bit values.
Rgb over_clear(ImGuiCol colour) {
    const ImVec4 c = ImGui::GetStyle().Colors[colour];
    const float clear[3] = {0.1f, 0.1f, 0.11f};
    auto channel = [&](float v, int i) { return static_cast<int>(std::lround(255.0f * (v * c.w + clear[i] * (1.0f - c.w)))); };
    return {channel(c.x, 0), channel(c.y, 1), channel(c.z, 2)};
}

/// Mean absolute difference over the image region between two snapshots.
double image_difference(const std::vector<unsigned char>& a, const std::vector<unsigned char>& b, const ImageLayout& layout) {
    const glm::vec2 size = layout.size();
    double sum = 0.0;
    long count = 0;
    for (int y = static_cast<int>(layout.origin.y); y < static_cast<int>(layout.origin.y + size.y); ++y)
        for (int x = static_cast<int>(layout.origin.x); x < static_cast<int>(layout.origin.x + size.x); ++x) {
            const Rgb p = pixel(a, x, y), q = pixel(b, x, y);
            sum += std::abs(p.r - q.r) + std::abs(p.g - q.g) + std::abs(p.b - q.b);
            ++count;
        }
    return sum / (3.0 * count);
}

TEST(Snapshot, PanelsAreWhereTheyBelong) {
    Preview preview;
    ASSERT_TRUE(preview.settle()) << preview.model->error();
    const std::vector<unsigned char> shot = preview.snapshot();
    // The sidebar: the window background everywhere but on headers, widgets and text.
    const Rgb window_bg = over_clear(ImGuiCol_WindowBg), clear{26, 26, 28};
    long background = 0, bright_text = 0, total = 0;
    for (int y = 30; y < window_height; ++y)
        for (int x = window_width - static_cast<int>(sidebar_width) + 4; x < window_width - 12; ++x) {
            const Rgb p = pixel(shot, x, y);
            background += near(p, window_bg, 2);
            bright_text += p.r > 200 && p.g > 200 && p.b > 200;
            ++total;
        }
    EXPECT_GT(background, total * 4 / 10);
    EXPECT_GT(bright_text, 2000);  // the labels and values
    // Collapsing headers: bars of the header colour across the sidebar.
    const Rgb header = [] {
        const ImVec4 h = ImGui::GetStyle().Colors[ImGuiCol_Header], w = ImGui::GetStyle().Colors[ImGuiCol_WindowBg];
        auto mix = [&](float hv, float wv, float clear) {
            const float under = wv * w.w + clear * (1.0f - w.w);
            return static_cast<int>(std::lround(255.0f * (hv * h.w + under * (1.0f - h.w))));
        };
        return Rgb{mix(h.x, w.x, 0.1f), mix(h.y, w.y, 0.1f), mix(h.z, w.z, 0.11f)};
    }();
    int header_rows = 0;
    for (int y = 0; y < window_height; ++y) {
        int run = 0;
        for (int x = window_width - 300; x < window_width - 100; ++x) run += near(pixel(shot, x, y), header, 3);
        header_rows += run > 190;
    }
    EXPECT_GE(header_rows, 3 * 12);  // at least three headers, each over a dozen pixels tall
    // Around the image: the clear colour; the status line's box at the top left.
    EXPECT_TRUE(near(pixel(shot, 20, window_height - 20), clear, 1));
    EXPECT_TRUE(near(pixel(shot, 500, window_height - 30), clear, 1));
    long status_bg = 0;
    const Rgb status = [] {
        const ImVec4 w = ImGui::GetStyle().Colors[ImGuiCol_WindowBg];
        auto mix = [&](float v, float clear) { return static_cast<int>(std::lround(255.0f * (v * 0.55f + clear * 0.45f))); };
        return Rgb{mix(w.x, 0.1f), mix(w.y, 0.1f), mix(w.z, 0.11f)};
    }();
    for (int x = 12; x < 150; ++x) status_bg += near(pixel(shot, x, 12), status, 2);
    EXPECT_GT(status_bg, 100);
}

/// How the preview's image region differs from the PNG `caustica render` writes of its scene.
struct BatchComparison {
    int worst = 0;        ///< largest channel difference, in 8-bit steps
    long differing = 0;   ///< pixels with any difference
    long mid_tones = 0;   ///< batch pixels whose green lies in (20, 235)
    int pixels = 0;
    float scale = 0.0f;   ///< the layout's magnification
};

/// Renders the preview's scene with `caustica render` (the view's options only: no preset of its
/// own) and compares the window's image region with it, pixel by pixel.
BatchComparison compare_with_batch(Preview& preview) {
    const std::vector<unsigned char> shot = preview.snapshot();
    const std::string reference = preview.folder.file("batch.png");
    const std::string command = std::string(CAUSTICA_BINARY) + " render " + preview.scene + " -o " + reference +
                                " --reproducible --threads 2 -s";
    BatchComparison result;
    if (std::system(command.c_str()) != 0) {
        ADD_FAILURE() << command;
        return result;
    }
    const Png8 batch = read_png(reference);
    const ImageLayout layout = preview.app->layout();
    EXPECT_EQ(batch.width, layout.image_width);
    EXPECT_EQ(batch.height, layout.image_height);
    result.pixels = batch.width * batch.height;
    result.scale = layout.scale;
    for (int y = 0; y < batch.height; ++y)
        for (int x = 0; x < batch.width; ++x) {
            const glm::vec2 w = layout.to_window({x + 0.5f, y + 0.5f});
            const Rgb s = pixel(shot, static_cast<int>(w.x), static_cast<int>(w.y));
            const unsigned char* b = &batch.data[(static_cast<std::size_t>(y) * batch.width + x) * batch.channels];
            const int d = std::max({std::abs(s.r - b[0]), std::abs(s.g - b[1]), std::abs(s.b - b[2])});
            result.worst = std::max(result.worst, d);
            result.differing += d > 0;
            result.mid_tones += b[1] > 20 && b[1] < 235;
        }
    std::printf("[ compare ] largest difference %d, %ld of %d pixels differ\n", result.worst, result.differing,
                result.pixels);
    return result;
}

TEST(Snapshot, ImageRegionMatchesABatchRenderOfTheSameView) {
    Preview preview;
    ASSERT_TRUE(preview.settle()) << preview.model->error();
    // What you see is what you save (docs/PREVIEW.md): the preview renders what `caustica render
    // SCENE` with the view's options does. Same job, same seed: the float images are identical. The
    // batch encodes with floor(255 v) (the PNG truncates), so the display must show
    // floor(255 v) / 255 too; GL's float-to-unorm conversion of that may round either way: at most
    // one step apart, per channel, and only where the float product lands a hair off a whole step.
    const BatchComparison c = compare_with_batch(preview);
    EXPECT_EQ(c.scale, 3.0f);  // 256 x 192 in the 910 x 720 image area: magnified three times
    EXPECT_LE(c.worst, 1);
    EXPECT_LT(c.differing, c.pixels / 100);
}

TEST(Snapshot, ViewTransformShowsWhatTheBatchPngHolds) {
    // The scene's --tonemap and --exposure go through the viewport's shader (shaders/image.frag):
    // the image region is the PNG `caustica render` writes with them, within the one step the
    // plain image may differ by (ImageRegionMatchesABatchRenderOfTheSameView).
    Preview preview(caustic_box_text(2000000, "gr.option('--tonemap filmic --exposure 1.5')\n"));
    ASSERT_TRUE(preview.settle()) << preview.model->error();
    ASSERT_EQ(preview.model->view_transform(), (ViewTransform{Tonemap::filmic, 1.5f, false}));
    const BatchComparison c = compare_with_batch(preview);
    EXPECT_LE(c.worst, 1);
    EXPECT_LT(c.differing, c.pixels / 100);
    EXPECT_GT(c.mid_tones, c.pixels / 10);  // the curve is exercised, not only black and white
}

TEST(Snapshot, OverlayIsDrawnWhereTheOutlineIs) {
    Preview preview;
    ASSERT_TRUE(preview.settle());
    const std::vector<unsigned char> off = preview.snapshot();
    const std::uint64_t renders = preview.model->stage_counters().renders;
    preview.frame(HeadlessInput{.keys = {keys::o}, .alt = true});  // Alt+O: the outline
    ASSERT_TRUE(preview.run_until([&] { return preview.model->overlay_settled() && !preview.model->overlay_image().outline.empty(); }));
    const std::vector<unsigned char> on = preview.snapshot();
    EXPECT_EQ(preview.model->stage_counters().renders, static_cast<int>(renders));  // a GL overlay, not a render
    const ImageLayout layout = preview.app->layout();
    const OverlayImage& overlay = preview.model->overlay_image();
    // Distance of a window point from the nearest outline segment or the light marker.
    auto distance = [&](glm::vec2 w) {
        float best = 1e9f;
        for (std::size_t i = 0; i + 1 < overlay.outline.size(); i += 2) {
            const glm::vec2 a = layout.to_window(overlay.outline[i]), b = layout.to_window(overlay.outline[i + 1]);
            const glm::vec2 ab = b - a;
            const float t = glm::dot(ab, ab) > 0.0f ? std::clamp(glm::dot(w - a, ab) / glm::dot(ab, ab), 0.0f, 1.0f) : 0.0f;
            best = std::min(best, glm::length(w - (a + t * ab)));
        }
        if (overlay.light_visible) best = std::min(best, glm::length(w - layout.to_window(overlay.light)) - 4.0f);
        return best;
    };
    long changed = 0, stray = 0;
    const glm::vec2 size = layout.size();
    for (int y = static_cast<int>(layout.origin.y); y < static_cast<int>(layout.origin.y + size.y); ++y)
        for (int x = static_cast<int>(layout.origin.x); x < static_cast<int>(layout.origin.x + size.x); ++x) {
            if (near(pixel(on, x, y), pixel(off, x, y), 0)) continue;
            ++changed;
            stray += distance({x + 0.5f, y + 0.5f}) > 2.5f;  // 2-pixel lines, with their end caps
        }
    EXPECT_GT(changed, 500);
    EXPECT_EQ(stray, 0);
    // And the outline is visible: the midpoint of (nearly) every segment changed colour.
    int visible = 0, segments = 0;
    for (std::size_t i = 0; i + 1 < overlay.outline.size(); i += 2) {
        const glm::vec2 m = layout.to_window(0.5f * (overlay.outline[i] + overlay.outline[i + 1]));
        if (!layout.contains(m)) continue;
        ++segments;
        visible += !near(pixel(on, static_cast<int>(m.x), static_cast<int>(m.y)), pixel(off, static_cast<int>(m.x), static_cast<int>(m.y)), 0);
    }
    std::printf("[ overlay ] %ld pixels changed, %ld away from the outline, %d of %d segment midpoints visible\n", changed,
                stray, visible, segments);
    EXPECT_GT(segments, 20);
    EXPECT_GE(visible, segments * 95 / 100);
}

TEST(Snapshot, DraggingOrbitsAndRReturnsToTheScriptsView) {
    Preview preview;
    ASSERT_TRUE(preview.settle());
    const std::vector<unsigned char> original = preview.snapshot();
    OrbitCamera expected = preview.model->orbit_camera();
    expected.orbit(-30.0, 0.0);
    HeadlessInput drag;
    drag.mouse = {400.0f, 300.0f};
    preview.frame(drag);
    drag.buttons[0] = true;
    preview.frame(drag);
    for (int i = 0; i < 10; ++i) {
        drag.mouse.x += 10.0f;  // 100 pixels to the right: the camera turns 30 degrees to its left
        preview.frame(drag);
    }
    drag.buttons[0] = false;
    preview.frame(drag);
    EXPECT_TRUE(preview.model->orbit_camera().moved());
    const glm::dvec3 eye = preview.model->orbit_camera().eye();
    EXPECT_NEAR(glm::length(eye - expected.eye()), 0.0, 1e-6);
    EXPECT_LT(eye.x, expected.target().x);  // the camera went to its left
    ASSERT_TRUE(preview.settle());
    const std::vector<unsigned char> orbited = preview.snapshot();
    EXPECT_GT(image_difference(original, orbited, preview.app->layout()), 10.0);
    preview.frame(HeadlessInput{.keys = {keys::home}});
    ASSERT_TRUE(preview.settle());
    EXPECT_FALSE(preview.model->orbit_camera().moved());
    EXPECT_EQ(image_difference(original, preview.snapshot(), preview.app->layout()), 0.0);
}

TEST(Snapshot, WheelZoomsAndDoubleClickSetsTheTarget) {
    Preview preview;
    ASSERT_TRUE(preview.settle());
    const double distance = preview.model->orbit_camera().distance();
    HeadlessInput wheel;
    wheel.mouse = {400.0f, 300.0f};
    wheel.wheel = 1.0f;
    preview.frame(wheel);
    EXPECT_NEAR(preview.model->orbit_camera().distance(), 0.9 * distance, 1e-9);
    ASSERT_TRUE(preview.settle());
    // Double-click the floor near the bottom of the image.
    const ImageLayout layout = preview.app->layout();
    HeadlessInput click;
    click.mouse = layout.to_window({200.0f, 180.0f});
    preview.frame(click);
    for (int i = 0; i < 2; ++i) {
        click.buttons[0] = true;
        preview.frame(click);
        click.buttons[0] = false;
        preview.frame(click);
    }
    EXPECT_NEAR(preview.model->orbit_camera().target().y, -1.0, 1e-3);
}

TEST(Snapshot, ViewTogglesDoNotShootPhotonsAgain) {
    Preview preview;
    ASSERT_TRUE(preview.settle());
    const auto before = preview.model->stage_counters();
    preview.frame(HeadlessInput{.keys = {keys::p}, .alt = true});  // Alt+P: photons only
    ASSERT_TRUE(preview.settle());
    EXPECT_TRUE(preview.model->knobs().photons_only);
    CausticKnobs k = preview.model->knobs();
    k.num_neighbours = 30;  // what the N slider does
    preview.model->set_knobs(k);
    ASSERT_TRUE(preview.settle());
    const auto after = preview.model->stage_counters();
    EXPECT_EQ(after.photon_passes, before.photon_passes);
    EXPECT_EQ(after.scene_builds, before.scene_builds);
    EXPECT_EQ(after.renders, before.renders + 2);
}

TEST(Snapshot, CtrlSSavesAndDoesNotReplaceWithoutAsking) {
    Preview preview;
    ASSERT_TRUE(preview.settle());
    const std::string path = preview.folder.file("shot.png");
    std::snprintf(preview.app->panels().save_path.data(), preview.app->panels().save_path.size(), "%s", path.c_str());
    preview.app->panels().save_path_scene = preview.model->scene_path();
    HeadlessInput save;
    save.ctrl = true;
    save.keys = {keys::s};
    preview.frame(save);
    ASSERT_TRUE(std::filesystem::exists(path));
    EXPECT_EQ(read_png(path).width, 256);
    std::filesystem::resize_file(path, 10);  // a marker: a second save must not replace the file unasked
    preview.frame(HeadlessInput{});  // release the keys: a key held over two frames is one press
    preview.frame(save);
    preview.frame(HeadlessInput{});
    EXPECT_EQ(std::filesystem::file_size(path), 10u);
    EXPECT_TRUE(ImGui::IsPopupOpen("", ImGuiPopupFlags_AnyPopupId | ImGuiPopupFlags_AnyPopupLevel));
}

TEST(Snapshot, ASceneErrorIsShownOverThePreviousImage) {
    Preview preview;
    ASSERT_TRUE(preview.settle());
    const std::vector<unsigned char> before = preview.snapshot();
    preview.folder.write("scene.lua", "root = gr.node('root')\nroot:no_such_method()\n");
    preview.model->reload();
    ASSERT_TRUE(preview.run_until([&] { return !preview.model->error().empty(); }));
    EXPECT_NE(preview.model->error().find("scene.lua:2:"), std::string::npos) << preview.model->error();
    const std::vector<unsigned char> after = preview.snapshot();
    long red = 0;
    for (int y = 40; y < 70; ++y)
        for (int x = 10; x < 300; ++x) red += near(pixel(after, x, y), {115, 13, 13}, 12);
    EXPECT_GT(red, 1000);  // the banner
    // The image below the banner is the previous scene's, untouched.
    const ImageLayout layout = preview.app->layout();
    long changed = 0;
    for (int y = static_cast<int>(layout.origin.y) + 100; y < static_cast<int>(layout.origin.y + layout.size().y); ++y)
        for (int x = static_cast<int>(layout.origin.x); x < static_cast<int>(layout.origin.x + layout.size().x); ++x)
            changed += !near(pixel(after, x, y), pixel(before, x, y), 0);
    EXPECT_EQ(changed, 0);
}

/// Runs a shell command; returns its exit code and puts its output (both streams) in `output`.
int run(const std::string& command, std::string& output) {
    const std::string file = std::filesystem::temp_directory_path() / ("caustica_ui_out_" + std::to_string(::getpid()));
    const int status = std::system((command + " >" + file + " 2>&1").c_str());
    std::ifstream in(file);
    std::stringstream text;
    text << in.rdbuf();
    output = text.str();
    std::filesystem::remove(file);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(CommandLine, WithoutADisplayViewRunsHeadlessAndWritesTheWindow) {
    TempFolder folder;
    const std::string scene = folder.write("scene.lua", caustic_box_text(200000));
    const std::string out = folder.file("window.png");
    std::string output;
    const int code = run("env -u DISPLAY XDG_CONFIG_HOME=" + folder.file("config") + " " + CAUSTICA_BINARY + " view " +
                             scene + " --frames 3 --snapshot " + out + " --overlay --orbit 15,5",
                         output);
    ASSERT_EQ(code, 0) << output;
    EXPECT_NE(output.find("runs headless"), std::string::npos) << output;
    const Png8 png = read_png(out);
    EXPECT_EQ(png.width, 1280);
    EXPECT_EQ(png.height, 720);
}

TEST(CommandLine, TheWindowedViewerExplainsAMissingDisplay) {
    TempFolder folder;
    const std::string scene = folder.write("scene.lua", caustic_box_text(0));
    const std::string viewer = std::filesystem::path(CAUSTICA_BINARY).parent_path() / "caustica-view";
    std::string output;
    EXPECT_EQ(run("env -u DISPLAY " + viewer + " " + scene + " --frames 1", output), 1);
    EXPECT_NE(output.find("65544"), std::string::npos) << output;
    EXPECT_NE(output.find("--headless"), std::string::npos) << output;
    EXPECT_NE(output.find("xvfb-run"), std::string::npos) << output;
}

TEST(CommandLine, BadArgumentsAreRefusedBeforeAnythingOpens) {
    std::string output;
    EXPECT_EQ(run(std::string(CAUSTICA_BINARY) + " view --headless --orbit 30", output), 2);
    EXPECT_NE(output.find("--orbit 30: expects YAW,PITCH"), std::string::npos) << output;
    EXPECT_EQ(run(std::string(CAUSTICA_BINARY) + " view --headless --help", output), 0);
    EXPECT_NE(output.find("--snapshot FILE"), std::string::npos) << output;
    EXPECT_EQ(run(std::string(CAUSTICA_BINARY) + " view --headless no_such_scene.lua", output), 2);
    EXPECT_NE(output.find("no_such_scene.lua: no such scene file"), std::string::npos) << output;
}

}  // namespace
}  // namespace caustica::ui
