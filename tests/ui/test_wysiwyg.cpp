// What you see is what you save (docs/PREVIEW.md): the preview composes its job exactly as
// `caustica render SCENE [options]` does, lists every difference the person makes (each
// resettable) and turns them into the command line that renders the same image; command-line
// options belong to their scene; undo and redo; saving when the render is done; camera
// bookmarks; the course-scene hint; what is shown per scene. GL-free and fast: tiny images.
#include "ui/view_model.h"
#include "ui_test_support.h"

#include "core/io/image_io.h"
#include "core/io/png_io.h"
#include "core/lua/scene_loader.h"
#include "core/photons/photon_tracer.h"
#include "core/scene/source_location.h"
#include "tests/course_scenes.h"
#include "tests/time_bounds.h"

#include <gtest/gtest.h>

#include <algorithm>

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <map>

namespace caustica::ui {
namespace {

using namespace caustica::ui::testing;

const std::string source_dir = CAUSTICA_SOURCE_DIR;

/// The caustic box at 32 x 24 pixels (same framing), photons as given.
std::string tiny_box(long long photons = 20000, const std::string& extra = "") {
    std::string text = caustic_box_text(photons, extra);
    const auto at = text.find("256, 192");
    if (at != std::string::npos) text.replace(at, 8, "32, 24");
    return text;
}

/// Every option as text, reals exactly: two Options print the same iff they are the same.
std::string options_text(const Options& o) {
    return describe_non_default(o) + " | unit " + exact_number(o.unit_distance) + " max " + exact_number(o.caustic_max_dist) +
           " fudge " + exact_number(o.energy_fudge) + " aat " + exact_number(o.aa_threshold) + " time " +
           exact_number(o.time_limit) + " err " + exact_number(o.target_error) + " minw " + exact_number(o.min_weight);
}

/// The options `caustica render SCENE TOKENS` renders the first gr.render with (app/render_plan.cpp:
/// the script's gr.option, then the command line over them); resolution_override is folded into
/// the size by both, so it is left out.
Options render_options(const std::string& scene, const std::vector<std::string>& tokens) {
    LoadSettings settings;
    settings.output_given = true;
    SceneScript script = load_scene_script(scene, settings);
    Options o = script.renders.at(0).options;
    apply_option_tokens(o, tokens);
    o.resolution_override = 0;
    return o;
}

Options shown_options(const ViewModel& model) {
    Options o = model.current_job().options;
    o.resolution_override = 0;
    return o;
}

ModelConfig config_with(std::vector<std::string> tokens, std::string scene = "") {
    ModelConfig config;
    config.option_tokens = std::move(tokens);
    config.option_scene = std::move(scene);
    return config;
}

bool loaded(ViewModel& model, const std::string& path) {
    return run_until(model, [&] { return !model.loading() && model.has_scene() && model.scene_path() == path; }, 30.0);
}

/// The preview opens `scene` with `tokens` on its command line: its job is what `caustica
/// render` makes of the same (one difference of the preview's own, listed with a reset: a
/// progressive render without a stopping rule refines until paused where `render` stops after
/// one pass).
void expect_preview_job_is_render_job(const std::string& scene, const std::vector<std::string>& tokens) {
    SCOPED_TRACE(scene);
    ViewModel model(config_with(tokens));
    model.open(scene);
    ASSERT_TRUE(loaded(model, scene)) << model.error();
    const Options render = render_options(scene, tokens);
    Options shown = shown_options(model);
    const std::vector<Difference> differences = model.differences();
    EXPECT_TRUE(shown.reproducible) << "the preview seeds as --reproducible does";
    shown.reproducible = render.reproducible;  // which the copied command line adds when the scene has not
    if (render.integrator == IntegratorKind::progressive && !render.accumulates()) {
        ASSERT_EQ(differences.size(), 1u);
        EXPECT_EQ(differences[0].id, "stop");
        EXPECT_EQ(shown.passes, 0);
        shown.passes = render.passes;
        shown.passes_given = render.passes_given;
    } else {
        EXPECT_TRUE(differences.empty()) << differences[0].label;
    }
    EXPECT_EQ(options_text(shown), options_text(render));
    EXPECT_EQ(model.scene_tokens(), tokens);
}

TEST(Wysiwyg, PreviewJobIsTheRenderCommandsJob) {
    TempFolder folder;
    const std::string box = folder.write("box.lua", tiny_box(20000, "gr.option('--aa-grid 2 --integrator progressive')\n"));
    // No preset of the preview's own: the scene's 20000 photons, N 5, aa-grid 2.
    expect_preview_job_is_render_job(box, {});
    expect_preview_job_is_render_job(box, {"--quality", "draft", "--caustic-num-neighbours", "9", "--passes", "2",
                                           "--threads", "1"});
    expect_preview_job_is_render_job(box, {"--integrator", "classic", "--caustic-max-dist", "0.0123456789", "--minres"});
    expect_preview_job_is_render_job(source_dir + "/scenes/textures.lua", {"--minres", "--threads", "1"});
    {  // the case: textures.lua asks for no photons, and the preview shoots none either
        ViewModel model(config_with({"--minres"}));
        model.open(source_dir + "/scenes/textures.lua");
        ASSERT_TRUE(loaded(model, source_dir + "/scenes/textures.lua"));
        EXPECT_EQ(model.current_job().options.caustic_num_photons, render_options(source_dir + "/scenes/textures.lua", {}).caustic_num_photons);
        EXPECT_EQ(model.current_job().options.caustic_num_photons, 0);
    }
}

TEST(Wysiwyg, PreviewJobIsTheRenderCommandsJobForACourseScene) {
    CAUSTICA_SKIP_WITHOUT_CS488();
    expect_preview_job_is_render_job(caustica::testing::cs488_file("simple.lua"),
                                     {"--a4", "--minres", "--caustic-num-photons", "1000"});
}

TEST(Wysiwyg, CommandLineReproducesThePersonsChoicesAndEachResets) {
    TempFolder folder;
    const std::string scene = folder.write("box.lua", tiny_box());
    const std::vector<std::string> tokens = {"--reproducible", "--threads", "2"};
    ViewModel model(config_with(tokens));
    model.open(scene);
    ASSERT_TRUE(loaded(model, scene)) << model.error();
    EXPECT_TRUE(model.differences().empty());
    EXPECT_EQ(model.command_line(), "caustica render " + scene + " --reproducible --threads 2 -o caustic_box.png");

    model.set_preset("draft");
    CausticKnobs k = model.knobs();
    EXPECT_EQ(k.num_photons, 1'000'000);  // the draft preset's
    k.num_photons = 1234;
    k.max_dist = 0.1 + 0.2;               // 0.30000000000000004: written so that it reads back the same
    k.integrator = IntegratorKind::progressive;
    k.projection_map = ProjectionMapMode::off;
    model.set_knobs(k);
    model.set_stop_rules({3, 0.0, 0.0});
    model.set_threads(1);
    model.set_resolution_scale(0.5);

    const std::vector<std::string> added = model.person_tokens();
    std::vector<std::string> all = model.scene_tokens();
    all.insert(all.end(), added.begin(), added.end());
    EXPECT_EQ(options_text(shown_options(model)), options_text(render_options(scene, all)));
    EXPECT_EQ(added, (std::vector<std::string>{"--quality", "draft", "--integrator", "progressive", "--caustic-num-photons",
                                               "1234", "--caustic-max-dist", "0.30000000000000004", "--projection-map",
                                               "off", "--passes", "3", "--threads", "1"}));
    EXPECT_NE(model.command_line().find(" --quality draft --integrator progressive "), std::string::npos);

    std::vector<std::string> ids;
    for (const Difference& d : model.differences()) ids.push_back(d.id);
    const std::string photons_id = "knob:" + std::to_string(static_cast<std::uint32_t>(KnobField::photons));
    EXPECT_EQ(ids, (std::vector<std::string>{"preset", "knob:512", photons_id, "knob:8", "knob:32", "stop", "threads",
                                             "resolution"}));
    // The resolution cannot be given on the command line: the notes say so.
    const std::vector<std::string> notes = model.command_line_notes();
    ASSERT_EQ(notes.size(), 1u);
    EXPECT_NE(notes[0].find("resolution"), std::string::npos);

    model.reset_difference(photons_id);  // back to the preset's value, the rest stays
    EXPECT_EQ(model.knobs().num_photons, 1'000'000);
    EXPECT_EQ(model.knobs().integrator, IntegratorKind::progressive);
    model.reset_difference("all");
    EXPECT_TRUE(model.differences().empty());
    EXPECT_TRUE(model.person_tokens().empty());
    EXPECT_EQ(options_text(shown_options(model)), options_text(render_options(scene, tokens)));
    EXPECT_EQ(model.current_job().width, 32);
    model.undo();  // "reset all" is one step
    EXPECT_EQ(model.preset(), "draft");
    EXPECT_EQ(model.knobs().integrator, IntegratorKind::progressive);
}

// The progressive passes' own knobs (first radius, its shrink, balanced radius, radius per pixel, guided emission,
// photon splitting, photons per pixel) reach the job, the copied command line and the differences,
// and reset like the others.
TEST(Wysiwyg, ProgressiveKnobsReachTheJobAndTheCommandLine) {
    TempFolder folder;
    const std::string scene = folder.write("box.lua", tiny_box(20000, "gr.option('--integrator progressive')\n"));
    ViewModel model(config_with({}));
    model.open(scene);
    ASSERT_TRUE(loaded(model, scene)) << model.error();
    CausticKnobs k = model.knobs();
    EXPECT_EQ(k.first_radius, 3.0);
    EXPECT_FALSE(k.adaptive_radius);
    EXPECT_FALSE(k.auto_radius);
    EXPECT_TRUE(k.guided_emission);
    EXPECT_EQ(k.radius_alpha, 2.0 / 3.0);
    EXPECT_EQ(k.photons_per_pixel, 0.0);
    EXPECT_FALSE(k.photon_split);
    k.first_radius = 1.5;
    k.adaptive_radius = true;
    k.auto_radius = true;
    k.guided_emission = false;
    k.radius_alpha = 0.9;
    k.photons_per_pixel = 0.25;
    k.photon_split = true;
    model.set_knobs(k);
    const Options shown = model.current_job().options;
    EXPECT_EQ(shown.accumulation_radius, 1.5);
    EXPECT_TRUE(shown.adaptive_radius);
    EXPECT_TRUE(shown.auto_radius);
    EXPECT_FALSE(shown.guided_emission);
    EXPECT_EQ(shown.radius_alpha, 0.9);
    EXPECT_EQ(shown.photons_per_pixel, 0.25);
    EXPECT_TRUE(shown.photon_split);
    const std::vector<std::string> added = model.person_tokens();
    // In the panel's order.
    const std::vector<std::string> expected = {"--accumulation-radius", "1.5", "--radius-alpha", "0.9",
                                               "--auto-radius", "on", "--adaptive-radius", "on", "--guided-emission", "off",
                                               "--photon-split", "on", "--photons-per-pixel", "0.25"};
    ASSERT_GE(added.size(), expected.size());
    EXPECT_EQ(std::vector<std::string>(added.begin(), added.begin() + static_cast<std::ptrdiff_t>(expected.size())),
              expected);
    std::vector<std::string> all = model.scene_tokens();
    all.insert(all.end(), added.begin(), added.end());
    const Options render = render_options(scene, all);
    EXPECT_EQ(render.accumulation_radius, 1.5);
    EXPECT_TRUE(render.adaptive_radius);
    EXPECT_TRUE(render.auto_radius);
    EXPECT_FALSE(render.guided_emission);
    EXPECT_EQ(render.radius_alpha, 0.9);
    EXPECT_EQ(render.photons_per_pixel, 0.25);
    EXPECT_TRUE(render.photon_split);
    std::vector<std::string> labels;
    for (const Difference& d : model.differences()) labels.push_back(d.label);
    for (const char* label : {"first radius", "balanced radius", "radius per pixel", "guided emission", "radius alpha",
                              "photons per pixel", "photon splitting"})
        EXPECT_NE(std::find(labels.begin(), labels.end(), label), labels.end()) << label;
    model.reset_difference("knob:" + std::to_string(static_cast<std::uint32_t>(KnobField::guided_emission)));
    EXPECT_TRUE(model.knobs().guided_emission);
    EXPECT_EQ(model.knobs().first_radius, 1.5);
    model.reset_difference("knob:" + std::to_string(static_cast<std::uint32_t>(KnobField::photons_per_pixel)));
    EXPECT_EQ(model.knobs().photons_per_pixel, 0.0);
    EXPECT_TRUE(model.knobs().photon_split);
    model.reset_difference("all");
    EXPECT_EQ(model.current_job().options.accumulation_radius, 3.0);
    EXPECT_FALSE(model.current_job().options.adaptive_radius);
    EXPECT_FALSE(model.current_job().options.auto_radius);
    EXPECT_EQ(model.current_job().options.radius_alpha, 2.0 / 3.0);
    EXPECT_FALSE(model.current_job().options.photon_split);
}

TEST(Wysiwyg, EndlessRefinementIsListedAndTheCommandRendersThePassesShown) {
    TempFolder folder;
    const std::string scene = folder.write("box.lua", tiny_box(2000, "gr.option('--integrator progressive')\n"));
    ViewModel model(config_with({"--reproducible"}));
    model.open(scene);
    ASSERT_TRUE(loaded(model, scene));
    const std::vector<Difference> differences = model.differences();
    ASSERT_EQ(differences.size(), 1u);
    EXPECT_EQ(differences[0].scene, "1 pass");
    EXPECT_EQ(differences[0].shown, "refine until paused");
    ASSERT_TRUE(run_until(model, [&] { return model.driver().accumulation().passes_done >= 2; }, 30.0));
    model.set_paused(true);
    ASSERT_TRUE(run_until(model, [&] { return !model.driver().busy(); }, 30.0));
    const int passes = model.driver().accumulation().passes_done;
    EXPECT_EQ(model.person_tokens(), (std::vector<std::string>{"--passes", std::to_string(passes)}));
    model.reset_difference("stop");  // as render: one pass
    EXPECT_TRUE(model.differences().empty());
    EXPECT_EQ(model.current_job().options.passes, 1);
}

TEST(Wysiwyg, CommandLineOptionsBelongToTheirSceneOnly) {
    TempFolder folder;
    const std::string a = folder.write("a.lua", tiny_box(3000));
    const std::string b = folder.write("b.lua", tiny_box(4000));
    ViewModel model(config_with({"--a4", "--caustic-num-photons", "1000"}, a));
    model.open(a);
    ASSERT_TRUE(loaded(model, a));
    EXPECT_TRUE(model.current_job().options.a4);
    EXPECT_EQ(model.current_job().options.caustic_num_photons, 1000);
    EXPECT_EQ(model.a4_origin(), "the command line");

    model.open(b);  // starts clean: its own gr.option only
    ASSERT_TRUE(loaded(model, b));
    EXPECT_FALSE(model.current_job().options.a4);
    EXPECT_EQ(model.current_job().options.caustic_num_photons, 4000);
    EXPECT_EQ(model.a4_origin(), "");
    EXPECT_TRUE(model.scene_tokens().empty());
    model.set_a4(true);
    EXPECT_TRUE(model.current_job().options.a4);
    EXPECT_EQ(model.a4_origin(), "ticked here");
    EXPECT_EQ(model.command_line(), "caustica render " + b + " --a4 --reproducible -o caustic_box.png");

    model.open(a);  // its options come back with it
    ASSERT_TRUE(loaded(model, a));
    EXPECT_TRUE(model.current_job().options.a4);
    EXPECT_EQ(model.current_job().options.caustic_num_photons, 1000);
    model.set_a4(false);
    EXPECT_FALSE(model.current_job().options.a4);
    EXPECT_EQ(model.scene_tokens(), (std::vector<std::string>{"--caustic-num-photons", "1000"}));

    // A script that sets --a4 itself cannot be unticked (there is no --no-a4 for render either).
    const std::string c = folder.write("c.lua", "gr.option('--a4')\n" + tiny_box());
    model.open(c);
    ASSERT_TRUE(loaded(model, c));
    EXPECT_EQ(model.a4_origin().rfind("gr.option in the script (", 0), 0u) << model.a4_origin();
    model.set_a4(false);
    EXPECT_TRUE(model.current_job().options.a4);
}

TEST(Wysiwyg, UndoAndRedoStepThroughKnobsPresetAndStopRulesADragIsOneStep) {
    TempFolder folder;
    const std::string scene = folder.write("box.lua", tiny_box(2000));
    ViewModel model(config_with({}));
    EXPECT_FALSE(model.can_undo());
    model.open(scene);
    ASSERT_TRUE(loaded(model, scene));
    const CausticKnobs original = model.knobs();

    model.set_coalescing(true);  // a slider dragged through three values
    for (int n : {10, 20, 30}) {
        CausticKnobs k = model.knobs();
        k.num_neighbours = n;
        model.set_knobs(k);
    }
    model.set_coalescing(false);
    model.set_preset("draft");
    model.set_stop_rules({4, 0.0, 0.0});
    ASSERT_TRUE(model.can_undo());
    EXPECT_FALSE(model.can_redo());

    model.undo();
    EXPECT_EQ(model.stop_rules().passes, 0);  // the preview's own: refine until paused
    EXPECT_EQ(model.preset(), "draft");
    model.undo();
    EXPECT_EQ(model.preset(), "");
    EXPECT_EQ(model.knobs().num_neighbours, 30);
    model.undo();  // the whole drag
    EXPECT_EQ(model.knobs(), original);
    EXPECT_FALSE(model.can_undo());
    model.redo();
    EXPECT_EQ(model.knobs().num_neighbours, 30);
    model.redo();
    model.redo();
    EXPECT_EQ(model.stop_rules().passes, 4);
    EXPECT_FALSE(model.can_redo());
    model.undo();
    CausticKnobs k = model.knobs();  // a new change forgets what could be redone
    k.num_photons = 5;
    model.set_knobs(k);
    EXPECT_FALSE(model.can_redo());
    ASSERT_TRUE(run_until_finished(model));
    EXPECT_EQ(model.driver().job().options.caustic_num_photons, 5);
    EXPECT_EQ(model.driver().job().options.caustic_num_neighbours, 30);  // the person's N wins over the preset's 25
}

TEST(Wysiwyg, CourseSceneHintOnlyWhereTheCourseConventionsShowTheScene) {
    CAUSTICA_SKIP_WITHOUT_CS488();
    LoadSettings settings;
    settings.output_given = true;
    settings.allow_read = {caustica::testing::cs488_dir()};
    std::map<std::string, std::string> hints;
    for (const char* name : {"hier", "macho-cows", "nonhier", "simple", "simple-cows"}) {
        const std::string path = caustica::testing::cs488_file(std::string(name) + ".lua");
        hints[name] = course_scene_hint(load_scene_script(path, settings));
    }
    // The cows lose objects from the view without --a4 (origins counted, 23 vs 21 and 41 vs 34);
    // nonhier and simple place nh_ primitives without transforms: the conventions agree, no hint.
    EXPECT_EQ(hints["macho-cows"], "Looks like a course (CS488 A4) scene: 23 of 23 objects are in view with --a4, 21 "
                                   "without. Tick --a4 if it renders broken.");
    EXPECT_NE(hints["simple-cows"].find("41 of 41 objects are in view with --a4, 34 without"), std::string::npos);
    EXPECT_EQ(hints["nonhier"], "");
    EXPECT_EQ(hints["simple"], "");
    EXPECT_EQ(hints["hier"], "");  // a known miss: its five objects stay in view either way
    std::map<std::string, std::string> seed_hints;
    std::vector<std::filesystem::path> ours = {source_dir + "/tests/ui/scenes/caustic_box.lua"};
    for (const auto& entry : std::filesystem::directory_iterator(source_dir + "/scenes")) ours.push_back(entry.path());
    for (const std::filesystem::path& path : ours) {
        if (path.extension() != ".lua") continue;
        const auto& entry = path;
        SCOPED_TRACE(entry.string());
        const SceneScript script = load_scene_script(entry.string(), settings);
        EXPECT_EQ(course_scene_hint(script), "");
        seed_hints[entry.filename().string()] = seed_scene_hint(script);
    }
    // Given --a4, the scenes whose objects leave the view get the other hint (textures.lua: 10
    // in view without it, 8 with); default.lua and soft_shadows.lua keep them all in view.
    EXPECT_EQ(seed_hints["textures.lua"], "Looks like a scene in the original's conventions: 10 of 10 objects are in view "
                                          "without --a4, 8 with. Untick --a4 if it renders broken.");
    EXPECT_EQ(seed_hints["default.lua"], "");
    for (const char* name : {"hier", "macho-cows", "nonhier", "simple", "simple-cows"})
        EXPECT_EQ(seed_scene_hint(load_scene_script(caustica::testing::cs488_file(std::string(name) + ".lua"), settings)), "")
            << name;
}

TEST(Wysiwyg, TheHintShowsForACourseSceneUntilA4IsTicked) {
    CAUSTICA_SKIP_WITHOUT_CS488();
    const std::string cows = caustica::testing::cs488_file("macho-cows.lua");
    ModelConfig config = config_with({"--minres"});
    config.allow_read = {caustica::testing::cs488_dir()};
    ViewModel model(config);
    model.open(cows);
    ASSERT_TRUE(loaded(model, cows)) << model.error();
    EXPECT_NE(model.a4_hint().find("Tick --a4"), std::string::npos);
    model.set_a4(true);
    EXPECT_EQ(model.a4_hint(), "");
    EXPECT_TRUE(model.current_job().options.a4);
}

TEST(Wysiwyg, PhotonSliderEndsAtWhatThePhotonPassAccepts) {
    const long long limit = photon_memory_limit();
    EXPECT_GT(limit, 30'000'000);  // above the final preset on any machine these tests run on
    EXPECT_NO_THROW(check_photon_memory(static_cast<double>(limit), limit, 0.0));
    EXPECT_THROW(check_photon_memory(static_cast<double>(limit) * 1.01, limit, 0.0), InputError);
}

TEST(Wysiwyg, NumbersAndCamerasAreWrittenSoThatTheyReadBackTheSame) {
    for (double v : {0.1 + 0.2, 1e-300, 123456789.123, 0.15, -2.5e17}) EXPECT_EQ(std::stod(exact_number(v)), v);
    CameraDesc c;
    c.eye = {0.1 + 0.2, 1.6, -4.5};
    c.view = {0.0, -0.25, -1.0};
    c.up = {0.0, 1.0, 0.0};
    c.fovy_degrees = 60.0;
    EXPECT_EQ(camera_lua(c), "{0.30000000000000004, 1.6, -4.5}, {0, -0.25, -1}, {0, 1, 0}, 60");
    EXPECT_EQ(shell_quote("/a/b c.lua"), "'/a/b c.lua'");
    EXPECT_EQ(shell_quote("it's"), "'it'\\''s'");
    EXPECT_EQ(shell_quote("--caustic-max-dist"), "--caustic-max-dist");
}

TEST(Wysiwyg, ARecentScenesFileThatIsNotASmallRegularFileIsNeitherReadNorWritten) {
    TempFolder folder;
    const std::string zero = folder.file("zero");
    fs::create_symlink("/dev/zero", zero);
    const std::string fifo = folder.file("fifo");
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    const std::string big = folder.file("big");
    {
        std::ofstream out(big);
        out << "/s/a.lua\n" << std::string(recent_file_limit, 'y') << "\n";
    }
    const auto started = std::chrono::steady_clock::now();
    for (const auto& [file, problem] : std::vector<std::pair<std::string, std::string>>{
             {zero, "is a device or socket, not a regular file"},
             {fifo, "is a named pipe (FIFO), not a regular file"},
             {big, "larger than 1 MiB"},
             {folder.path().string(), "is a folder, not a file"}}) {
        SceneSource source(LoadSettings{}, file);
        EXPECT_TRUE(source.recent().empty()) << file;
        EXPECT_EQ(source.warning(), file + ": " + problem + "; the recent scenes list is not read or kept");
        source.add_recent("/s/b.lua");  // remembered for the session, the file left alone
        EXPECT_EQ(source.recent(), std::vector<std::string>{"/s/b.lua"});
    }
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count(),
              caustica::testing::time_bound(2.0));
    EXPECT_TRUE(fs::is_fifo(fifo));
    EXPECT_TRUE(fs::is_symlink(zero));
    EXPECT_EQ(fs::file_size(big), recent_file_limit + 10);
    EXPECT_EQ(files_in(folder.path()), (std::vector<std::string>{"big", "fifo", "zero"}));

