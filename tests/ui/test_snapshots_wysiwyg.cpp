// Headless snapshots of "what you see is what you save" (docs/PREVIEW.md): the command line the
// sidebar copies renders, in batch, the very image the preview shows after the person's changes;
// and the save questions answer to Enter and Esc (an Enter that answers one question never answers
// the next one too).
#include "headless_preview.h"
#include "ui/keys.h"

#include "core/io/png_io.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <functional>
#include <map>
#include <memory>

namespace caustica::ui {
namespace {

using namespace caustica::ui::testing;

using Preview = HeadlessPreview;

constexpr int key_l = 76;  // GLFW: ASCII for letters

std::map<std::string, std::string> png_text(const std::string& path) {
    std::map<std::string, std::string> text;
    for (const auto& [key, value] : read_png(path).text) text[key] = value;
    return text;
}

/// Renders `command_line` in batch and checks that it is the image the preview shows; returns the
/// batch image's path.
std::string expect_batch_renders_what_is_shown(Preview& preview, const std::string& command_line,
                                               const std::vector<unsigned char>& shot) {
    const std::string reference = preview.folder.file("batch.png");
    const std::string command = std::string(CAUSTICA_BINARY) + command_line.substr(std::string("caustica").size()) +
                                " -o " + reference + " -s";
    EXPECT_EQ(std::system(command.c_str()), 0) << command;
    const Png8 batch = read_png(reference);
    const ImageLayout layout = preview.app->layout();
    EXPECT_EQ(batch.width, layout.image_width);
    EXPECT_EQ(batch.height, layout.image_height);
    if (batch.width != layout.image_width || batch.height != layout.image_height) return reference;
    // Same job, same seed: identical float images; the display may round the batch's floor(255 v)
    // one step either way (test_snapshots.cpp, ImageRegionMatchesABatchRenderOfTheSameView).
    int worst = 0;
    long differing = 0;
    for (int y = 0; y < batch.height; ++y)
        for (int x = 0; x < batch.width; ++x) {
            const glm::vec2 w = layout.to_window({x + 0.5f, y + 0.5f});
            const unsigned char* s = &shot[(static_cast<std::size_t>(w.y) * window_width + static_cast<std::size_t>(w.x)) * 4];
            const unsigned char* b = &batch.data[(static_cast<std::size_t>(y) * batch.width + x) * batch.channels];
            const int d = std::max({std::abs(s[0] - b[0]), std::abs(s[1] - b[1]), std::abs(s[2] - b[2])});
            worst = std::max(worst, d);
            differing += d > 0;
        }
    std::printf("[ compare ] %s: largest difference %d, %ld pixels differ\n", command_line.c_str(), worst, differing);
    EXPECT_LE(worst, 1);
    EXPECT_LT(differing, batch.width * batch.height / 100);
    return reference;
}

TEST(SnapshotWysiwyg, CopiedCommandLineRendersTheImageShown) {
    Preview preview(caustic_box_text(100000));
    ASSERT_TRUE(preview.settle()) << preview.model->error();
    // The person's changes: a preset, then knobs over it.
    preview.model->set_preset("draft");
    CausticKnobs k = preview.model->knobs();
    k.num_photons = 150000;
    k.num_neighbours = 40;
    k.max_dist = 0.1 + 0.2;
    preview.model->set_knobs(k);
    ASSERT_TRUE(preview.settle()) << preview.model->error();
    const std::string command_line = preview.model->command_line();
    EXPECT_TRUE(preview.model->command_line_notes().empty());
    const std::vector<unsigned char> shot = preview.window.pixels();
    write_doc_image(preview.window.pixels(), "wysiwyg_differences.png");

    const std::string reference = expect_batch_renders_what_is_shown(preview, command_line, shot);
    // And the batch render really is the changed one, not the scene's defaults.
    EXPECT_NE(png_text(reference)["caustica:options"].find("--caustic-num-neighbours 40"), std::string::npos);
}

TEST(SnapshotWysiwyg, AShownLayerIsWhatTheCopiedCommandLineRenders) {
    Preview preview(caustic_box_text(100000));
    ASSERT_TRUE(preview.settle()) << preview.model->error();
    const auto before = preview.model->stage_counters();
    // Alt+L three times (a frame without it between: a held key does not repeat): image -> caustic.
    auto next_layer = [&] {
        preview.frame(HeadlessInput{.keys = {key_l}, .alt = true});
        preview.frame(HeadlessInput{});
    };
    for (int i = 0; i < 3; ++i) next_layer();
    ASSERT_TRUE(preview.settle()) << preview.model->error();
    EXPECT_EQ(preview.model->knobs().layer, ShadingLayer::caustic);
    EXPECT_EQ(preview.model->stage_counters().photon_passes, before.photon_passes);  // the same photons
    const std::string command_line = preview.model->command_line();
    EXPECT_NE(command_line.find(" --show-layer caustic"), std::string::npos) << command_line;
    write_doc_image(preview.window.pixels(), "show_layer_caustic.png");
    const std::string reference = expect_batch_renders_what_is_shown(preview, command_line, preview.window.pixels());
    EXPECT_NE(png_text(reference)["caustica:options"].find("--show-layer caustic"), std::string::npos);
    // Four more come back to the whole image.
    for (int i = 0; i < 4; ++i) next_layer();
    EXPECT_EQ(preview.model->knobs().layer, ShadingLayer::beauty);
}

TEST(SnapshotWysiwyg, SaveQuestionsAnswerToEnterAndEsc) {
    // A progressive preview without a stopping rule renders until paused: always "in progress".
    std::string text = caustic_box_text(20000, "gr.option('--integrator progressive')\n");
    // The script names its output as a scene does, below the folder the preview runs in.
    TempFolder out;
    const caustica::testing::InFolder in_out(out.path());
    const std::string saved = out.file("shot.png");
    text.replace(text.find("'caustic_box.png', 256, 192"), 27, "'shot.png', 64, 48");
    Preview preview(text);
    ASSERT_TRUE(preview.run_until([&] { return preview.model->driver().accumulation().passes_done >= 1; }));
    auto frame = [&](std::vector<int> taps, bool ctrl = false) {
        HeadlessInput input;
        input.taps = std::move(taps);
        input.ctrl = ctrl;
        preview.window.frame(*preview.app, input);
        preview.window.frame(*preview.app);
    };
    frame({keys::s}, true);  // Ctrl+S mid-render: "save now (N passes)" or (not here) "when done"
    EXPECT_FALSE(fs::exists(saved));
    write_doc_image(preview.window.pixels(), "wysiwyg_save_question.png");
    frame({keys::enter});    // Enter: save now
    ASSERT_TRUE(fs::exists(saved));
    const std::string first = png_text(saved)["caustica:passes"];
    EXPECT_EQ(preview.model->last_saved(), fs::weakly_canonical(saved).string());

    ASSERT_TRUE(preview.run_until([&] { return std::to_string(preview.model->driver().accumulation().passes_done) != first; }));
    frame({keys::s}, true);
    frame({keys::enter});    // save now: the file exists, so the overwrite question opens (not answered by this Enter)
    EXPECT_EQ(png_text(saved)["caustica:passes"], first);
    frame({keys::escape});   // Esc: keep the file
    EXPECT_EQ(png_text(saved)["caustica:passes"], first);

    frame({keys::s}, true);
    frame({keys::enter});
    frame({keys::enter});    // Enter: replace
    EXPECT_NE(png_text(saved)["caustica:passes"], first);
}

}  // namespace
}  // namespace caustica::ui
