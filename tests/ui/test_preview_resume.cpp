// The preview's saved accumulations (docs/PREVIEW.md, "Resume"): saving a progressive image
// writes its state beside it, keyed so that `caustica render --resume` with the copied command
// line's options continues it; a preview opening the scene again continues it to the bits of one
// uninterrupted run; a damaged state, or one of another job, is ignored with the reason and kept.
// GL-free and fast: tiny images, a few thousand photons.
#include "ui/saved_accumulation.h"
#include "ui/view_model.h"
#include "ui_test_support.h"

#include "core/lua/scene_loader.h"
#include "core/render/accumulation_state.h"
#include "tests/time_bounds.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <sstream>

namespace caustica::ui {
namespace {

using namespace caustica::ui::testing;
using caustica::testing::InFolder;
using caustica::testing::time_bound;

/// The caustic box at 32 x 24 pixels on the progressive integrator; it saves as caustic_box.png.
std::string progressive_box() {
    std::string text = caustic_box_text(2000, "gr.option('--integrator progressive')\n");
    const auto at = text.find("256, 192");
    if (at != std::string::npos) text.replace(at, 8, "32, 24");
    return text;
}

ModelConfig with_tokens(std::vector<std::string> tokens) {
    ModelConfig config;
    config.option_tokens = std::move(tokens);
    return config;
}

/// Opens `scene` and renders until its stopping rule ends the accumulation.
void open_and_finish(ViewModel& model, const std::string& scene) {
    model.open(scene);
    ASSERT_TRUE(run_until(model, [&] { return !model.loading() && model.has_scene(); }, time_bound(30.0))) << model.error();
    ASSERT_TRUE(run_until_finished(model, time_bound(30.0))) << model.error();
    ASSERT_TRUE(model.error().empty()) << model.error();
}

/// The key of the job `caustica render` makes of ViewModel::command_line() (its options between
/// the scene and -o, composed as app/render_plan.cpp composes them).
AccumulationKey key_of_command_line(const std::string& command_line, const std::string& scene) {
    std::istringstream words(command_line);
    std::string word;
    std::vector<std::string> tokens;
    for (int skipped = 0; skipped < 3 && words >> word; ++skipped) {}  // caustica render SCENE
    while (words >> word && word != "-o") tokens.push_back(word);
    LoadSettings settings;
    settings.output_given = true;
    RenderJob job = load_scene_script(scene, settings).renders.at(0);
    job.apply_command_line(tokens);
    return accumulation_key(job);
}

bool same_bits(const Image& a, const Image& b) {
    return a.width == b.width && a.height == b.height &&
           std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof a.pixels[0]) == 0;
}

// Saved after 3 passes (and with --minres, which the preview folds into the image size while
// `render` keeps it an option): the state beside the image holds those 3 passes, for the job the
// copied command line renders.
TEST(PreviewResume, SavingAnAccumulationWritesTheStateRenderResumeContinues) {
    for (const std::vector<std::string>& tokens : {std::vector<std::string>{"--passes", "3"},
                                                   std::vector<std::string>{"--passes", "3", "--minres"}}) {
        SCOPED_TRACE(tokens.size());
        TempFolder folder;
        const std::string scene = folder.write("box.lua", progressive_box());
        const InFolder here(folder.path());  // where the script's output name lands
        ViewModel model(with_tokens(tokens));
        open_and_finish(model, scene);
        ASSERT_EQ(model.driver().accumulation().passes_done, 3);
        const SaveResult saved = model.save(model.default_save_path(), false);
        ASSERT_EQ(saved.outcome, SaveOutcome::written) << saved.message;
        EXPECT_NE(saved.message.find("caustic_box.png.caustica-state"), std::string::npos) << saved.message;

        const RenderJob shown = model.current_job();
        const AccumulationState state =
            read_accumulation_state(folder.file("caustic_box.png.caustica-state"), shown.width, shown.height);
        EXPECT_EQ(state.next_pass, 3);
        EXPECT_EQ(state.key, key_of_command_line(model.command_line(), scene)) << model.command_line();
        // The copied command writes beside the saved image; its notes say how to continue instead.
        const std::vector<std::string> notes = model.command_line_notes();
        EXPECT_TRUE(std::any_of(notes.begin(), notes.end(), [&](const std::string& n) {
            return n.find(": add --resume and write -o " + model.last_saved()) != std::string::npos;
        })) << model.command_line();
        // Another job would not continue that state: the note goes.
        CausticKnobs knobs = model.knobs();
        knobs.num_neighbours += 2;
        model.set_knobs(knobs);
        for (const std::string& n : model.command_line_notes())
            EXPECT_EQ(n.find("add --resume"), std::string::npos) << n;
    }
}

// Saved while refining (no stopping rule), the render goes on; the state is written from the
// copy the loop makes at the end of the pass under way, past the passes the image holds.
TEST(PreviewResume, ASaveWhileRefiningWritesTheStateAtTheEndOfThePassUnderWay) {
    TempFolder folder;
    const std::string scene = folder.write("box.lua", progressive_box());
    const InFolder here(folder.path());
    ViewModel model(with_tokens({}));
    model.open(scene);
    ASSERT_TRUE(run_until(model, [&] { return model.driver().accumulation().passes_done >= 2; }, time_bound(30.0)))
        << model.error();
    const std::uint64_t restarts = model.driver().restarts();
    const SaveResult saved = model.save(model.default_save_path(), false);
    const int passes_saved = model.driver().accumulation().passes_done;
    ASSERT_EQ(saved.outcome, SaveOutcome::written) << saved.message;
    EXPECT_NE(saved.message.find("at the end of the pass under way"), std::string::npos) << saved.message;
    std::optional<ModelNote> note;
    ASSERT_TRUE(run_until(model, [&] { return (note = model.take_note()).has_value(); }, time_bound(30.0)));
    EXPECT_FALSE(note->problem) << note->text;
    EXPECT_NE(note->text.find("caustic_box.png.caustica-state"), std::string::npos) << note->text;
    EXPECT_TRUE(model.driver().busy()) << "the save stopped the refinement";
    EXPECT_EQ(model.driver().restarts(), restarts);
    const RenderJob shown = model.current_job();
    const AccumulationState state =
        read_accumulation_state(folder.file("caustic_box.png.caustica-state"), shown.width, shown.height);
    EXPECT_GT(state.next_pass, passes_saved);
    model.set_paused(true);
}

// A run straight to 6 passes; then 3 passes saved, and a new preview of the scene with a limit of
// 6: it starts at the 3 saved passes (or later, should a pass end before the model looks), says
// so, and ends with the bits of the straight run.
TEST(PreviewResume, ANewPreviewContinuesTheSavedPassesToTheBitsOfOneRun) {
    TempFolder folder;
    const std::string scene = folder.write("box.lua", progressive_box());
    const InFolder here(folder.path());
    Image straight;
    {
        ViewModel model(with_tokens({"--passes", "6"}));
        open_and_finish(model, scene);
        ASSERT_EQ(model.driver().accumulation().passes_done, 6);
        straight = model.driver().image();
    }
    {
        ViewModel model(with_tokens({"--passes", "3"}));
        open_and_finish(model, scene);
        ASSERT_EQ(model.save(model.default_save_path(), false).outcome, SaveOutcome::written);
    }
    ViewModel model(with_tokens({"--passes", "6"}));
    model.open(scene);
    int first_passes = -1;  // passes_done when the accumulation first shows
    std::optional<ModelNote> note;
    ASSERT_TRUE(run_until(model, [&] {
        if (!note) note = model.take_note();
        if (first_passes < 0 && model.driver().accumulation().accumulating)
            first_passes = model.driver().accumulation().passes_done;
        return !model.changes_pending() && model.driver().finished();
    }, time_bound(30.0))) << model.error();
    EXPECT_GE(first_passes, 3) << "the saved passes were not continued";
    ASSERT_TRUE(note.has_value());
    EXPECT_FALSE(note->problem);
    EXPECT_EQ(note->text, "continuing 3 passes from caustic_box.png.caustica-state");
    EXPECT_EQ(model.driver().accumulation().passes_done, 6);
    EXPECT_TRUE(same_bits(model.driver().image(), straight));
}

// A damaged state and one saved with other options are ignored, each with its reason; the scene
// renders from nothing (to its limit of 2 passes: continued, the 4 saved ones would show), and the
// file stays as it was.
TEST(PreviewResume, ADamagedOrForeignStateIsIgnoredWithTheReasonAndKept) {
    TempFolder folder;
    const std::string scene = folder.write("box.lua", progressive_box());
    const InFolder here(folder.path());
    {
        ViewModel model(with_tokens({"--passes", "4", "--caustic-num-neighbours", "9"}));
        open_and_finish(model, scene);
        ASSERT_EQ(model.save(model.default_save_path(), false).outcome, SaveOutcome::written);
    }
    const std::string state_path = folder.file("caustic_box.png.caustica-state");
    const std::string foreign = file_text(state_path);
    std::string damaged = foreign;
    damaged[damaged.size() / 2] ^= 0x40;

    struct Case {
        std::string bytes, reason;
    };
    for (const Case& c : {Case{foreign, "other options"}, Case{damaged, "checksum"}}) {
        SCOPED_TRACE(c.reason);
        folder.write("caustic_box.png.caustica-state", c.bytes);
        ViewModel model(with_tokens({"--passes", "2"}));
        model.open(scene);
        std::optional<ModelNote> note;
        ASSERT_TRUE(run_until(model, [&] {
            if (!note) note = model.take_note();
            return !model.changes_pending() && model.driver().finished();
        }, time_bound(30.0))) << model.error();
        EXPECT_TRUE(model.error().empty()) << model.error();
        EXPECT_EQ(model.driver().accumulation().passes_done, 2);
        ASSERT_TRUE(note.has_value());
        EXPECT_TRUE(note->problem);
        EXPECT_EQ(note->text.rfind("not continued: caustic_box.png.caustica-state: ", 0), 0u) << note->text;
        EXPECT_NE(note->text.find(c.reason), std::string::npos) << note->text;
        EXPECT_EQ(file_text(state_path), c.bytes) << "the file was changed";
    }
}

// A save while refining waits for the end of the pass under way; a change that restarts the render
// first ends that wait: nothing is written, and the note says why.
TEST(PreviewResume, ARestartBeforeThePassEndsWritesNoState) {
    TempFolder folder;
    const std::string scene = folder.write("box.lua", progressive_box());
    const InFolder here(folder.path());
    ViewModel model(with_tokens({}));
    model.open(scene);
    ASSERT_TRUE(run_until(model, [&] { return model.driver().accumulation().passes_done >= 1; }, time_bound(30.0)))
        << model.error();
    const SaveResult saved = model.save(model.default_save_path(), false);
    ASSERT_EQ(saved.outcome, SaveOutcome::written) << saved.message;
    ASSERT_NE(saved.message.find("at the end of the pass under way"), std::string::npos) << saved.message;
    CausticKnobs knobs = model.knobs();
    knobs.num_neighbours += 3;  // restarts the accumulation, before the model looks again
    model.set_knobs(knobs);
    std::optional<ModelNote> note;
    ASSERT_TRUE(run_until(model, [&] { return (note = model.take_note()).has_value(); }, time_bound(30.0)));
    EXPECT_TRUE(note->problem) << note->text;
    EXPECT_NE(note->text.find("not written: another render started"), std::string::npos) << note->text;
    EXPECT_FALSE(std::filesystem::exists(folder.file("caustic_box.png.caustica-state")));
    model.set_paused(true);
}

// The state a save writes is checked against the job shown when the save was asked for: one made
// for another camera (a snapshot from before a restart) is refused and nothing is written.
TEST(PreviewResume, AStateOfAnotherJobIsNeverWrittenUnderTheShownJobsKey) {
    TempFolder folder;
    const std::string scene = folder.write("box.lua", progressive_box());
    const InFolder here(folder.path());
    ViewModel model(with_tokens({"--passes", "2"}));
    open_and_finish(model, scene);
    AccumulationState state;
    ASSERT_TRUE(model.driver().session().accumulation_state(state));
    const RenderJob shown = model.current_job();
    RenderJob moved = shown;
    moved.camera.eye.x += 0.25;
    const std::string path = folder.file("other.caustica-state");
    try {
        write_saved_accumulation(path, state, moved, job_as_rendered(moved, 0), true);
        FAIL() << "another camera's accumulation was written";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("the accumulation at hand is another job's"), std::string::npos) << e.what();
    }
    EXPECT_FALSE(std::filesystem::exists(path));
    // The shown job's own state is written, keyed for `render --resume`.
    write_saved_accumulation(path, state, shown, job_as_rendered(shown, 0), true);
    EXPECT_EQ(read_accumulation_state(path, shown.width, shown.height).next_pass, 2);
}

}  // namespace
}  // namespace caustica::ui