    const std::string good = folder.file("config/recent-scenes");
    {
        SceneSource source(LoadSettings{}, good);
        EXPECT_EQ(source.warning(), "");
        source.add_recent("/s/a.lua");
        source.add_recent("/s/b.lua");
    }
    EXPECT_EQ(file_text(good), "/s/b.lua\n/s/a.lua\n");
    SceneSource source(LoadSettings{}, good);
    EXPECT_EQ(source.recent(), (std::vector<std::string>{"/s/b.lua", "/s/a.lua"}));
    EXPECT_EQ(files_in(folder.file("config")), std::vector<std::string>{"recent-scenes"});
}

TEST(Wysiwyg, ASceneThatIsNotAFileSaysWhatItIs) {
    TempFolder folder;
    const std::string fifo = folder.file("pipe.lua");
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    EXPECT_EQ(not_a_scene_file(fifo), fifo + ": is a named pipe (FIFO), not a scene file");
    EXPECT_EQ(not_a_scene_file(folder.path().string()), folder.path().string() + ": is a folder, not a scene file");
    EXPECT_EQ(not_a_scene_file("/dev/null"), "/dev/null: is a device, not a scene file");
    EXPECT_EQ(not_a_scene_file(folder.file("none.lua")), folder.file("none.lua") + ": no such scene file");
    ViewModel model(config_with({}));
    model.open(fifo);  // opening it from the panel says the same, without blocking on the pipe
    ASSERT_TRUE(run_until(model, [&] { return !model.loading() && !model.error().empty(); }, 10.0));
    EXPECT_EQ(model.error(), fifo + ": is a named pipe (FIFO), not a scene file");
}

TEST(Wysiwyg, ResetAllMidDragWithNothingToResetKeepsTheDragsUndoStep) {
    TempFolder folder;
    const std::string scene = folder.write("box.lua", tiny_box(0));
    ViewModel model(config_with({}));
    model.open(scene);
    ASSERT_TRUE(loaded(model, scene));
    model.reset_difference("all");  // nothing chosen: no step
    EXPECT_FALSE(model.can_undo());
    model.set_preset("draft");
    model.set_coalescing(true);  // a drag that ends where it began
    model.set_preset("");
    model.reset_difference("all");
    model.set_coalescing(false);
    ASSERT_TRUE(model.can_undo());
    model.undo();
    EXPECT_EQ(model.preset(), "draft");
    model.undo();
    EXPECT_EQ(model.preset(), "");
    EXPECT_FALSE(model.can_undo());

    model.set_preset("draft");  // reset all while a drag is open is a step of its own
    model.set_coalescing(true);
    CausticKnobs k = model.knobs();
    k.num_neighbours = 7;
    model.set_knobs(k);
    model.reset_difference("all");
    model.set_coalescing(false);
    EXPECT_EQ(model.preset(), "");
    model.undo();
    EXPECT_EQ(model.preset(), "draft");
    EXPECT_EQ(model.knobs().num_neighbours, 7);
}

TEST(Wysiwyg, BookmarkedCameraIsShownAndKeptAcrossAReload) {
    TempFolder folder;
    const std::string scene = folder.write("box.lua", tiny_box(0));
    ViewModel model(config_with({}));
    model.open(scene);
    ASSERT_TRUE(loaded(model, scene));
    model.orbit(30.0, 10.0);
    const CameraDesc orbited = model.orbit_camera().desc();
    model.reset_camera();
    model.go_to_camera(orbited);
    EXPECT_TRUE(model.orbit_camera().moved());
    const CameraDesc shown = model.current_job().camera;
    for (int i = 0; i < 3; ++i) {
        EXPECT_NEAR(shown.eye[i], orbited.eye[i], 1e-12);
        EXPECT_NEAR(shown.view[i], orbited.view[i], 1e-12);
    }
    EXPECT_EQ(model.camera_text(), camera_lua(shown));
}

TEST(Wysiwyg, BookmarksAreKeptBesideTheRecentListBetweenRuns) {
    TempFolder folder;
    ModelConfig config = config_with({});
    config.recent_file = folder.file("config/recent-scenes");
    CameraDesc camera;
    camera.eye = {1.0, 2.0, 3.0};
    camera.view = {0.0, 0.0, -1.0};
    {
        ViewModel model(config);
        EXPECT_TRUE(model.bookmarks().set("/s/a.lua", "front", camera));
    }
    EXPECT_TRUE(fs::exists(folder.file("config/camera-bookmarks")));
    ViewModel model(config);
    const auto marks = model.bookmarks().of("/s/a.lua");
    ASSERT_EQ(marks.size(), 1u);
    EXPECT_EQ(marks[0].second.eye, camera.eye);
}

TEST(Wysiwyg, OpenRefusesWhatIsNotALuaScript) {
    TempFolder folder;
    const std::string image = folder.write("picture.png", "not lua");
    ViewModel model(config_with({}));
    model.open(image);
    EXPECT_FALSE(model.loading());
    EXPECT_EQ(model.error(), image + ": not a scene script (scenes are .lua files)");
    model.update();
    EXPECT_FALSE(model.has_scene());
}

TEST(Wysiwyg, ATextureCreatedAfterTheErrorReloadsTheScene) {
    TempFolder folder;
    const std::string scene = folder.write("tex.lua", tiny_box(0, "wood = gr.texture('maps/wood.png')\nwhite:set_texture(wood)\n"));
    ViewModel model(config_with({}));
    model.open(scene);
    ASSERT_TRUE(run_until(model, [&] { return !model.loading() && !model.error().empty(); }, 30.0));
    EXPECT_NE(model.error().find("wood.png"), std::string::npos) << model.error();
    EXPECT_FALSE(model.has_scene());
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    fs::create_directories(folder.file("maps"));
    Image texture(2, 2);
    write_png_atomic(folder.file("maps/wood.png"), texture, PixelEncoding::clamped_linear, {});
    ASSERT_TRUE(run_until(model, [&] { return model.has_scene(); }, 10.0)) << model.error();
    EXPECT_EQ(model.error(), "");
}

TEST(Wysiwyg, SaveWhenDoneWritesTheFinishedImageWithItsFullPath) {
    TempFolder folder;
    const std::string scene = folder.write("box.lua", tiny_box(3000, "gr.option('--integrator progressive --passes 3')\n"));
    ViewModel model(config_with({"--reproducible"}));
    model.open(scene);
    ASSERT_TRUE(run_until(model, [&] { return model.driver().has_job(); }, 30.0));
    const std::string out = folder.file("done.png");
    EXPECT_TRUE(model.render_ends());
    model.save_when_done(out, false);
    EXPECT_EQ(model.scheduled_save(), out);
    std::optional<SaveResult> result;
    ASSERT_TRUE(run_until(model, [&] { return (result = model.take_scheduled_result()).has_value(); }, 30.0));
    EXPECT_EQ(result->outcome, SaveOutcome::written) << result->message;
    EXPECT_TRUE(model.driver().finished());
    EXPECT_EQ(model.driver().accumulation().passes_done, 3);
    EXPECT_EQ(model.last_saved(), fs::weakly_canonical(out).string());
    EXPECT_TRUE(model.scheduled_save().empty());
    std::map<std::string, std::string> text;
    for (const auto& [key, value] : read_png(out).text) text[key] = value;
    EXPECT_EQ(text["caustica:passes"], "3");
    EXPECT_FALSE(model.rendering());
    EXPECT_EQ(model.passes_text(), "3 of 3 passes");

    // An endless refinement never ends: only "save now" makes sense.
    model.set_stop_rules({0, 0.0, 0.0});
    EXPECT_FALSE(model.render_ends());
}

TEST(Wysiwyg, StatisticsBelongToTheSceneShown) {
    TempFolder folder;
    const std::string lit = folder.write("lit.lua", tiny_box(5000));
    // The same box whose light has no quadratic falloff: asked for photons, it shoots none.
    std::string dark_text = tiny_box(5000);
    const auto at = dark_text.find("{0.3, 0.0, 0.45}");
    ASSERT_NE(at, std::string::npos);
    dark_text.replace(at, 16, "{1.0, 0.0, 0.0}");
    const std::string dark = folder.write("dark.lua", dark_text);
    ViewModel model(config_with({}));
    model.open(lit);
    ASSERT_TRUE(run_until_finished(model));
    EXPECT_GT(model.driver().stats().caustic_photons, 0u);
    EXPECT_EQ(model.photons_note(), "");
    model.open(dark);
    ASSERT_TRUE(loaded(model, dark));
    EXPECT_EQ(model.driver().stats().caustic_photons, 0u);  // forgotten at once, before its render
    EXPECT_TRUE(model.driver().pass_history().empty());
    EXPECT_TRUE(model.driver().computed_stages().empty());
    ASSERT_TRUE(run_until_finished(model));
    for (const StageTime& s : model.driver().computed_stages()) {  // every time shown is this render's
        bool found = false;
        for (const StageTime& now : model.driver().stats().stages) found |= now.name == s.name && now.seconds == s.seconds;
        EXPECT_TRUE(found) << s.name;
    }
    EXPECT_EQ(model.photons_note(), "requested 5000 photons, none shot: no light shoots photons (only lights with "
                                     "quadratic falloff do)");
}

TEST(Wysiwyg, CopiedCommandKeepsAllowReadAndTheDisplayExposureNeverScalesAnExr) {
    TempFolder folder;
    const std::string scene = folder.write("box.lua", tiny_box(3000));
    ModelConfig config = config_with({"--reproducible"});
    fs::create_directories(folder.file("textures"));
    config.allow_read = {folder.file("textures")};
    ViewModel model(config);
    model.open(scene);
    ASSERT_TRUE(loaded(model, scene)) << model.error();
    // The batch command must be allowed to read what the preview read.
    EXPECT_EQ(model.command_line(),
              "caustica render " + scene + " --allow-read " + folder.file("textures") + " --reproducible -o caustic_box.png");

    ASSERT_TRUE(run_until_finished(model, 30.0));
    model.display().exposure = 3.0f;
    model.display().exposure_to_png = true;  // "PNG: apply the display exposure"
    ASSERT_EQ(model.save(folder.file("a.pfm"), false).outcome, SaveOutcome::written);
    ASSERT_EQ(model.save(folder.file("a.png"), false).outcome, SaveOutcome::written);
    const Image linear = read_image_file(folder.file("a.pfm"));
    const Image& shown = model.driver().image();
    ASSERT_EQ(linear.width, shown.width);
    double max_diff = 0.0, brightest = 0.0;
    for (int y = 0; y < shown.height; ++y)
        for (int x = 0; x < shown.width; ++x) {
            max_diff = std::max(max_diff, double(glm::length(linear.at(x, y) - shown.at(x, y))));
            brightest = std::max(brightest, double(shown.at(x, y).g));
        }
    EXPECT_EQ(max_diff, 0.0);  // the PFM holds the render's values, not 8x them
    ASSERT_GT(brightest, 0.05);
    // The PNG does get the 3 stops: a pixel at 1/8 or more is white.
    const Png8 png = read_png(folder.file("a.png"));
    int white = 0, bright = 0;
    for (int y = 0; y < shown.height; ++y)
        for (int x = 0; x < shown.width; ++x)
            if (shown.at(x, y).g >= 0.13f) {
                ++bright;
                white += png.data[(std::size_t(y) * png.width + x) * png.channels + 1] == 255;
            }
    ASSERT_GT(bright, 0);
    EXPECT_EQ(white, bright);
}

TEST(Wysiwyg, ViewTransformShowsTheBatchPngsToneCurveAndExposure) {
    // The shaders' formula (display_value mirrors it) against core/io/tonemap and the PNG encoder,
    // on a ramp through every curve's knee and past 1, at several exposures: the 8-bit value the
    // viewport shows is the one `caustica render --tonemap X --exposure E` writes, within one step
    // (float rounding of the curve may land either side of a step).
    for (Tonemap op : {Tonemap::clamp, Tonemap::reinhard, Tonemap::filmic})
        for (float stops : {-2.0f, 0.0f, 1.0f, 3.5f}) {
            int worst = 0;
            for (int i = 0; i <= 4096; ++i) {
                const float linear = 16.0f * static_cast<float>(i) / 4096.0f;
                const int shown = static_cast<int>(std::lround(255.0f * display_value(glm::vec3(linear), {op, stops, false}).x));
                const int written = encode_channel(tonemap_channel(linear, op, stops), PixelEncoding::clamped_linear);
                worst = std::max(worst, std::abs(shown - written));
            }
            EXPECT_LE(worst, 1) << tonemap_name(op) << " at " << stops << " stops";
        }
    // Reinhard keeps what clamping loses: 4 shows as 0.8, not white.
    EXPECT_NEAR(display_value(glm::vec3(4.0f), {Tonemap::reinhard, 0.0f, false}).x, 204.0f / 255.0f, 1e-6f);
}

TEST(Wysiwyg, ThePickedToneCurveIsShownSavedAndOnTheCommandLine) {
    TempFolder folder;
    const std::string scene = folder.write("box.lua", tiny_box(3000, "gr.option('--exposure 1')\n"));
    ViewModel model(config_with({"--reproducible"}));
    model.open(scene);
    ASSERT_TRUE(loaded(model, scene)) << model.error();
    ASSERT_TRUE(run_until_finished(model, 30.0));
    // The scene's own --exposure is shown: the viewport is what render writes.
    EXPECT_EQ(model.view_transform(), (ViewTransform{Tonemap::clamp, 1.0f, false}));
    model.display().exposure = 0.5f;
    model.display().tonemap = Tonemap::filmic;
    EXPECT_EQ(model.view_transform(), (ViewTransform{Tonemap::filmic, 1.5f, false}));
    const std::vector<Difference> differences = model.differences();
    ASSERT_TRUE(std::any_of(differences.begin(), differences.end(), [](const Difference& d) {
        return d.id == "tonemap" && d.scene == "clamp" && d.shown == "filmic";
    }));
    EXPECT_EQ(model.command_line(), "caustica render " + scene + " --reproducible --tonemap filmic -o caustic_box.png");
    // The PNG takes the curve shown (with the scene's exposure: the display's is added only when asked).
    ASSERT_EQ(model.save(folder.file("a.png"), false).outcome, SaveOutcome::written);
    const Png8 png = read_png(folder.file("a.png"));
    const Image& image = model.driver().image();
    ASSERT_EQ(png.width, image.width);
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x)
            for (int c = 0; c < 3; ++c)
                ASSERT_EQ(png.data[(std::size_t(y) * png.width + x) * png.channels + c],
                          encode_channel(tonemap_channel(image.at(x, y)[c], Tonemap::filmic, 1.0f),
                                         PixelEncoding::clamped_linear))
                    << x << ", " << y;
    model.reset_difference("tonemap");
    EXPECT_EQ(model.view_transform().tonemap, Tonemap::clamp);
    EXPECT_EQ(model.command_line(), "caustica render " + scene + " --reproducible -o caustic_box.png");
}

