// The integrator per scene (docs/PREVIEW.md, "What you see is what you save"): the project's own
// scenes open with the integrator their gr.option picks, as `caustica render` renders them; the
// person's pick is kept per scene in a file beside the recent list, back when the scene is opened
// again or by a new model, unless the scene's command line sets --integrator; a corrupt, oversized
// or odd file is ignored or kept as it is, never lost or waited for.
#include "ui/integrator_memory.h"
#include "ui/small_file.h"
#include "ui/view_model.h"
#include "ui_test_support.h"

#include "core/lua/scene_loader.h"
#include "tests/time_bounds.h"

#include <gtest/gtest.h>

#include <sys/stat.h>

#include <algorithm>
#include <chrono>
#include <map>

namespace caustica::ui {
namespace {

using namespace caustica::ui::testing;

const std::string source_dir = CAUSTICA_SOURCE_DIR;

/// A glass ball over a floor, 16 x 12 pixels, a few photons: quick to render with either integrator.
const char* small_scene =
    "floor = gr.material({0.7, 0.7, 0.7}, {0, 0, 0}, 0)\n"
    "glass = gr.material({0, 0, 0}, {0.9, 0.9, 0.9}, 80)\n"
    "glass:set_ri(1.5)\n"
    "root = gr.node('root')\n"
    "ground = gr.cube('ground')\n"
    "ground:translate(0, -1.05, 0)\n"
    "ground:scale(3, 0.05, 3)\n"
    "ground:set_material(floor)\n"
    "root:add_child(ground)\n"
    "ball = gr.sphere('ball')\n"
    "ball:set_material(glass)\n"
    "root:add_child(ball)\n"
    "lamp = gr.light({0, 4, 1}, {1, 1, 1}, {0.5, 0, 0.05})\n"
    "gr.option('--caustic-num-photons 3000')\n"
    "gr.render(root, 'out.png', 16, 12, {0, 1, 5}, {0, -0.2, -1}, {0, 1, 0}, 50, {0.1, 0.1, 0.1}, {lamp})\n";

ModelConfig config_in(const TempFolder& folder, std::vector<std::string> tokens = {}, std::string scene = "") {
    ModelConfig config;
    config.recent_file = folder.file("config/recent-scenes");
    config.option_tokens = std::move(tokens);
    config.option_scene = std::move(scene);
    return config;
}

/// Runs the model until `path` is the scene shown.
bool opened(ViewModel& model, const std::string& path) {
    model.open(path);
    return run_until(model, [&] { return !model.loading() && model.has_scene() && model.scene_path() == path; }, 30.0);
}

/// The ids of the differences listed.
std::vector<std::string> difference_ids(const ViewModel& model) {
    std::vector<std::string> ids;
    for (const Difference& d : model.differences()) ids.push_back(d.id);
    return ids;
}

const std::string integrator_id = "knob:" + std::to_string(static_cast<std::uint32_t>(KnobField::integrator));

/// The key the memory keeps a scene under: its absolute path, links resolved.
std::string key_of(const std::string& path) { return fs::weakly_canonical(fs::absolute(path)).string(); }

TEST(SceneIntegrator, TheProjectsScenesPickTheirIntegratorAndThePreviewOpensWithIt) {
    // Progressive where a caustic is the point of the scene; classic, the default, elsewhere.
    const std::map<std::string, IntegratorKind> expected = {
        {"glass_of_liquid.lua", IntegratorKind::progressive}, {"csg_lens.lua", IntegratorKind::progressive},
        {"default.lua", IntegratorKind::classic},             {"csg_showcase.lua", IntegratorKind::classic},
        {"soft_shadows.lua", IntegratorKind::classic},        {"textures.lua", IntegratorKind::classic}};
    for (const auto& [name, integrator] : expected) {
        LoadSettings settings;
        settings.output_given = true;
        EXPECT_EQ(load_scene_script(source_dir + "/scenes/" + name, settings).renders.at(0).options.integrator, integrator)
            << name;
    }
    // The preview renders what `caustica render scenes/glass_of_liquid.lua` renders: progressive,
    // and not as a pick of the person's (no difference but the preview's endless refinement).
    const TempFolder folder;
    const std::string glass = source_dir + "/scenes/glass_of_liquid.lua";
    ViewModel model(config_in(folder, {"--minres", "--threads", "1", "--caustic-num-photons", "20000"}));
    ASSERT_TRUE(opened(model, glass)) << model.error();
    EXPECT_EQ(model.knobs().integrator, IntegratorKind::progressive);
    EXPECT_EQ(model.current_job().options.integrator, IntegratorKind::progressive);
    EXPECT_EQ(difference_ids(model), std::vector<std::string>{"stop"});
    EXPECT_EQ(model.command_line().find("--integrator"), std::string::npos) << model.command_line();
    EXPECT_FALSE(model.integrator_kept());
    // Accumulating passes: only the progressive integrator does (its statistics come when it stops).
    EXPECT_TRUE(run_until(model, [&] { return model.driver().accumulation().passes_done >= 1; }, 30.0));
}

TEST(SceneIntegrator, ThePersonsPickIsKeptPerSceneAcrossReopeningAndANewModel) {
    const TempFolder folder;
    const std::string a = folder.write("a.lua", small_scene), b = folder.write("b.lua", small_scene);
    const std::string memory_file = folder.file("config/scene-integrators");
    {
        ViewModel model(config_in(folder));
        ASSERT_TRUE(opened(model, a));
        EXPECT_EQ(model.knobs().integrator, IntegratorKind::classic);
        CausticKnobs k = model.knobs();
        k.integrator = IntegratorKind::progressive;
        model.set_knobs(k);
        ASSERT_TRUE(run_until(model, [&] { return model.integrator_kept(); }, 5.0));
        EXPECT_EQ(file_text(memory_file), key_of(a) + "\tprogressive\n");

        ASSERT_TRUE(opened(model, b));  // another scene: its own integrator
        EXPECT_EQ(model.knobs().integrator, IntegratorKind::classic);
        EXPECT_TRUE(difference_ids(model).empty());
        EXPECT_FALSE(model.integrator_kept());

        ASSERT_TRUE(opened(model, a));  // back: the person's pick, listed and carried by the command line
        EXPECT_EQ(model.current_job().options.integrator, IntegratorKind::progressive);
        EXPECT_TRUE(model.integrator_kept());
        const std::vector<Difference> differences = model.differences();
        ASSERT_FALSE(differences.empty());
        EXPECT_EQ(differences[0].id, integrator_id);
        EXPECT_EQ(differences[0].scene, "classic");
        EXPECT_EQ(differences[0].shown, "progressive");
        EXPECT_NE(model.command_line().find(" --integrator progressive"), std::string::npos) << model.command_line();
        EXPECT_FALSE(model.can_undo());  // the scene opened with it: nothing of this opening to undo
    }
    {
        ViewModel model(config_in(folder));  // the next launch
        ASSERT_TRUE(opened(model, a));
        EXPECT_EQ(model.current_job().options.integrator, IntegratorKind::progressive);
        EXPECT_EQ(difference_ids(model).at(0), integrator_id);
    }
    {
        // The command line's --integrator for the scene wins, and leaves the pick in the file.
        ViewModel model(config_in(folder, {"--integrator", "classic"}, a));
        ASSERT_TRUE(opened(model, a));
        EXPECT_EQ(model.current_job().options.integrator, IntegratorKind::classic);
        EXPECT_TRUE(difference_ids(model).empty());
        ASSERT_TRUE(run_until(model, [&] { return model.driver().finished(); }, 30.0));
        EXPECT_EQ(file_text(memory_file), key_of(a) + "\tprogressive\n");
    }
    {
        // Taking the difference back forgets the pick: the scene opens as the script says again.
        ViewModel model(config_in(folder));
        ASSERT_TRUE(opened(model, a));
        model.reset_difference(integrator_id);
        ASSERT_TRUE(run_until(model, [&] { return !model.integrator_kept(); }, 5.0));
        EXPECT_EQ(file_text(memory_file), "");
    }
    ViewModel model(config_in(folder));
    ASSERT_TRUE(opened(model, a));
    EXPECT_EQ(model.current_job().options.integrator, IntegratorKind::classic);
}

TEST(SceneIntegrator, UnreadableLinesAreSkippedAndWrittenBackAsTheyWere) {
    const TempFolder folder;
    const std::string kept = escape_field("/s/a\tb.lua") + "\tprogressive\n";
    const std::string odd = "no tab here\n/s/x.lua\tpath-tracer\n\tprogressive\n";
    const std::string file = folder.write("scene-integrators", odd + kept);
    IntegratorMemory memory(file);
    EXPECT_EQ(memory.of("/s/a\tb.lua"), IntegratorKind::progressive);
    EXPECT_EQ(memory.of("/s/x.lua"), std::nullopt);
    EXPECT_EQ(memory.warning(), file + ": 3 unreadable lines ignored (kept in the file; first: line 1)");
    memory.set("/s/c.lua", IntegratorKind::classic);
    EXPECT_EQ(file_text(file), odd + kept + "/s/c.lua\tclassic\n");
    memory.set("/s/a\tb.lua", std::nullopt);
    EXPECT_EQ(file_text(file), odd + "/s/c.lua\tclassic\n");
    memory.set("/s/c.lua", IntegratorKind::classic);  // no change, no write: the file stays as it is
    EXPECT_EQ(file_text(file), odd + "/s/c.lua\tclassic\n");
}

TEST(SceneIntegrator, AFileOverTheReadLimitOrNotARegularFileIsIgnoredAndNeverWrittenOver) {
    const TempFolder folder;
    const std::string big = folder.write("big", "/s/a.lua\tprogressive\n" + std::string(IntegratorMemory::read_limit, 'x'));
    const std::string fifo = folder.file("fifo");
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    const auto started = std::chrono::steady_clock::now();
    for (const auto& [file, problem] : std::vector<std::pair<std::string, std::string>>{
             {big, "larger than 1 MiB"}, {fifo, "is a named pipe (FIFO), not a regular file"}}) {
        SCOPED_TRACE(file);
        IntegratorMemory memory(file);
        EXPECT_EQ(memory.of("/s/a.lua"), std::nullopt);
        const std::string ignored = file + ": " + problem +
                                    "; the integrators picked per scene are not read from it, and it is never written over";
        EXPECT_EQ(memory.warning(), ignored);
        memory.set("/s/a.lua", IntegratorKind::classic);  // kept for this session only
        EXPECT_EQ(memory.warning(), ignored + "; this choice lasts until the preview closes");
        EXPECT_EQ(memory.of("/s/a.lua"), IntegratorKind::classic);
    }
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count(),
              caustica::testing::time_bound(2.0));
    EXPECT_EQ(fs::file_size(big), 21 + IntegratorMemory::read_limit);
    EXPECT_EQ(file_text(big).substr(0, 21), "/s/a.lua\tprogressive\n");
    EXPECT_TRUE(fs::is_fifo(fifo));