TEST(Wysiwyg, CopiedCommandIsReproducibleAndNeverOverwritesTheSavedImage) {
    TempFolder folder;
    const std::string scene = folder.write("box.lua", tiny_box(3000));
    const caustica::testing::InFolder here(folder.path());  // where the script's output name lands
    ViewModel model(config_with({}));                       // no --reproducible given
    model.open(scene);
    ASSERT_TRUE(loaded(model, scene)) << model.error();
    EXPECT_TRUE(model.current_job().options.reproducible) << "the preview seeds as --reproducible does";
    EXPECT_TRUE(model.differences().empty()) << "which changes nothing to list";
    EXPECT_EQ(model.command_line(), "caustica render " + scene + " --reproducible -o caustic_box.png");
    ASSERT_TRUE(run_until_finished(model, 30.0)) << model.error();

    ASSERT_EQ(model.save(folder.file("elsewhere.png"), false).outcome, SaveOutcome::written);
    EXPECT_EQ(model.command_output(), "caustic_box.png") << "nothing saved there";
    ASSERT_EQ(model.save(model.default_save_path(), false).outcome, SaveOutcome::written);
    EXPECT_EQ(model.command_output(), "caustic_box-render.png");
    EXPECT_EQ(model.command_line(), "caustica render " + scene + " --reproducible -o caustic_box-render.png");

    // "PNG: apply the display exposure" saved the display's stops too: the command says them.
    model.display().exposure = 2.0f;
    model.display().exposure_to_png = true;
    EXPECT_EQ(model.command_line(),
              "caustica render " + scene + " --reproducible --exposure 2 -o caustic_box-render.png");
}

/// The caustica:options of a saved PNG, parsed as `caustica render` parses options and checked by
/// its refusal of stopping rules it could never end (check_render_stop_rules).
void expect_render_accepts_the_options_of(const std::string& png, const std::string& state) {
    SCOPED_TRACE(state);
    std::map<std::string, std::string> text;
    for (const auto& [key, value] : read_png(png).text) text[key] = value;
    const std::string& written = text["caustica:options"];
    Options o;
    ASSERT_NO_THROW(apply_option_tokens(o, split_option_string(written))) << written;
    EXPECT_NO_THROW(check_render_stop_rules(o)) << written;
    EXPECT_TRUE(o.reproducible) << written;
    if (text.count("caustica:state") && text["caustica:state"].rfind("stopped", 0) != 0) {
        // Saved before its end: the options render the passes it holds.
        EXPECT_EQ(std::to_string(o.pass_limit()), text["caustica:passes"]) << written;
        EXPECT_EQ(o.time_limit, 0.0) << written;
        EXPECT_EQ(text["caustica:state"], state);
    }
}

TEST(Wysiwyg, EveryOptionListASavedImageHoldsIsOneRenderAccepts) {
    TempFolder folder;
    const std::string endless = folder.write("endless.lua", tiny_box(2000, "gr.option('--integrator progressive')\n"));
    const std::string timed = folder.write("timed.lua", tiny_box(2000, "gr.option('--integrator progressive --time 600')\n"));
    const std::string limited = folder.write("limited.lua", tiny_box(2000, "gr.option('--integrator progressive --passes 3')\n"));
    const std::string classic = folder.write("classic.lua", tiny_box(2000));
    ViewModel model(config_with({}));
    int saves = 0;
    auto save = [&] {
        const std::string path = folder.file("saved-" + std::to_string(++saves) + ".png");
        const SaveResult r = model.save(path, false);
        EXPECT_EQ(r.outcome, SaveOutcome::written) << r.message;
        return path;
    };
    auto refine = [&](const std::string& scene) {
        model.open(scene);
        ASSERT_TRUE(loaded(model, scene)) << model.error();
        ASSERT_TRUE(run_until(model, [&] { return !model.changes_pending() && model.driver().accumulation().passes_done >= 2; }, 30.0));
    };
    refine(endless);
    expect_render_accepts_the_options_of(save(), "refining");  // was --passes 0
    model.set_paused(true);
    ASSERT_TRUE(run_until(model, [&] { return !model.driver().busy(); }, 30.0));
    expect_render_accepts_the_options_of(save(), "paused");
    refine(timed);
    expect_render_accepts_the_options_of(save(), "refining");  // --passes N in place of --time 600
    model.open(limited);
    ASSERT_TRUE(loaded(model, limited)) << model.error();
    ASSERT_TRUE(run_until_finished(model, 30.0)) << model.error();
    expect_render_accepts_the_options_of(save(), "stopped by the pass limit");
    model.open(classic);
    ASSERT_TRUE(loaded(model, classic)) << model.error();
    ASSERT_TRUE(run_until_finished(model, 30.0)) << model.error();
    expect_render_accepts_the_options_of(save(), "classic, complete");
}

}  // namespace
}  // namespace caustica::ui