    // A model over such a file opens scenes as their scripts say and shows why nothing is kept.
    const std::string scene = folder.write("scene.lua", small_scene);
    const std::string recent = folder.file("config/recent-scenes");
    folder.write("config/scene-integrators", std::string(IntegratorMemory::read_limit + 1, '\n'));
    ModelConfig config;
    config.recent_file = recent;
    ViewModel model(config);
    ASSERT_TRUE(opened(model, scene));
    EXPECT_EQ(model.current_job().options.integrator, IntegratorKind::classic);
    const std::vector<std::string> warnings = model.warnings();
    EXPECT_NE(std::find(warnings.begin(), warnings.end(),
                        folder.file("config/scene-integrators") + ": larger than 1 MiB; the integrators picked per scene "
                                                                  "are not read from it, and it is never written over"),
              warnings.end());
}

TEST(SceneIntegrator, TheWriterKeepsTheFileWithinItsLimitDroppingTheScenesPickedLongestAgo) {
    const TempFolder folder;
    std::string text;
    const std::string padding(180, 'p');
    int lines = 0;
    while (text.size() < IntegratorMemory::write_limit + 4096)
        text += "/s/" + std::to_string(lines++) + padding + ".lua\tprogressive\n";
    const std::string file = folder.write("scene-integrators", text);
    IntegratorMemory memory(file);
    EXPECT_EQ(memory.of("/s/0" + padding + ".lua"), IntegratorKind::progressive);
    memory.set("/s/new.lua", IntegratorKind::classic);
    EXPECT_NE(memory.warning().find("dropped to keep the file within 256 KiB"), std::string::npos) << memory.warning();
    const std::string written = file_text(file);
    EXPECT_LE(written.size(), IntegratorMemory::write_limit);
    EXPECT_TRUE(written.ends_with("/s/" + std::to_string(lines - 1) + padding + ".lua\tprogressive\n/s/new.lua\tclassic\n"));
    EXPECT_EQ(memory.of("/s/0" + padding + ".lua"), std::nullopt);  // the oldest went first
}

}  // namespace
}  // namespace caustica::ui
